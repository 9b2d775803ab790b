"""Study files: parsing, errors that name key and line, designs, seeds and run keys."""

from pathlib import Path

import numpy as np
import pytest

from railbrake.campaign import designs, plan, study
from railbrake.errors import InputError

DATA = Path(__file__).parent / "data"

HEAD = """schema: railbrake.study/1
name: t
base: emergency-250-dry
set: {train.cars: 1, stop.max_time: "60 s"}
"""


def parse(body: str) -> study.Study:
    return study.parse(HEAD + body, "t.yaml")


def test_unknown_factor_path_names_line_and_closest_keys():
    with pytest.raises(InputError) as err:
        parse("factors:\n  initial_sped: [\"60 km/h\"]\ndesign: {kind: grid}\n")
    message = str(err.value)
    assert "t.yaml, line 6: factors.initial_sped" in message
    assert "closest valid: initial_speed" in message


def test_range_with_low_not_below_high_names_line():
    with pytest.raises(InputError, match=r"line 7: factors.initial_speed: low '120 km/h' >= high '60 km/h'"):
        parse("factors:\n  adhesion.condition: [wet]\n  initial_speed: {low: 120 km/h, high: 60 km/h}\n"
              "design: {kind: latin-hypercube, samples: 4}\n")


@pytest.mark.parametrize("body, key", [
    ("factors:\n  initial_speed: {low: 60 km/h, high: 90 km/h}\ndesign: {kind: latin-hypercube, samples: 0}\n",
     "line 7: design.samples = 0: a design with no runs"),
    ("factors:\n  initial_speed: []\ndesign: {kind: grid}\n", "line 6: factors.initial_speed: an empty list"),
    ("design: {kind: list, points: []}\n", "line 5: design.points: a design with no runs"),
    ("factors:\n  initial_speed: [\"60 km/h\"]\ndesign: {kind: grid}\nseeds: 0\n",
     "line 8: seeds = 0: a design with no runs"),
])
def test_design_with_no_runs_fails_naming_key_and_line(body, key):
    with pytest.raises(InputError, match=key):
        parse(body)


def test_levels_need_one_kind_of_unit_and_a_range_the_same_dimension():
    with pytest.raises(InputError, match="levels mix"):
        parse("factors:\n  initial_speed: [\"60 km/h\", \"2 s\"]\ndesign: {kind: grid}\n")
    with pytest.raises(InputError, match="not the same kind of quantity"):
        parse("factors:\n  initial_speed: {low: 60 km/h, high: 5 s}\ndesign: {kind: latin-hypercube, samples: 2}\n")


def test_sobol_needs_a_power_of_two():
    with pytest.raises(InputError, match="line 7: design.samples = 6: a Sobol design needs a power of two"):
        parse("factors:\n  initial_speed: {low: 60 km/h, high: 90 km/h}\ndesign: {kind: sobol, samples: 6}\n")


def test_grid_is_the_full_factorial_and_values_are_si():
    s = study.load(DATA / "small.yaml")
    runs = plan.plan(s)
    assert len(runs) == 2 * 2 * 2
    speeds = sorted({r.factors["initial_speed"] for r in runs})
    assert speeds == pytest.approx([40 / 3.6, 60 / 3.6])
    assert s.factor("initial_speed").unit == "m/s"
    assert len({r.key for r in runs}) == len(runs)


def test_latin_hypercube_fills_each_stratum_once_and_seeds_repeat():
    s = parse("factors:\n  initial_speed: {low: 60 km/h, high: 120 km/h}\n"
              "design: {kind: latin-hypercube, samples: 5}\nseed: 7\n")
    points = list(designs.points(s, np.random.default_rng(np.random.SeedSequence(7).spawn(2)[0])))
    v = np.array([float(p.values["initial_speed"].split()[0]) for p in points])
    strata = np.floor((v - 60) / 12).astype(int)
    assert sorted(strata) == [0, 1, 2, 3, 4]
    # the same SeedSequence gives the same runs (keys), another seed other ones (each run is resolved:
    # two samples are enough)
    two = parse("factors:\n  initial_speed: {low: 60 km/h, high: 120 km/h}\n"
                "design: {kind: latin-hypercube, samples: 2}\nseed: 7\n")
    keys = [r.key for r in plan.plan(two)]
    assert keys == [r.key for r in plan.plan(two)] and len(set(keys)) == 2
    two = two.with_(seed=8)
    assert not set(keys) & {r.key for r in plan.plan(two)}


def test_sobol_design_is_saltelli_a_b_ab():
    s = parse("factors:\n  initial_speed: {low: 60 km/h, high: 120 km/h}\n"
              "  adhesion.condition: [dry-medium, wet]\ndesign: {kind: sobol, samples: 4}\n")
    points = list(designs.points(s, np.random.default_rng(0)))
    assert len(points) == 4 * (2 + 2)
    by = {(p.block, p.sample): p.values for p in points}
    for i in range(4):   # AB0 takes factor 0 from B and factor 1 from A
        assert by[("AB0", i)]["initial_speed"] == by[("B", i)]["initial_speed"]
        assert by[("AB0", i)]["adhesion.condition"] == by[("A", i)]["adhesion.condition"]


def test_fault_and_zone_parts_become_one_fault_and_one_zone():
    s = parse("factors:\n  fault.type: [none, vent_stuck_open]\n  fault.car: [1]\n  fault.start: [\"2 s\"]\n"
              "  zone.start: [\"100 m\"]\n  zone.length: [\"50 m\"]\n  zone.condition: [hs-wet]\n"
              "design: {kind: grid}\n")
    runs = plan.plan(s)
    assert "faults" not in runs[0].sets
    assert runs[1].sets["faults"] == [{"type": "vent_stuck_open", "car": 1, "start": "2 s"}]
    assert runs[1].sets["adhesion.zones"] == [{"start": "100 m", "end": "150 m", "condition": "hs-wet"}]


def test_a_failed_relay_valve_s_pressure_is_a_factor():
    s = parse("factors:\n  fault.type: [relay_valve_failed]\n  fault.car: [1]\n"
              "  fault.pressure: {low: 0 bar, high: 3 bar, levels: 4}\ndesign: {kind: grid}\n")
    runs = plan.plan(s)
    assert [r.sets["faults"][0]["pressure"] for r in runs] == ["0 bar", "1 bar", "2 bar", "3 bar"]
    assert [r.factors["fault.pressure"] for r in runs] == pytest.approx([0.0, 1e5, 2e5, 3e5])   # SI: Pa
    with pytest.raises(InputError, match=r"design point 0 .*fault\.pressure.* a vent_stuck_open fault does not use "
                                         r"pressure"):
        plan.plan(parse("factors:\n  fault.type: [vent_stuck_open]\n  fault.car: [1]\n"
                        "  fault.pressure: [1 bar]\ndesign: {kind: grid}\n"))


def test_a_fault_on_a_missing_car_fails_before_any_run():
    s = parse("factors:\n  fault.type: [vent_stuck_open]\n  fault.car: [2]\ndesign: {kind: grid}\n")
    with pytest.raises(InputError, match="design point 0 .*fault.car=2"):
        plan.plan(s)


def test_named_cases_set_several_keys():
    s = parse("factors:\n  case:\n    - {name: dry, adhesion.condition: dry-medium}\n"
              "    - {name: patch, zone.start: 100 m, zone.length: 50 m, zone.condition: hs-wet}\n"
              "design: {kind: grid}\n")
    runs = plan.plan(s)
    assert [r.factors["case"] for r in runs] == ["dry", "patch"]
    assert runs[1].sets["adhesion.zones"][0]["end"] == "150 m"
    with pytest.raises(InputError, match=r"line 7: factors.case.0.adhesion.conditon: unknown path"):
        parse("factors:\n  case:\n    - {name: dry, adhesion.conditon: dry-medium}\ndesign: {kind: grid}\n")


def test_an_integer_range_gives_every_integer_alike():
    s = parse("factors:\n  fault.type: [vent_stuck_open]\n  fault.car: [1]\n"
              "  fault.axle: {low: 1, high: 4}\ndesign: {kind: latin-hypercube, samples: 8}\n")
    axles = [p.values["fault.axle"] for p in designs.points(s, np.random.default_rng(3))]
    assert sorted(axles) == [1, 1, 2, 2, 3, 3, 4, 4]   # the hypercube's strata, two per axle


def test_only_keeps_the_points_at_any_of_the_values_given_per_factor():
    from railbrake.campaign import tune
    s = parse("factors:\n  initial_speed: [\"60 km/h\", \"100 km/h\"]\n"
              "  adhesion.condition: [dry-medium, wet, oil-film]\ndesign: {kind: grid}\n")
    keep = tune.select(s, ["initial_speed=100 km/h", "adhesion.condition=wet", "adhesion.condition=oil-film"])
    kept = [(r.factors["initial_speed"], r.factors["adhesion.condition"]) for r in plan.plan(s, keep)]
    assert kept == [(pytest.approx(100 / 3.6), "wet"), (pytest.approx(100 / 3.6), "oil-film")]
    with pytest.raises(InputError, match="--only speed=1: 'speed' is not a factor"):
        tune.select(s, ["speed=1"])


def test_the_en15595_preset_crosses_controllers_speeds_adhesion_brakes_and_load_cases():
    from railbrake import simulation
    from railbrake.campaign import configuration
    s = study.load("wsp-en15595")
    train = configuration.resolve(s.base, s.fixed).train
    assert s.factor("wsp.controller").levels == list(simulation.WSP_CONTROLLERS)   # every controller, from the code
    speeds = s.factor("initial_speed").levels
    assert s.factor("initial_speed").si(speeds[-1]) == pytest.approx(train.max_speed)   # the train's maximum
    assert s.factor("train.load_case").levels == ["tare", "normal", "crush"]
    names = {f: [level["name"] for level in s.factor(f).levels] for f in ("adhesion_case", "brake")}
    assert names == {"adhesion_case": ["dry", "low", "very-low", "hs-wet", "dry-low-dry"],
                     "brake": ["emergency", "full-service"]}
    points = list(designs.points(s, np.random.default_rng(0)))
    assert len(points) == len(simulation.WSP_CONTROLLERS) * 2 * 5 * 2 * 3
    # every case has its dry reference with the same controller, speed, brake and load
    reference = s.spec.assessment.reference["adhesion_case"]
    key = lambda p: (p.values["wsp.controller"], p.values["initial_speed"], p.values["brake"]["name"],  # noqa: E731
                     p.values["train.load_case"])
    assert {key(p) for p in points} == {key(p) for p in points if p.values["adhesion_case"]["name"] == reference}
    assert s.spec.assessment.criteria.max_lock_events == 0 and s.spec.assessment.criteria.min_utilisation == 0.85
    assert s.spec.assessment.rank == "wsp.controller"


def test_the_en15595_sudden_change_is_met_at_speed_with_the_brake_applied():
    """From the maximum speed the dry-low-dry patch begins where the emergency brake has built up
    (the cylinders as full as at the patch's end) and the train still runs within 3 % of that speed."""
    from railbrake import simulation
    from railbrake.campaign import configuration
    s = study.load("wsp-en15595")
    patch = next(level for level in s.factor("adhesion_case").levels if level["name"] == "dry-low-dry")
    start, length = (s.factor("initial_speed").si(patch[k]) for k in ("zone.start", "zone.length"))
    top = s.factor("initial_speed").levels[-1]
    resolved = configuration.resolve(s.base, {**s.fixed, "initial_speed": top})
    r = simulation.run(resolved)
    at = np.searchsorted(r.outputs["position"], [start, start + length])
    cylinders = np.mean([r.outputs[n] for n in r.axle_channels("cylinder")], axis=0) - r.atmosphere
    assert cylinders[at[0]] >= 0.98 * cylinders[at[1]] > 0.0
    assert r.outputs["speed"][at[0]] >= 0.97 * s.factor("initial_speed").si(top)


def test_all_levels_come_from_the_schema_and_only_where_it_lists_them():
    s = parse("factors:\n  wsp.controller: all\n  adhesion.rail_conditioning: all\ndesign: {kind: grid}\n")
    from railbrake import simulation
    assert s.factor("wsp.controller").levels == list(simulation.WSP_CONTROLLERS)
    assert s.factor("adhesion.rail_conditioning").levels == ["axles", "cells"]
    with pytest.raises(InputError, match=r"t.yaml, line 6: factors.initial_speed = 'all': initial_speed has no fixed set"):
        parse("factors:\n  initial_speed: all\ndesign: {kind: grid}\n")
    with pytest.raises(InputError, match="unknown path 'wsp.controler'"):
        parse("factors:\n  wsp.controler: all\ndesign: {kind: grid}\n")


def test_the_ranked_factor_must_be_a_factor_other_than_the_reference():
    body = ("factors:\n  wsp.controller: all\n  adhesion_case:\n    - {name: dry, adhesion.condition: dry-medium}\n"
            "    - {name: low, adhesion.condition: oil-film}\ndesign: {kind: grid}\n"
            "assessment:\n  reference: {adhesion_case: dry}\n  rank: RANK\n")
    assert parse(body.replace("RANK", "wsp.controller")).spec.assessment.rank == "wsp.controller"
    for bad in ("adhesion_case", "initial_speed"):
        with pytest.raises(InputError, match=f"assessment.rank = '{bad}': must be a factor of the study other than "
                                             "the reference's \\(wsp.controller\\)"):
            parse(body.replace("RANK", bad))


WSP_HEAD = """schema: railbrake.study/1
name: controllers
base: emergency-300-heavy-rain
set: {train.cars: 1, adhesion.condition: hs-wet, stop.max_time: "8 s"}
"""


def test_the_wsp_controllers_and_the_conditioning_mode_are_factors():
    """Each run of a study gets the controller and mode of its design point in its C parameters,
    and they act: the runs' valve commands differ."""
    from railbrake import simulation
    from railbrake.campaign import configuration
    s = study.parse(WSP_HEAD + "factors:\n  wsp.controller: [threshold, slip_setpoint, decel_slip_speed]\n"
                    "  wsp.conditioning_mode: [false, true]\ndesign: {kind: grid}\n", "t.yaml")
    runs = plan.plan(s)
    assert len(runs) == 6
    vents = {}
    for r in runs:
        resolved = configuration.resolve(s.base, r.sets)
        w = simulation.wsp_params(resolved.scenario)
        controller, mode = r.sets["wsp.controller"], r.sets["wsp.conditioning_mode"]
        assert (w.controller, w.conditioning_mode) == (simulation.WSP_CONTROLLERS.index(controller), int(mode))
        result = configuration.run(resolved, record=True)
        vents[controller, str(mode)] = np.concatenate([result.outputs[n] for n in result.axle_channels("vent")])
    assert len({v.tobytes() for v in vents.values()}) == 6


def test_a_level_setting_a_key_its_controller_does_not_read_fails_before_any_run():
    body = ("schema: railbrake.study/1\nname: c\nbase: emergency-300-heavy-rain\n"
            "set: {train.cars: 1, wsp.setpoint_speed: \"0.05 m/s\"}\n"
            "factors:\n  wsp.controller: [slip_setpoint, decel_slip_speed]\ndesign: {kind: grid}\n")
    with pytest.raises(InputError, match=r"design point 1 \(wsp.controller=decel_slip_speed\).*wsp.setpoint_speed.*"
                                         r"only slip_setpoint"):
        plan.plan(study.parse(body, "t.yaml"))


def test_wsp_tune_takes_each_controller_s_parameters_in_their_c_bounds():
    from railbrake.campaign import tune
    tuning = ("tuning:\n  params:\n    wsp.ds_speed_threshold: {low: \"0.1 m/s\", high: \"1 m/s\"}\n"
              "    wsp.ds_decel_threshold: {low: \"1.5 m/s^2\", high: \"3 m/s^2\"}\n"
              "    wsp.conditioning_ratio: {low: 1.5, high: 4.0}\n")
    s = study.parse(WSP_HEAD.replace("stop.max_time", "wsp.controller: decel_slip_speed, wsp.conditioning_mode: true, "
                                     "stop.max_time") + "factors:\n  initial_speed: [\"300 km/h\"]\n"
                    "design: {kind: grid}\n" + tuning, "t.yaml")
    params = tune.parameters(s, ["ds_speed_threshold", "wsp.ds_decel_threshold", "conditioning_ratio"])
    assert [p.key for p in params] == ["wsp.ds_speed_threshold", "wsp.ds_decel_threshold", "wsp.conditioning_ratio"]
    assert params[0].factor.low == pytest.approx(0.1) and params[0].factor.high == pytest.approx(1.0)
    defaults = tune.default_values(params)   # the C core's defaults, the first trial
    assert defaults == {"wsp.ds_speed_threshold": pytest.approx(0.3), "wsp.ds_decel_threshold": pytest.approx(2.0),
                        "wsp.conditioning_ratio": pytest.approx(3.0)}
    with pytest.raises(InputError, match=r"tuning.params.wsp.ds_decel_threshold: low '1 m/s\^2' to high '200 "
                                         r"m/s\^2': must lie in \[0.1, 100\] m/s\^2"):
        study.parse(WSP_HEAD + "factors:\n  initial_speed: [\"300 km/h\"]\ndesign: {kind: grid}\n"
                    "tuning:\n  params:\n    wsp.ds_decel_threshold: {low: \"1 m/s^2\", high: \"200 m/s^2\"}\n", "t.yaml")
