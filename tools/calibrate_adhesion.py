"""Calibrate the adhesion presets that are not Polach's published sets.

Run: python tools/calibrate_adhesion.py. It prints the parameters written into
src/railbrake/data/adhesion/*.yaml; the targets are documented in those files and checked
by tests/unit/test_adhesion.py.
"""

from dataclasses import replace

import numpy as np
from scipy.optimize import brentq, least_squares

from railbrake.adhesion import load_condition
from railbrake.contact import PolachParams, default_contact, polach_coefficient, polach_peak

CONTACT = default_contact()
Q = CONTACT.normal_force


def peak(params, v_kmh):
    return polach_peak(v_kmh / 3.6, Q, CONTACT, params)[0]


def scale_mu0(shape: PolachParams, v_kmh: float, target: float) -> float:
    """mu0 that gives `target` peak at v_kmh with the other four parameters of `shape`."""
    def gap(mu0):
        return peak(PolachParams(mu0, shape.A, shape.B, shape.kA, shape.kS), v_kmh) - target
    return brentq(gap, 1e-3, 2.0)


def conditioned(params: PolachParams, axle: int, f0: float, n_rec: float) -> PolachParams:
    factor = 1.0 - (1.0 - f0) * np.exp(-axle / n_rec)
    return replace(params, mu0=params.mu0 * factor)


def car_mean(params, f0, n_rec, car, v_kmh):
    return float(np.mean([peak(conditioned(params, a, f0, n_rec), v_kmh)
                          for a in range(4 * (car - 1), 4 * car)]))


def tail_ratio(params: PolachParams, v_kmh: float) -> float:
    """F/Q at 30 % creep over the peak: below 1 the curve falls after its peak, so a locked
    wheel brakes less than a wheel near the peak (what WSP relies on)."""
    coefficient = polach_coefficient(0.3, v_kmh / 3.6, Q, CONTACT, params)
    return coefficient / peak(params, v_kmh)


def calibrate_heavy_rain(leading_factor_low: float = 0.2, rolling_factor: bool = False):
    """Joint fit of mu0, A, B (kA, kS from Polach's wet set) and the conditioning law to: ~0.02 on car 1 and ~0.05 on
    car 4 at 300 km/h (Shinkansen heavy-rain measurement); the 8-car mean following the design
    curve 13.6/(v+85) from 100 to 300 km/h (weighted less: that curve is a lower bound that
    includes leading cars); and a falling tail (F/Q at 30 % creep <= 0.8 peak) on every car.
    rolling_factor: v_ref of mu0 / (1 + v / v_ref) fitted too (the preset does not use it: see main)."""
    speeds = np.array([100.0, 200.0, 300.0])

    def params(x):
        v_ref = x[5] / 3.6 if rolling_factor else None
        return PolachParams(x[0], x[1], x[2], 0.3, 0.1, v_ref)

    def residual(x):
        p, f0, n_rec = params(x), x[3], x[4]
        r = [3.0 * (car_mean(p, f0, n_rec, 1, 300.0) / 0.02 - 1.0),
             3.0 * (car_mean(p, f0, n_rec, 4, 300.0) / 0.05 - 1.0)]
        for v in speeds:
            train = np.mean([car_mean(p, f0, n_rec, c, v) for c in range(1, 9)])
            r.append(train / (13.6 / (v + 85.0)) - 1.0)
        for v in (50.0, 150.0, 300.0):
            for axle in (0, 12, 60):
                r.append(3.0 * max(0.0, tail_ratio(conditioned(p, axle, f0, n_rec), v) - 0.8))
        return r

    x0, lo, hi = [0.3, 0.3, 0.5, 0.3, 4.0], [0.05, 0.0, 0.0, leading_factor_low, 0.5], [1.0, 1.0, 10.0, 1.0, 64.0]
    if rolling_factor:
        x0, lo, hi = x0 + [100.0], lo + [5.0], hi + [2000.0]
    fit = least_squares(residual, x0, bounds=(lo, hi))
    print(f"heavy-rain{' with the rolling-speed factor' if rolling_factor else ''} residuals "
          "(car1, car4, train@100/200/300, tails):", np.round(fit.fun, 3))
    return params(fit.x), fit.x[3:5]


# Polach's wet set (Wear 258 (2005) 992-1000, Table 2)
WET_SET = PolachParams(0.30, 0.40, 0.20, 0.30, 0.10)
HS_WET_SPEEDS = np.array([30.0, 60.0, 100.0, 150.0, 200.0, 250.0, 300.0, 320.0])
HS_WET_BOUNDS = ([0.01, 5.0], [1.0, 2000.0])   # mu0, v_ref_kmh: hs-wet.yaml fit.parameters


def design(v_kmh):
    """The Shinkansen design adhesion 13.6/(v + 85), v in km/h [P, as cited]."""
    return 13.6 / (v_kmh + 85.0)


def with_rolling_factor(shape: PolachParams, mu0: float, v_ref_kmh: float) -> PolachParams:
    return PolachParams(mu0, shape.A, shape.B, shape.kA, shape.kS, v_ref_kmh / 3.6)


def hs_wet_shape() -> PolachParams:
    """The curve's shape of the heavy-rain preset (A, B fitted on the Shinkansen heavy-rain
    measurement, kA, kS Polach's wet set): the same wet rail at the same speeds."""
    return load_condition("heavy-rain").params


def fit_hs_wet(shape: PolachParams):
    """mu0 and v_ref (mu0 / (1 + v / v_ref)) of `shape` fitted on the design curve 30-320 km/h."""
    def residual(x):
        p = with_rolling_factor(shape, x[0], x[1])
        r = [peak(p, v) / design(v) - 1.0 for v in HS_WET_SPEEDS]
        return r + [3.0 * max(0.0, tail_ratio(p, v) - 0.8) for v in (60.0, 300.0)]

    fits = [least_squares(residual, x0, bounds=HS_WET_BOUNDS) for x0 in ([0.3, 100.0], [0.15, 50.0], [0.5, 400.0])]
    return min(fits, key=lambda f: f.cost)


def calibrate_hs_wet():
    """mu0 and the rolling-speed factor's v_ref so that the peak follows the Shinkansen design adhesion
    13.6/(v+85) from 30 to 320 km/h; A, B, kA, kS those of heavy-rain (hs_wet_shape: the design
    curve's peaks do not fix the curve after the peak, hs_wet_shape_free). Both fitted parameters end
    inside their bounds."""
    best = fit_hs_wet(hs_wet_shape())
    print("hs-wet residuals (peak / design - 1 at 30..320 km/h, tails):", np.round(best.fun, 4))
    inside = np.all((best.x > np.array(HS_WET_BOUNDS[0]) + 1e-6) & (best.x < np.array(HS_WET_BOUNDS[1]) - 1e-6))
    print("hs-wet mu0, v_ref_kmh:", np.round(best.x, 4), "inside their bounds:", bool(inside))
    return with_rolling_factor(hs_wet_shape(), *best.x)


def peak_slip_velocity(params: PolachParams, v_kmh: float) -> float:
    return polach_peak(v_kmh / 3.6, Q, CONTACT, params)[1] * v_kmh / 3.6


def hs_wet_shape_free():
    """Why hs-wet's A and B are not fitted, and why heavy-rain's: fitted with mu0 and v_ref on the
    design curve's peaks, A and B are not determined by them (A goes to its bound 0 at the same
    residuals); Polach's wet set fits the peaks as well but puts them at 4 times heavy-rain's slip
    velocity at 300 km/h, on the same wet rail. And why the rolling-speed factor: without it
    (Polach's law alone, A, B free), A goes to 0 on every speed range and with kA, kS free too, as
    the friction falls with slip velocity only."""
    def residual(x):
        p = with_rolling_factor(PolachParams(x[0], x[2], x[3], 0.3, 0.1), x[0], x[1])
        r = [peak(p, v) / design(v) - 1.0 for v in HS_WET_SPEEDS]
        return r + [3.0 * max(0.0, tail_ratio(p, v) - 0.8) for v in (60.0, 300.0)]
    fit = least_squares(residual, [0.3, 100.0, 0.4, 0.2], bounds=([0.01, 5.0, 0.0, 0.0], [1.0, 2000.0, 1.0, 20.0]))
    print(f"hs-wet with A, B free beside mu0, v_ref: A = {fit.x[2]:.2g}, B = {fit.x[3]:.3g} s/m, worst residual "
          f"{np.max(np.abs(fit.fun)):.4f} (the peaks do not fix the tail)")
    wet = fit_hs_wet(WET_SET)
    heavy = [peak_slip_velocity(load_condition("heavy-rain").params_at_axle(a), 300.0) for a in (0, 31)]
    print(f"hs-wet on Polach's wet set's A, B: mu0, v_ref_kmh = {np.round(wet.x, 4)}, worst residual "
          f"{np.max(np.abs(wet.fun)):.4f}; peak slip velocity at 300 km/h "
          f"{peak_slip_velocity(with_rolling_factor(WET_SET, *wet.x), 300.0):.2f} m/s against heavy-rain's "
          f"{heavy[0]:.2f}-{heavy[1]:.2f} m/s (axles 1 and 32)")
    for speeds in (HS_WET_SPEEDS, HS_WET_SPEEDS[1:], HS_WET_SPEEDS[2:]):
        for free_k in (False, True):
            def residual(x):
                p = PolachParams(*x) if free_k else PolachParams(x[0], x[1], x[2], 0.3, 0.1)
                r = [peak(p, v) / design(v) - 1.0 for v in speeds]
                return r + [3.0 * max(0.0, tail_ratio(p, v) - 0.8) for v in (60.0, 300.0)]
            x0, lo, hi = [0.3, 0.1, 0.5], [0.01, 0.0, 0.0], [1.5, 1.0, 40.0]
            if free_k:
                x0, lo, hi = x0 + [0.3, 0.1], lo + [1e-3, 1e-3], hi + [1.0, 1.0]
            fit = least_squares(residual, x0, bounds=(lo, hi))
            print(f"hs-wet without the rolling-speed factor, {speeds[0]:.0f}-{speeds[-1]:.0f} km/h, kA kS "
                  f"{'free' if free_k else 'wet set'}: A = {fit.x[1]:.2g}, worst residual {np.max(np.abs(fit.fun)):.3f}")


def heavy_rain_lower_envelope_residual(x, mu0=None):
    """Residuals of heavy-rain read with the design curve as what it is, a lower bound of wet-rail
    measurements (not the train's mean): the car values fix level and conditioning, the fully
    conditioned rail follows the curve's slope 13.6/(v+85) with its level free, through the
    rolling-speed factor (A, B, kA, kS as the preset's); falling tails on every car. x = mu0, v_ref_kmh,
    leading_factor, recovery_axles, or the last three with mu0 given."""
    mu0, (v_ref, f0, n_rec) = (x[0], x[1:]) if mu0 is None else (mu0, x)
    shape = load_condition("heavy-rain").params
    p = with_rolling_factor(shape, mu0, v_ref)
    r = [3.0 * (car_mean(p, f0, n_rec, 1, 300.0) / 0.02 - 1.0),
         3.0 * (car_mean(p, f0, n_rec, 4, 300.0) / 0.05 - 1.0)]
    r += [peak(p, v) / peak(p, 300.0) / (design(v) / design(300.0)) - 1.0 for v in (100.0, 150.0, 200.0, 250.0)]
    return r + [3.0 * max(0.0, tail_ratio(conditioned(p, a, f0, n_rec), v) - 0.8)
                for v in (50.0, 150.0, 300.0) for a in (0, 12, 60)]


def heavy_rain_lower_envelope():
    """The heavy-rain refit that removes the conflict behind fit.at_bound.leading_factor, and why the
    preset does not take it: read as a lower bound, the design curve no longer pulls the train's mean
    down, and the leading factor leaves its bound (about 0.12); but two car values at one speed and the
    curve's slope do not fix the conditioned rail's level, the leading factor and the recovery length
    together: with mu0 held anywhere from 0.4 to 0.7, the other three refit to the same residuals, the
    leading factor from 0.001 to 0.12 and the recovery from 3 to 21 axles (the profile printed)."""
    lo, hi = [0.01, 5.0, 1e-3, 0.5], [1.5, 2000.0, 1.0, 64.0]
    fit = least_squares(heavy_rain_lower_envelope_residual, [0.3, 150.0, 0.3, 4.0], bounds=(lo, hi))
    mu0, v_ref, f0, n_rec = fit.x
    p = with_rolling_factor(load_condition("heavy-rain").params, mu0, v_ref)
    means = [np.mean([car_mean(p, f0, n_rec, c, v) for c in range(1, 9)]) / design(v) - 1.0 for v in (100.0, 200.0, 300.0)]
    print(f"heavy-rain, design curve as a lower bound: mu0 {mu0:.4f}, v_ref {v_ref:.1f} km/h, leading_factor "
          f"{f0:.4f}, recovery_axles {n_rec:.2f}; residuals (car1, car4, slope at 100..250 km/h) "
          f"{np.round(fit.fun[:6], 4)}; 8-car mean / design - 1 at 100/200/300 km/h {np.round(means, 3)}")
    for held in (0.3, 0.4, 0.45, 0.55, 0.7):
        prof = least_squares(lambda x: heavy_rain_lower_envelope_residual(x, held), [135.0, 0.12, 10.0],
                             bounds=(lo[1:], hi[1:]))
        print(f"  mu0 held at {held}: v_ref {prof.x[0]:.1f} km/h, leading_factor {prof.x[1]:.4f}, "
              f"recovery_axles {prof.x[2]:.2f}, cost {prof.cost:.2e}")


def hs_wet_check():
    """The data set not fitted: the Shinkansen heavy-rain measurement at 300 km/h, front car about
    0.02 to car 4 about 0.05 (validation case hs-wet-300-scatter)."""
    p = calibrate_hs_wet()
    at_300 = peak(p, 300.0)
    print(f"hs-wet check: peak at 300 km/h {at_300:.4f}, inside the heavy-rain band [0.02, 0.05]:",
          0.02 <= at_300 <= 0.05)


CK_SPEEDS = np.array([20.0, 50.0, 80.0, 120.0, 160.0, 200.0, 250.0, 300.0, 350.0])


def curtius_kniffler(v_kmh):
    """The Curtius-Kniffler dry-rail curve (Elektrische Bahnen 20 (1950) 201-210), v in km/h."""
    return 7.5 / (v_kmh + 44.0) + 0.161


def calibrate_dry_medium():
    """mu0, A, B (kA, kS from Polach's dry set) so that the peak follows Curtius-Kniffler from 20 to
    350 km/h, with a falling tail (F/Q at 30 % creep <= 0.8 peak); every parameter ends inside
    its bounds."""
    bounds = ([0.05, 0.0, 0.0], [1.5, 1.0, 20.0])

    def residual(x):
        p = PolachParams(x[0], x[1], x[2], 1.0, 0.4)
        r = [peak(p, v) / curtius_kniffler(v) - 1.0 for v in CK_SPEEDS]
        return r + [3.0 * max(0.0, tail_ratio(p, v) - 0.8) for v in (60.0, 300.0)]

    fit = least_squares(residual, [0.358, 0.4, 0.6], bounds=bounds)
    print("dry-medium residuals (peak / Curtius-Kniffler - 1 at 20..350 km/h, tails):", np.round(fit.fun, 3))
    inside = np.all((fit.x > np.array(bounds[0]) + 1e-6) & (fit.x < np.array(bounds[1]) - 1e-6))
    print("dry-medium parameters inside their bounds:", bool(inside))
    return PolachParams(fit.x[0], fit.x[1], fit.x[2], 1.0, 0.4)


def fit_mu0(shape: PolachParams, speeds_kmh, targets) -> float:
    """mu0 (least squares on peak / target - 1) with the other four parameters of `shape`."""
    def residual(x):
        p = PolachParams(x[0], shape.A, shape.B, shape.kA, shape.kS)
        return [peak(p, v) / t - 1.0 for v, t in zip(speeds_kmh, targets)]
    return float(least_squares(residual, [shape.mu0], bounds=([1e-3], [2.0])).x[0])


# HAROLD full-scale rig, wetted leaf layer, 40 and 70 mph: 0.01-0.02 (centre 0.015), the data set
# validation/validation/leaves-full-scale-rig
LEAVES_RIG_KMH = (64.37, 112.65)
LEAVES_RIG_CENTRE = 0.015


def main():
    print("dry-medium:", calibrate_dry_medium())
    wet_shape = WET_SET
    print("oil-film mu0 (0.06 at 100 km/h):", scale_mu0(wet_shape, 100.0, 0.06))
    print("leaves mu0 (0.03 at 100 km/h, centre of the leaf-layer range 0.01-0.05):",
          scale_mu0(wet_shape, 100.0, 0.03))
    print("leaves-full-scale mu0 (0.015 at 64 and 113 km/h, HAROLD rig):",
          fit_mu0(wet_shape, LEAVES_RIG_KMH, [LEAVES_RIG_CENTRE] * 2))
    base, (f0, n_rec) = calibrate_heavy_rain()
    print("heavy-rain base:", base, "leading_factor:", f0, "recovery_axles:", n_rec)
    hs_wet_check()
    hs_wet_shape_free()
    # the evidence behind heavy-rain's fit.at_bound.leading_factor: relaxed, it goes towards 0
    _, (f0, n_rec) = calibrate_heavy_rain(leading_factor_low=1e-3)
    print("heavy-rain with the leading factor's bound relaxed to 0.001:", f0, n_rec)
    # the rolling-speed factor tried on heavy rain (heavy-rain.yaml fit.at_bound.leading_factor): it
    # lifts the train mean at 100 km/h, but the conflict lies at one speed, 300 km/h, where a factor of
    # speed alone cannot separate the front car from car 4 and the mean; the leading factor stays at
    # its bound, relaxed it still falls far below it
    base, (f0, n_rec) = calibrate_heavy_rain(rolling_factor=True)
    print("heavy-rain with the rolling-speed factor:", base, "leading_factor:", f0, "recovery_axles:", n_rec)
    _, (f0, n_rec) = calibrate_heavy_rain(leading_factor_low=1e-3, rolling_factor=True)
    print("heavy-rain with the rolling-speed factor, leading factor's bound relaxed to 0.001:", f0, n_rec)
    # the design curve read as the lower bound it is: the conflict goes, the fit is then undetermined
    heavy_rain_lower_envelope()


if __name__ == "__main__":
    main()
