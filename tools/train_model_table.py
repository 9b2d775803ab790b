"""The table of docs/simulation.md "The run against the calculation": every preset train on dry,
level track from 200, 250, 300 km/h and its top speed, `railbrake run` against `railbrake
stopping-distance` (with the simulated response and with the profile's). Prints Markdown rows.

    python tools/train_model_table.py
"""

from railbrake import simulation, sizing, vehicle
from railbrake.units import KMH


def row(train: str, kmh: float) -> str:
    r = simulation.run(simulation.emergency_scenario(train, kmh * KMH, max_time=400.0))
    ta, tb = simulation.response_times(r)
    simulated = sizing.stopping_distance(kmh * KMH, train=train, delay=ta, build_up=tb).distance
    profile = sizing.stopping_distance(kmh * KMH, train=train).distance
    k = r.kpis
    run = k["stopping_distance_m"]
    return (f"| {train} | {kmh:.0f} | {run:.0f} | {simulated:.0f} | {100 * (run / simulated - 1):+.1f} % | "
            f"{profile:.0f} | {ta:.2f} / {tb:.2f} | {k['brake_energy_mj']:.0f} | {k['max_disc_temperature_c']:.0f} | "
            f"{k['air_drawn_kg']:.3f} | {k['min_supply_bar']:.2f} |")


if __name__ == "__main__":
    for name in vehicle.preset_names():
        top = vehicle.load_train(name).max_speed / KMH
        for kmh in (200, 250, 300, top):
            print(row(name, kmh), flush=True)
