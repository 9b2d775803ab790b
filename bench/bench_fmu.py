"""FMU timing (issue 6): the exported plant with its BCU (FMI 2.0 and 3.0, 1 and 8 cars) stepped
by FMPy's low-level classes, one 1 ms doStep per call as a HIL target would and 10 ms per call,
against the native run of the same scenario and seconds (rb_run_advance: BCU + plant, plus the
KPI bookkeeping the FMU does not do, so a ratio below 1 is possible). Prints plant steps per second,
the real-time factor and the overhead ratio (native rate / FMU rate); best of REPEAT on a shared
machine. The plant alone with the brakes applied (rb_plant_bench) is printed for reference."""

import ctypes
import tempfile
import time
import zipfile
from pathlib import Path

from fmpy import read_model_description
from fmpy.fmi2 import FMU2Slave
from fmpy.fmi3 import FMU3Slave

from railbrake import _core
from railbrake import scenario as scenarios
from railbrake import simulation
from railbrake.fmu import export_fmu

SCENARIO = "emergency-250-dry"
SIMULATED = 20.0       # s of braking per timing
REPEAT = 3


def fmu_steps_per_second(path: Path, version: str, step: float) -> float:
    folder = path.with_suffix("")
    with zipfile.ZipFile(path) as zf:
        zf.extractall(folder)
    md = read_model_description(str(folder))
    cls = FMU2Slave if version == "2" else FMU3Slave
    fmu = cls(guid=md.guid, unzipDirectory=str(folder), modelIdentifier=md.coSimulation.modelIdentifier)
    fmu.instantiate()
    if version == "2":
        fmu.setupExperiment(startTime=0.0)
    fmu.enterInitializationMode()
    fmu.exitInitializationMode()
    calls = int(round(SIMULATED / step))
    t0 = time.perf_counter()
    for i in range(calls):
        fmu.doStep(i * step, step)
    wall = time.perf_counter() - t0
    fmu.terminate()
    fmu.freeInstance()
    return SIMULATED / 1e-3 / wall


def native_run_steps_per_second(cars: int) -> float:
    """The same SIMULATED seconds of the scenario in rb_run_advance (BCU + plant + KPIs, no
    recording), timed without the Python set-up."""
    sc = scenarios.load(SCENARIO)
    plant = simulation.plant_params(sc, cars)
    bcu, wsp, spec = simulation.bcu_params(plant, sc, True), simulation.wsp_params(sc), simulation._scenario_struct(sc)
    state = ctypes.create_string_buffer(_core.rb_run_state_size())
    _core.call(_core.rb_run_init, ctypes.byref(plant), ctypes.byref(bcu), ctypes.byref(wsp), ctypes.byref(spec), state)
    finished = ctypes.c_int(0)
    t0 = time.perf_counter()
    _core.call(_core.rb_run_advance, ctypes.byref(plant), ctypes.byref(bcu), ctypes.byref(spec), state, SIMULATED,
               None, 0, ctypes.byref(finished))
    return SIMULATED / 1e-3 / (time.perf_counter() - t0)


def best(function, *args) -> float:
    """Best of REPEAT: the machine is shared, the fastest run is the least disturbed."""
    return max(function(*args) for _ in range(REPEAT))


def main() -> None:
    with tempfile.TemporaryDirectory() as tmp:
        for cars in (1, 8):
            plant = 1e6 / simulation.bench_plant(cars=cars, steps=20000)["step_us_cpu_mean"]   # its fastest run
            run = best(native_run_steps_per_second, cars)
            print(f"{cars} cars, {SCENARIO}, first {SIMULATED:.0f} s: native BCU + plant (rb_run_advance) "
                  f"{run:9.0f} steps/s; plant alone, brakes applied (rb_plant_bench) {plant:9.0f} steps/s")
            for version in ("2", "3"):
                path = export_fmu(SCENARIO, Path(tmp) / f"fmi{version}_{cars}.fmu", version, cars=cars)
                for step in (1e-3, 1e-2):
                    rate = best(fmu_steps_per_second, path, version, step)
                    print(f"  FMI {version}.0 via FMPy, doStep {step * 1e3:3.0f} ms: {rate:9.0f} steps/s, "
                          f"{rate * 1e-3:5.0f}x real time, overhead x{run / rate:5.2f} vs the native run")


if __name__ == "__main__":
    main()
