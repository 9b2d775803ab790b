"""Every public function and input class of `railbrake` and of its subpackages' faces (their
__all__), and the methods of Result, called with one argument wrong in type or value (None, a
string for a number, negative, NaN, infinities, huge, wrong containers, ...): each refusal (any
exception) names that argument as the caller wrote it. An accepted call is not a refusal and is
not counted here (test_api_fuzz.py checks the laws' results). Calls that would start a long
simulation get a 1-car short run as their base, so that a refusal comes before any work and an
accepted value costs a fraction of a second. Output files are folder tmp_path's."""

from __future__ import annotations

import faulthandler
import inspect
import json
import math
from pathlib import Path

import numpy as np
import pytest

import railbrake
from railbrake import (adhesion, brakecalc, etcs, fmu, hil, plots, pneumatics, results, sequence, simulation,
                       validation, valves)
from railbrake.hil import HilResult, RealTime

FACES = [railbrake, adhesion, brakecalc, etcs, fmu, hil, plots, pneumatics, results, sequence, simulation,
         validation, valves]
# public callables not fuzzed here, and why
NOT_HERE = {
    "railbrake.simulation.plant_params": "takes and builds the C structs (layer below the face's run)",
    "railbrake.simulation.bcu_params": "takes the C plant struct plant_params builds",
    "railbrake.simulation.structs": "builds the C structs of a run (railbrake.run checks their inputs)",
    "railbrake.simulation.run_structs": "runs C structs structs() built",
    "railbrake.simulation.run_batch": "runs C structs structs() built",
    "railbrake.simulation.kpi_dict": "reads a C Kpis struct the run filled",
    "railbrake.simulation.bench": "a timing bench: runs for seconds by design",
    "railbrake.simulation.bench_plant": "a timing bench: runs for seconds by design",
    "railbrake.hil.run": "paces a plant in real time against a BCU over UDP (tests/unit/hil)",
    "railbrake.hil.serve_bcu": "serves a BCU over UDP in real time (tests/unit/hil)",
    "railbrake.hil.hil_config": "builds the C HIL struct from a C BCU struct",
    "railbrake.hil.run_kpis": "reads the C plant state of a HIL run",
    "railbrake.hil.loss_dict": "reads the C HIL result struct",
    "railbrake.hil.request_real_time": "changes this process's scheduling and memory locking",
    "railbrake.compare": "takes its runs positionally (*runs), no argument name to vary "
                         "(tests/unit/results/test_result_api.py: its refusals name runs[i])",
}
SCENARIO = "emergency-250-dry"
# classes that are results, not inputs: built by railbrake, their fields typed, never checked
RESULT_TYPES = {"Result", "CreepCurve", "Peak", "PolachFit", "NetworkResult", "RunRecord", "BrokenCase", "Case",
                "CaseResult", "EpvCharacteristic", "LostUnits", "AdhesionCondition"}
EXCEPTIONS = {"InputError", "AdhesionRangeWarning"}
RESULT_TYPES |= {"BrakeCalculation", "HilResult", "RealTime", "BcuCounters", "Sequence", "SequenceFile", "Test",
                 "Step", "Condition", "Expect", "WaitUntil", "WaitAt", "Demand", "RecordKpi", "Threshold",
                 "CHANNEL_DIMENSION"}   # results, or pydantic file models (validated as files: tests/unit/sequence)
LABELS = ("where", "option", "origin")   # the caller's own name of a value a function checks
WRITTEN = ("output", "path", "folder")   # arguments naming a file or folder that may be written
# values that are valid and cost much: an FMU with its binary compiled
COSTLY = {(fmu.export_fmu, "binary", True)}

BAD = [None, "abc", "", -1, 0, 7, -0.5, math.nan, math.inf, -math.inf, 1e308, -1e308, True, [], [1.0, "x"],
       [[1.0, 2.0], [3.0]], {}, {"a": 1}, object(), b"1", "x" * 10_000]


@pytest.fixture(scope="module")
def bases(tmp_path_factory):
    """callable -> (its label, the keyword arguments of a valid call)."""
    folder = tmp_path_factory.mktemp("faces")
    result = railbrake.run(SCENARIO, cars=1)
    result.save(folder / "saved")
    curve = adhesion.creep_curves("dry-medium", [20.0])[0]
    state = etcs.State(0.9, np.array([1.0, 1.0]))
    sc = railbrake.scenario.load(SCENARIO)
    calc = brakecalc.calculate("crh380a-8")
    speed = np.asarray(result.outputs["speed"])
    distance = np.concatenate([[0.0], np.cumsum(0.5 * (speed[1:] + speed[:-1]) * np.diff(result.time))])
    from importlib.resources import files
    sequence_text = (files("railbrake") / "data" / "sequences" / f"{sequence.presets()[0]}.yaml").read_text()
    hil_result = HilResult(result.scenario, result.cars, result.time, dict(result.outputs), dict(result.units),
                           {"steps": len(result.time)}, {}, dict(result.kpis), RealTime(False),
                           atmosphere=result.atmosphere)
    force_table = valves.load_epv()["solenoid_table"]
    cases = {
        railbrake.load_result: dict(folder=folder / "saved"),
        railbrake.run: dict(scenario=SCENARIO, cars=1),
        adhesion.RailConditioning: dict(leading_factor=0.5, recovery_axles=4.0),
        adhesion.EnergyConditioning: dict(leading_factor=0.5, reference_energy=1e5),
        adhesion.Fit: dict(fitted_on=("curtius-kniffler-dry",), checked_on=()),
        adhesion.car_axles: dict(car=1),
        adhesion.car_of_axle: dict(axle=1),
        adhesion.check_points: dict(creep=curve.creep, coefficient=curve.coefficient, speed=20.0,
                                    where=lambda name, i: f"{name}[{i}]"),
        adhesion.conditions: {},
        adhesion.creep_curves: dict(condition="dry-medium", speeds=[20.0]),
        adhesion.identify_polach: dict(creep=curve.creep, coefficient=curve.coefficient, speed=20.0),
        adhesion.load_condition: dict(condition="dry-medium"),
        adhesion.peak_adhesion: dict(condition="dry-medium", speed=20.0),
        adhesion.preset_names: {},
        adhesion.creep_outside_validity: dict(condition=adhesion.load_condition("dry-medium"), creep=0.05),
        adhesion.run_outside_validity: dict(condition=adhesion.load_condition("dry-medium"), initial_speed_kmh=100.0),
        adhesion.warn_outside_range: dict(condition=adhesion.load_condition("dry-medium"), speed_kmh=100.0),
        etcs.State: dict(probability=0.9, ratios=np.array([1.0, 1.0])),
        etcs.coded: dict(k=0.9),
        etcs.ebcl: dict(index=3),
        etcs.equal_units: dict(n=4, p=1e-3),
        etcs.k_dry: dict(states=[state], confidence=0.99),
        etcs.mixture_cdf: dict(states=[state], x=0.9),
        etcs.quantile: dict(states=[state], level=0.01),
        fmu.export_fmu: dict(scenario=SCENARIO, output=folder / "plant.fmu", cars=1, binary=False),
        pneumatics.Network: {},
        pneumatics.orifice_mass_flow: dict(p_up=6e5, T_up=293.0, p_down=1e5, area=1e-5),
        pneumatics.sonic_conductance: dict(area=1e-5),
        results.from_hil: dict(result=hil_result, sc=railbrake.scenario.load(SCENARIO)),
        results.from_simulation: dict(result=result, sc=railbrake.scenario.load(SCENARIO)),
        validation.case_root: {},
        validation.load_cases: dict(case_id="crh380al-running-resistance"),
        validation.run_cases: dict(cases=[]),
        valves.epv_characteristic: dict(n_points=21, ramp_time=1.0),
        valves.epv_network: dict(p=valves.load_epv(), current_schedule=[(0.0, 0.5)]),
        valves.epv_step: dict(t_end=0.2, n_points=21),
        valves.load_epv: {},
        valves.load_relay: {},
        valves.oscillates: dict(time=np.linspace(0, 1, 11), pressure=np.ones(11)),
        valves.read_force_table: dict(path=force_table),
        valves.relay_step: dict(t_end=0.2, n_points=21),
        valves.step_metrics: dict(time=np.linspace(0, 1, 11), gauge_bar=np.linspace(0, 3, 11)),
        brakecalc.as_json: dict(calcs=[calc]),
        brakecalc.brake_percentage: dict(distance=700.0),
        brakecalc.braked_weight: dict(lambda_percent=150.0, mass_t=400.0),
        brakecalc.braking_curve: dict(time=result.time, speed=speed, distance=distance, response_time=1.0),
        brakecalc.calculate: dict(train="crh380a-8"),
        brakecalc.equivalent_deceleration: dict(v0=50.0, distance=500.0, response_time=2.0),
        brakecalc.interval_decelerations: dict(speed=speed, distance=distance,
                                               intervals_kmh=[[200.0, 100.0]]),
        brakecalc.settings: {},
        brakecalc.to_html: dict(calcs=[calc]),
        brakecalc.uic_stopping_distance: dict(lambda_percent=150.0),
        brakecalc.write: dict(calcs=[calc], folder=folder / "brakecalc"),
        plots.new_figure: dict(nrows=1, ncols=1),
        plots.save: dict(fig=plots.new_figure()[0], path=folder / "figure.png"),
        sequence.duration: dict(text="1 s", where="test"),
        sequence.load: dict(name=sequence.presets()[0]),
        sequence.matching: dict(pattern="slip_*", channels=dict(result.units), where="test"),
        sequence.parse: dict(text=sequence_text, origin="test.yaml"),
        sequence.presets: {},
        sequence.quantity: dict(text="1 s", dimension="time", where="test"),
        simulation.Change: dict(time=1.0),
        simulation.axle_name: dict(index=0),
        simulation.channels: dict(n_cars=1),
        simulation.demanded_steps: dict(scenario=sc),
        simulation.emergency_scenario: dict(train="crh380a-8", initial_speed=50.0, max_time=60.0),
        simulation.kernel_code: {},
        simulation.response_times: dict(result=result),
        simulation.run: dict(scenario=SCENARIO, cars=1),
        simulation.scenario_train: dict(scenario=sc, n_cars=1),
        simulation.simulated_response: dict(train="crh380a-8", initial_speed=50.0),
        simulation.stopping_distance: dict(v0=50.0, train="crh380a-8", response_time=2.0),
        simulation.substeps_for: dict(dt=0.001),
        simulation.wall_time: {},
        simulation.outside_validity_kpi: dict(scenario=sc, max_slip=0.05),
        simulation.wsp_params: dict(scenario=sc),
        hil.channels: dict(n_cars=1),
        hil.config_digest: dict(scenario=sc, n_cars=1),
        hil.describe_config: dict(scenario=sc, n_cars=1),
        hil.parse_udp_url: dict(text="udp://127.0.0.1:47800", option="--bcu"),
        result.save: dict(folder=folder / "again"),
        result.plot: dict(kind="braking_curve", path=folder / "plot.png"),
    }
    labels, missing = {}, []
    for face in FACES:
        for name in face.__all__:
            item = getattr(face, name)
            label = f"{face.__name__}.{name}"
            if callable(item) and name not in RESULT_TYPES | EXCEPTIONS and label not in NOT_HERE:
                labels[item] = label
                if item not in cases:
                    missing.append(label)
    assert not missing, f"public callables without a base call here: {missing}"
    labels[result.save], labels[result.plot] = "Result.save", "Result.plot"
    return {function: (labels[function], kwargs) for function, kwargs in cases.items()}, folder


def _parameters(function) -> list[str]:
    kinds = (inspect.Parameter.POSITIONAL_OR_KEYWORD, inspect.Parameter.KEYWORD_ONLY)
    return [p.name for p in inspect.signature(function).parameters.values() if p.kind in kinds]


def _refusal(function, kwargs, name) -> str | None:
    """None when the call was accepted or refused naming `name` (or the label the caller gave the
    value, for functions that take one: where, option); else the unnamed refusal."""
    names = [name] + [kwargs[label] for label in LABELS if isinstance(kwargs.get(label), str) and label != name
                      and kwargs[label]]
    faulthandler.dump_traceback_later(60, exit=True)   # a call that would run for long: fail loudly
    try:
        function(**kwargs)
    except Exception as exc:   # noqa: BLE001 - every refusal is checked
        if not any(n in str(exc) for n in names):
            return f"{type(exc).__name__}: {str(exc)[:200]}"
    finally:
        faulthandler.cancel_dump_traceback_later()
    return None


@pytest.mark.slow   # thousands of Python refusals (50 s under the sanitizers), not the core's memory
def test_every_refusal_names_the_argument(bases, monkeypatch):
    cases, folder = bases
    monkeypatch.chdir(folder)   # an accepted empty or relative output path writes there, not into the checkout
    problems, calls, refusals = [], 0, 0
    for function, (label, base) in cases.items():
        for name in _parameters(function):
            for value in BAD:
                if any(f is function and n == name and v is value for f, n, v in COSTLY):
                    continue
                if name in WRITTEN and isinstance(value, str) and value and len(value) < 100:
                    value = str(folder / "bad" / label / value)   # not into the working directory
                kwargs = dict(base, **{name: value})
                calls += 1
                got = _refusal(function, kwargs, name)
                if got is not None:
                    problems.append(f"{label}({name}={value!r:.40}): {got}")
    print("fuzz-result", json.dumps({"target": "api_faces", "calls": calls, "unnamed_refusals": len(problems)}))
    assert calls > 1000
    assert not problems, f"{len(problems)} of {calls} calls refused without naming the argument:\n" + \
        "\n".join(problems[:60])
