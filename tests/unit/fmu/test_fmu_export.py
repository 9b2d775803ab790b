"""The exported FMU against the FMI standard (fmpy's validation) and the native run.

Real-time targets import FMI 2.0 co-simulation FMUs with C sources and a 1 ms model step
(FMI 2.0, Modelica Association 2014; docs/references.md). The FMU runs the same C code in the same order as
railbrake.simulation.run, so its outputs must equal the native run's to 1e-9 relative.
"""

import shutil
import zipfile

import numpy as np
import pytest
from fmpy import read_model_description, simulate_fmu
from fmpy.build import build_platform_binary
from fmpy.validation import validate_fmu

from railbrake import scenario as scenarios
from railbrake import simulation
from railbrake.fmu import export_fmu

ATM = 1.01325e5


def channels(cars: int) -> list[str]:
    axles = [f"c{c}a{a}" for c in range(1, cars + 1) for a in range(1, 5)]
    return (["speed", "position", "main_reservoir"] + [f"supply_c{c}" for c in range(1, cars + 1)]
            + [f"wheel_speed_{x}" for x in axles] + [f"cylinder_{x}" for x in axles])


def assert_equals_native(fmu_path, native, cars, start_values=None, stop_time=None, of_scale=False):
    """FMPy's run of the FMU, sampled at the native record interval, equals the native run within
    1e-9 of each sample (of_scale: of the channel's largest value)."""
    t = native.time
    interval = float(t[1] - t[0])
    stop = float(t[-2]) if stop_time is None else stop_time     # the native run's last row is the stop itself
    names = channels(cars)
    result = simulate_fmu(str(fmu_path), stop_time=stop, output_interval=interval, output=names,
                          start_values=start_values or {})
    n = len(result)
    assert n > 10 and np.allclose(result["time"], t[:n], rtol=0, atol=1e-12)
    largest = 0.0
    for name in names:
        fmu, ref = result[name], native.outputs[name][:n]
        assert np.all(np.abs(fmu - ref) <= 1e-9 * (np.max(np.abs(ref)) if of_scale else np.abs(ref))), name
        largest = max(largest, float(np.max(np.abs(fmu - ref) / np.maximum(np.abs(ref), np.finfo(float).tiny))))
    print(f"FMU vs native, {cars} car(s), {n} samples to {result['time'][-1]:.2f} s: "
          f"largest relative difference {largest:.3g}")
    return result


def test_validates(fmu):
    version, path = fmu
    assert validate_fmu(str(path)) == []
    md = read_model_description(str(path))
    assert md.fmiVersion == f"{version}.0"
    identifier = md.coSimulation.modelIdentifier
    assert identifier.startswith("railbrake_emergency_250_dry_")
    units = {v.name: v.unit for v in md.modelVariables}
    assert units["speed"] == "m/s" and units["position"] == "m" and units["cylinder_c1a1"] == "Pa"
    assert units["mass_c1"] == "kg" and units["supply_volume_c1"] == "m3"
    with zipfile.ZipFile(path) as zf:
        names = zf.namelist()
    platform = "linux64" if version == "2" else "x86_64-linux"
    assert f"binaries/{platform}/{identifier}.so" in names
    assert "documentation/licenses/LICENSE.txt" in names
    assert {"sources/fmu_model.c", f"sources/fmi{version}.c", "sources/plant_step.c",
            "sources/railbrake/rb_plant.h"} <= set(names)
    assert ("sources/buildDescription.xml" in names) == (version == "3")


def test_equals_native_run(fmu):
    """Internal BCU following the scenario's demand: the whole stop from 250 km/h, bit for bit."""
    _, path = fmu
    native = simulation.run("emergency-250-dry", cars=1)
    result = assert_equals_native(path, native, 1)
    assert result["speed"][-1] < 0.5     # FMPy ran the whole stop


def test_discs_and_pads_as_the_native_run(fmu2):
    """The FMU's friction surface temperatures and pad friction: its hottest surface is the native
    run's (KPI, every 1 ms step; the FMU sampled every record interval), its pads' friction the
    law's at that surface (rb_pad_friction_eval)."""
    native = simulation.run("emergency-250-dry", cars=1)
    t = native.time
    names = [f"disc_surface_temperature_c1a{a}" for a in range(1, 5)] + ["pad_friction_c1a1", "speed"]
    result = simulate_fmu(str(fmu2), stop_time=float(t[-2]), output_interval=float(t[1] - t[0]), output=names)
    hottest = max(float(np.max(result[n])) for n in names[:4]) - simulation.ZERO_CELSIUS
    assert hottest == pytest.approx(native.kpis["max_disc_surface_temperature_c"], abs=0.5)
    stepped = result[1:]   # (at t = 0 no step has run: no friction yet)
    assert 0.3 < float(np.min(stepped["pad_friction_c1a1"][stepped["speed"] > 1.0])) < 0.45


@pytest.mark.slow
@pytest.mark.parametrize("cars", [2, 8])
def test_trains_equal_the_native_run(cars, tmp_path):
    """Coupled cars over the whole stop: the last bits that part (the binary's compiler is not the
    core library's) grow in the couplers' motion near standstill, so each channel is held within
    1e-9 of its largest value (the pointwise relative figure is printed)."""
    path = export_fmu("emergency-250-dry", tmp_path / "train.fmu", "2", cars=cars)
    assert_equals_native(path, simulation.run("emergency-250-dry", cars=cars), cars, of_scale=True)


def test_equals_native_run_with_wsp_acting(tmp_path):
    """Heavy rain (adhesion 0.02-0.05, Shinkansen heavy rain as cited in docs/references.md): the internal WSP vents
    and re-applies many times in the first 10 s; the FMU still equals the native run."""
    path = export_fmu("emergency-300-heavy-rain", tmp_path / "rain.fmu", "3", cars=1)
    native = simulation.run("emergency-300-heavy-rain", cars=1)
    assert_equals_native(path, native, 1, stop_time=10.0)
    first_10s = native.time <= 10.0
    assert all(native.outputs[f"vent_c1a{a}"][first_10s].sum() > 20 for a in range(1, 5))


def test_equals_native_run_with_the_decel_slip_controller_in_conditioning_mode(tmp_path):
    """The WSP controller and the conditioning mode are the scenario's at export (the wsp struct of
    fmu_scenario.c): the FMU runs the deceleration and slip-speed controller, trailing axles apart."""
    sets = {"wsp.controller": "decel_slip_speed", "wsp.conditioning_mode": True}
    path = export_fmu("emergency-300-heavy-rain", tmp_path / "decel.fmu", "2", cars=1, sets=sets)
    with zipfile.ZipFile(path) as zf:
        generated = zf.read("sources/fmu_scenario.c").decode()
    assert "m->wsp.controller = 2;" in generated and "m->wsp.conditioning_mode = 1;" in generated
    native = simulation.run(scenarios.load("emergency-300-heavy-rain").with_(dict(sets, **{"train.cars": 1})))
    assert_equals_native(path, native, 1, stop_time=10.0)
    first_10s = native.time <= 10.0
    vents = [native.outputs[f"vent_c1a{a}"][first_10s].sum() for a in range(1, 5)]
    assert min(vents) > 5 and vents[0] != vents[1]   # leading and trailing axle of a bogie apart


def test_compiled_from_its_sources_simulates_the_same(fmu, tmp_path):
    """The sources inside the FMU build with fmpy's CMake project (as `fmpy compile` does)."""
    version, path = fmu
    folder = tmp_path / "unzipped"
    with zipfile.ZipFile(path) as zf:
        zf.extractall(folder)
    shutil.rmtree(folder / "binaries")          # the binary must come from the sources
    build_platform_binary(folder, build_dir=tmp_path)
    native = simulation.run("emergency-250-dry", cars=1)
    assert_equals_native(folder, native, 1, stop_time=10.0)


def test_kernel_choice_reaches_the_build(tmp_path):
    """kernel="portable": the FMU's own sources carry the choice, and it equals the native portable run."""
    path = export_fmu("emergency-250-dry", tmp_path / "portable.fmu", "2", cars=1, kernel="portable")
    with zipfile.ZipFile(path) as zf:
        assert "m->plant.kernel = 1;" in zf.read("sources/fmu_scenario.c").decode()
    native = simulation.run("emergency-250-dry", cars=1, kernel="portable")
    assert_equals_native(path, native, 1, stop_time=10.0)


def test_fault_switch_starts_the_scenario_fault(tmp_path):
    """fault_1 switched on from t = 0 equals the native run whose fault starts at 0 s; the stuck-open
    vent valve bleeds its cylinder (hold valve open: relay supply against the vent) far below the others."""
    path = export_fmu("fault-vent-valve-stuck", tmp_path / "fault.fmu", "2", cars=3)
    base = scenarios.load("fault-vent-valve-stuck")
    faults = [f.model_copy(update={"start": 0.0}) for f in base.spec.faults]
    stop = base.spec.stop.model_copy(update={"max_time": 4.0})
    early = scenarios.Scenario(base.spec.model_copy(update={"faults": faults, "stop": stop}), "test", {})
    native = simulation.run(early, cars=3)
    result = assert_equals_native(path, native, 3, start_values={"fault_1": True}, stop_time=4.0)
    assert result["cylinder_c3a1"][-1] > ATM + 2e5
    assert result["cylinder_c3a2"][-1] < result["cylinder_c3a1"][-1] - 1.5e5


def test_external_bcu_inputs_drive_the_valves(fmu2):
    """external_bcu: the cylinders follow the pressure demand input (relay valve in equilibrium, no
    WSP command) and an axle held and vented (the WSP's vent state) falls to atmospheric pressure."""
    demand = ATM + 3.0e5
    signals = np.array([(0.0, demand, False, False), (3.0, demand, False, False), (3.0, demand, True, True),
                        (5.0, demand, True, True)],
                       dtype=[("time", float), ("pressure_demand_c1", float), ("hold_c1a1", np.bool_),
                              ("vent_c1a1", np.bool_)])
    result = simulate_fmu(str(fmu2), stop_time=5.0, output_interval=0.01, input=signals,
                          start_values={"external_bcu": True},
                          output=["cylinder_c1a1", "cylinder_c1a2", "speed"])
    at_3s = np.searchsorted(result["time"], 2.95)
    assert abs(result["cylinder_c1a1"][at_3s] - demand) < 0.05e5
    assert abs(result["cylinder_c1a2"][-1] - demand) < 0.05e5
    assert result["cylinder_c1a1"][-1] < ATM + 0.05e5
    assert result["speed"][-1] < result["speed"][0]     # the brakes act


def test_tuned_parameter_reaches_the_plant(fmu2):
    """initial_speed set before initialisation is the train speed at t = 0."""
    result = simulate_fmu(str(fmu2), stop_time=0.01, output_interval=0.01, output=["speed"],
                          start_values={"initial_speed": 30.0})
    assert result["speed"][0] == 30.0


def test_train_preset_and_bad_arguments(tmp_path):
    path = export_fmu("velaro-8", tmp_path / "velaro.fmu", "3", cars=2, binary=False)
    md = read_model_description(str(path))
    assert "velaro-8" in md.description and "cylinder_c2a4" in {v.name for v in md.modelVariables}
    from railbrake.errors import InputError
    with pytest.raises(InputError, match="FMI version '4'"):
        export_fmu("emergency-250-dry", tmp_path / "x.fmu", "4")
    with pytest.raises(InputError, match="nor a train preset"):
        export_fmu("no-such-thing", tmp_path / "x.fmu", "2")


def test_model_description_an_integrator_reads(fmu, tmp_path):
    """Display units as integrators read them (bar gauge over the train's atmosphere, km/h, degC, kN),
    a quantity and a description for every variable, author/version/licence/generation, and
    documentation/index.html listing every port with its value reference."""
    version, path = fmu
    md = read_model_description(str(path))
    assert md.author and md.version and "Apache-2.0" in md.license and md.generationTool.startswith("railbrake")
    assert md.generationDateAndTime
    displays = {u.name: {d.name: (d.factor, d.offset) for d in u.displayUnits} for u in md.unitDefinitions}
    assert displays["Pa"]["bar_g"] == pytest.approx((1e-5, -ATM * 1e-5))      # 1 bar = 1e5 Pa (SI)
    assert displays["m/s"]["km/h"] == pytest.approx((3.6, 0.0))
    assert displays["K"]["degC"] == pytest.approx((1.0, -273.15))              # ITS-90 / SI brochure
    assert displays["N"]["kN"] == pytest.approx((1e-3, 0.0))
    by_name = {v.name: v for v in md.modelVariables}
    assert by_name["cylinder_c1a1"].displayUnit == "bar_g" and by_name["speed"].displayUnit == "km/h"
    assert by_name["air_temperature"].displayUnit == "degC" and by_name["ed_force_c1"].displayUnit == "kN"
    assert by_name["cylinder_c1a1"].declaredType is None and by_name["cylinder_c1a1"].quantity == "Pressure"
    for v in md.modelVariables:
        assert v.description, v.name
        if v.type in ("Real", "Float64") and v.unit:
            assert v.quantity, v.name
    with zipfile.ZipFile(path) as zf:
        page = zf.read("documentation/index.html").decode()
    assert "Interface control table" in page and "licenses/LICENSE.txt" in page
    for v in md.modelVariables:
        assert f"<td>{v.valueReference}</td><td>{v.name}</td>" in page, v.name
