"""The emergency path's fault kinds written in a scenario file (issue 36): each parses with its
unit and changes the 1 ms plant's stop as its component says.

Two cars of crh380a-8, emergency from 80 km/h on dry rail, the faults on car 1 from the demand on.
References: the emergency circuit's structure (core/src/emergency_circuit.c: the emergency valve
feeds the relay's control chamber through the load-weighing valve, which limits it; a car that
does not see the loop brakes through its EP valve), the relay valve (its output follows its
control pressure, at most the pressure a failed one is stuck at), the isolating cock (its
cylinder at the atmosphere) and the train file's load-weighing limit. The checks compare a run
with the value the file gives or with another fault of the same effect, never an earlier output.
"""

from importlib import resources

import pytest

from railbrake import scenario, simulation

BAR = 1e5
TEXT = """schema: railbrake.scenario/1
name: emergency-path
train: {{preset: {train}, cars: 2}}
initial_speed: 80 km/h
demand: [{{time: 0 s, emergency: true}}]
adhesion: {{condition: dry-medium}}
stop: {{max_time: 60 s}}
faults: [{faults}]
"""
TOLERANCE = 0.02   # bar: the plant's relay regulates its output to the control pressure


def run(*faults, train="crh380a-8"):
    return simulation.run(scenario.parse(TEXT.format(train=train, faults=", ".join(faults)), "emergency-path.yaml"))


def gauge(result, channel):
    return (result.outputs[channel] - result.atmosphere) / BAR


@pytest.fixture(scope="module")
def sound():
    return run()


def test_each_kind_parses_with_its_unit():
    faults = scenario.parse(TEXT.format(train="crh380a-8", faults=", ".join([
        "{type: emergency_valve_failed, car: 1}", "{type: emergency_loop_lost, car: 2}",
        "{type: relay_valve_failed, car: 1, pressure: 1.2 bar}", "{type: pressure_limiter_failed, car: 2, pressure: 80 kPa}",
        "{type: axle_isolated, car: 1, axle: 2}"])), "f.yaml").spec.faults
    assert [f.type for f in faults] == ["emergency_valve_failed", "emergency_loop_lost", "relay_valve_failed",
                                        "pressure_limiter_failed", "axle_isolated"]
    assert [f.pressure for f in faults] == [None, None, pytest.approx(1.2 * BAR), pytest.approx(0.8 * BAR), None]
    assert (faults[4].car, faults[4].axle) == (1, 2)


@pytest.mark.parametrize("faults", [["{type: emergency_valve_failed, car: 1}"],
                                    ["{type: relay_valve_failed, car: 1, pressure: 0 bar}"],
                                    # the loop not seen: only the EP valve could brake the car, and it has failed
                                    ["{type: emergency_loop_lost, car: 1}", "{type: ep_valve_failed, car: 1}"]])
def test_a_car_whose_emergency_path_gives_no_output_has_no_brake(sound, faults):
    result, isolated = run(*faults), run("{type: car_isolated, car: 1}")
    for axle in range(1, 5):
        assert gauge(result, f"cylinder_c1a{axle}").max() < 0.01
        assert result.outputs[f"brake_energy_c1a{axle}"][-1] == 0.0
        assert gauge(result, f"cylinder_c2a{axle}").max() > 3.0   # the sound car fills
    # the same stop as the isolating cock's (the car's cylinders at the atmosphere either way)
    assert result.kpis["stopping_distance_m"] == pytest.approx(isolated.kpis["stopping_distance_m"], rel=1e-6)
    assert result.kpis["stopping_distance_m"] > 1.5 * sound.kpis["stopping_distance_m"]


def test_a_car_that_does_not_see_the_loop_brakes_through_its_ep_valve(sound):
    result = run("{type: emergency_loop_lost, car: 1}")
    # the BCU's emergency demand reaches the cylinders through the EP valve instead of the choke
    assert gauge(result, "cylinder_c1a1")[-1] == pytest.approx(gauge(sound, "cylinder_c1a1")[-1], abs=TOLERANCE)


@pytest.mark.parametrize("stuck", ["0.6 bar", "1.2 bar", "150 kPa"])
def test_a_relay_valve_stuck_at_a_partial_pressure_holds_the_cylinders_there(sound, stuck):
    result = run(f"{{type: relay_valve_failed, car: 1, pressure: {stuck}}}")
    value = float(stuck.split()[0]) * (1.0 if stuck.endswith("bar") else 1e3 / BAR)
    assert gauge(sound, "cylinder_c1a1")[-1] > value + 0.5   # below what the car's relay would give
    for axle in range(1, 5):
        cylinder = gauge(result, f"cylinder_c1a{axle}")
        assert cylinder[-1] == pytest.approx(value, abs=TOLERANCE)
        assert cylinder.max() < value + TOLERANCE
    assert gauge(result, "pilot_c1").max() > 2.0   # its control chamber fills as the sound one's
    assert result.kpis["stopping_distance_m"] > sound.kpis["stopping_distance_m"]


@pytest.fixture(scope="module")
def low_limit_train(tmp_path_factory):
    """crh380a-8 with its load-weighing valves limiting at 1.5 bar, below the BCU's emergency
    demand (the shipped limits lie above it: a back-up the sound brake never reaches)."""
    shipped = "limit_bar: {tare: 3.8, crush: 4.5}"
    text = (resources.files("railbrake") / "data" / "trains" / "crh380a-8.yaml").read_text()
    assert text.count(shipped) == 2   # motor and trailer
    path = tmp_path_factory.mktemp("train") / "low-limit.yaml"
    path.write_text(text.replace(shipped, "limit_bar: {tare: 1.5, crush: 1.5}"))
    return str(path), 1.5


def test_a_limiter_failed_high_lets_the_cylinders_exceed_the_nominal_limit(sound, low_limit_train):
    train, limit = low_limit_train
    base, result = run(train=train), run("{type: pressure_limiter_failed, car: 1, pressure: 8 bar}", train=train)
    for r in (base, result):
        assert gauge(r, "cylinder_c2a1")[-1] == pytest.approx(limit, abs=TOLERANCE)   # the sound limiter holds
    assert gauge(base, "cylinder_c1a1")[-1] == pytest.approx(limit, abs=TOLERANCE)
    # failed high the car follows the BCU's demand, as the car whose limit lies above it
    cylinder = gauge(result, "cylinder_c1a1")
    assert cylinder[-1] > limit + 0.5
    assert cylinder[-1] == pytest.approx(gauge(sound, "cylinder_c1a1")[-1], abs=TOLERANCE)
    assert result.kpis["stopping_distance_m"] < base.kpis["stopping_distance_m"]


@pytest.mark.parametrize("low", ["0.8 bar", "1.2 bar"])
def test_a_limiter_failed_low_holds_the_emergency_pressure_at_its_value(sound, low):
    result = run(f"{{type: pressure_limiter_failed, car: 1, pressure: {low}}}")
    value = float(low.split()[0])
    assert gauge(result, "pilot_c1").max() == pytest.approx(value, abs=TOLERANCE)
    assert gauge(result, "cylinder_c1a1")[-1] == pytest.approx(value, abs=TOLERANCE)
    assert gauge(result, "cylinder_c2a1")[-1] == pytest.approx(gauge(sound, "cylinder_c2a1")[-1], abs=TOLERANCE)


def test_an_isolated_bogie_gets_no_brake_force_on_its_axles(sound):
    result = run("{type: axle_isolated, car: 1, axle: 1}", "{type: axle_isolated, car: 1, axle: 2}")
    for axle in (1, 2):
        assert gauge(result, f"cylinder_c1a{axle}").max() < 0.01
        assert result.outputs[f"brake_energy_c1a{axle}"][-1] == 0.0
    for axle in (3, 4):   # the other bogie brakes as the sound car's
        assert gauge(result, f"cylinder_c1a{axle}")[-1] == pytest.approx(
            gauge(sound, f"cylinder_c1a{axle}")[-1], abs=TOLERANCE)
        assert result.outputs[f"brake_energy_c1a{axle}"][-1] > 0.0
    assert result.kpis["stopping_distance_m"] > sound.kpis["stopping_distance_m"]
