"""Fit the sintered pads' fading law of the train presets to published dynamometer stops.

Run: python tools/fit_pad_fade.py
It runs the fit of src/railbrake/data/pads/sintered-cu.yaml (its `fit` entry: the onset from the
speed below which such pads are published stable, the level and the rate from the stop averages
named there) with stops of the data file's dynamometer disc in the core (railbrake.pad_fade.fit),
and prints the cold table (the trailer's table shifted) and the fade the train files carry; they
are written into src/railbrake/data/trains/*.yaml by hand. A calibration: the validation case
pad-friction-stop-250-380 checks its consistency, pad-friction-stop-cross-pad a fit on other data.
Last it prints how a fit on 250 km/h and a third stop of the same pad (350 km/h, none published
that we found) would carry those two figures' scatter into its 380 km/h prediction.
"""

from railbrake import pad_fade
from railbrake.units import KMH
from railbrake.vehicle import ZERO_CELSIUS, dynamometer_stop


def main() -> None:
    data = pad_fade.load_data()
    car, conditions = pad_fade.dynamometer(data)
    fit = pad_fade.preset_fit(data)
    table = car.c.brake.pad.table
    print("table.speed_kmh:", [round(table.speed[i] / KMH, 6) for i in range(table.n)])
    print("table.value:", [round(table.value[i] + fit.shift, 4) for i in range(table.n)])
    print(f"fade: onset_c: {fit.onset - ZERO_CELSIUS:.1f}, rate_per_K: {fit.rate:.3e}")
    pad = pad_fade.pad_with(car, fit.shift, fit.onset, fit.rate)
    for v in (200, 250, 300, 350, 380):
        stop = dynamometer_stop(car, v * KMH, pad=pad, **conditions)
        print(f"{v} km/h: mean friction {stop.mean_friction:.4f}, surface peak "
              f"{stop.max_surface_temperature - ZERO_CELSIUS:.0f} °C, mean disc {stop.max_mean_temperature - ZERO_CELSIUS:.0f} °C")
    third_stop(data, car, conditions, pad)


def third_stop(data, car, conditions, pad) -> None:
    """How far a fit on 250 km/h and a third stop (350 km/h, at the fitted law's own value) carries
    the scatter of those two into the 380 km/h prediction: the tolerance a check of that fit needs
    (pad-friction-stop-cross-pad)."""
    figure = next(f for f in data["figures"] if f["id"] == data["fit"]["level"]["from"])
    scatter, level = figure["stability"], data["fit"]["level"]
    onset_speed = data["fit"]["onset"]["speed_kmh"] * KMH
    third = dynamometer_stop(car, 350 * KMH, pad=pad, **conditions).mean_friction
    for d250, d350 in ((scatter, 0.0), (-scatter, 0.0), (0.0, scatter), (0.0, -scatter)):
        f = pad_fade.fit(car, conditions, onset_speed=onset_speed, level_speed=level["speed_kmh"] * KMH,
                         level_mean=level["mean"] + d250, rate_speed=350 * KMH, rate_mean=third + d350)
        stop = dynamometer_stop(car, 380 * KMH, pad=pad_fade.pad_with(car, f.shift, f.onset, f.rate), **conditions)
        print(f"250 km/h {d250:+.4f}, 350 km/h {d350:+.4f}: 380 km/h predicted {stop.mean_friction:.4f}")


if __name__ == "__main__":
    main()
