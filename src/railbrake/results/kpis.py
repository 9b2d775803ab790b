"""What each KPI means, its unit, and the warnings a run's KPIs call for. KPIs not listed here
(added by newer cores) are shown with their name only; a KPI may be None (not reached)."""

from __future__ import annotations

# key: (unit, definition). Definitions as computed in core/src/run.c (rb_run.h).
KPI_INFO = {
    "stopping_distance_m": ("m", "distance from the first brake demand to the stop"),
    "stopping_time_s": ("s", "time from the first brake demand to the stop"),
    "mean_deceleration": ("m/s²", "speed lost / time since the first brake demand"),
    "max_slip": ("1", "largest |slip| of any axle while the train runs above 10 km/h"),
    "wheel_lock_events": ("", "episodes of an axle below 10 % of the train speed, above 10 km/h"),
    "max_lock_duration_s": ("s", "longest such lock episode"),
    "air_consumed_kg": ("kg", "air vented to the atmosphere (cylinders, WSP vents)"),
    "adhesion_utilisation": ("1", "mean rail deceleration / (g x mean available peak adhesion); "
                                  "EN 15595 judges a WSP on it"),
    "safety_timer_trips": ("", "times the WSP safety timer ended continuous venting"),
    "air_balance_error": ("1", "|air in volumes + vented - compressed - initial| / initial (model check)"),
    "stopped": ("", "the train stopped before the scenario's max_time"),
    "min_main_reservoir_bar": ("bar g", "lowest main reservoir pressure"),
    "min_supply_bar": ("bar g", "lowest supply reservoir pressure of any car"),
    "min_supply_margin_bar": ("bar", "lowest supply reservoir pressure less its car's cylinder demand, "
                                     "while braking (below 0: the supply cannot give the demand)"),
    "max_air_shortfall_bar": ("bar", "largest amount by which a braking car's cylinder demand exceeded its supply "
                                     "reservoir, the most its cylinders can reach: a cylinder short of its demand "
                                     "for want of air (0: never)"),
    "braked_distance_m": ("m", "distance from the first brake demand to the end of the run (HIL; also "
                               "when it ended before the stop)"),
    "air_drawn_kg": ("kg", "air taken from the main reservoir and its pipe (cylinder fills, venting, "
                           "leaks), the compressors' delivery included"),
    "air_vented_kg": ("kg", "air vented to the atmosphere"),
    "cylinder_shortfall_s": ("s", "longest time a cylinder stayed more than 0.2 bar below its demand "
                                  "with its WSP valves at rest, while braking"),
    "worst_axle": ("", "axle with the most lock events or, without locks, the largest slip above 2 % "
                       "(none: no axle slid)"),
    "brake_energy_mj": ("MJ", "energy dissipated by the friction brakes"),
    "max_disc_temperature_c": ("°C", "highest mean brake disc temperature of any axle"),
    "max_disc_surface_temperature_c": ("°C", "highest friction surface temperature of any brake disc (the "
                                             "mean disc temperature for discs without a surface layer)"),
    "mean_pad_friction": ("1", "stop-averaged pad friction: the pads' instantaneous friction averaged over "
                               "their sliding distance while they press, all braked axles (UIC 541-3's "
                               "mean friction of a dynamometer stop); none if no pad pressed"),
    "valve_switchings": ("", "changes of state of the WSP hold and vent valves of the whole train while "
                             "braking (the valves' actual states)"),
    "max_sliding_energy_kj": ("kJ", "largest over the axles of the sliding energy, the time integral of creep "
                                    "force x slip velocity while braking: the wheel-flat risk"),
    "sliding_energy_kj": ("kJ", "the sliding energy summed over the axles"),
    "adhesion_outside_validity": ("", "the run was forced (adhesion.allow_outside_validity) with an adhesion "
                                      "condition outside its validity: which, and where it holds"),
}

AIR_BALANCE_LIMIT = 1e-6   # a larger relative error means the air model lost mass (model check)
SHORTFALL_WARNING_S = 2.0  # s: without a healthy reference, a cylinder short of its demand for longer [T]
SHORTFALL_FACTOR = 1.25    # a cylinder short of its demand a quarter longer than the healthy brake's
                           # own build-up keeps it (simulation.response.healthy_shortfall) did not get the air [T]


def unit(key: str) -> str:
    return KPI_INFO.get(key, ("", ""))[0]


def definition(key: str) -> str:
    return KPI_INFO.get(key, ("", ""))[1]


def text(value) -> str:
    """A KPI value as shown in tables and the report."""
    if value is None:
        return "n/a"
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, float):
        return f"{value:.6g}"
    return str(value)


def shortfall_limit(healthy_shortfall_s: float | None) -> float:
    """s: the cylinder_shortfall_s above which a run warns: SHORTFALL_FACTOR times a healthy brake's
    of the same train (simulation.response.healthy_shortfall), else SHORTFALL_WARNING_S."""
    return SHORTFALL_WARNING_S if healthy_shortfall_s is None else SHORTFALL_FACTOR * healthy_shortfall_s


def warnings(kpis: dict, healthy_shortfall_s: float | None = None, min_working_bar: float | None = None) -> list[str]:
    """Plain-words warnings about a run's KPIs; healthy_shortfall_s: the cylinder_shortfall_s of a
    healthy brake of the run's train (its own build-up), the cylinders' shortfall is judged on;
    min_working_bar: the train file's minimum working pressure of the main reservoir (bar gauge)."""
    out = []
    if kpis.get("stopped") is False:
        out.append("the train did not stop within the scenario's max_time: distance and time are to the end of the run")
    if kpis.get("stopping_distance_m", 0) is None:
        out.append("no stopping distance: the run never braked to a stop")
    if (kpis.get("wheel_lock_events") or 0) > 0:
        out.append(f"{kpis['wheel_lock_events']} wheel lock episodes (longest "
                   f"{text(kpis.get('max_lock_duration_s'))} s): wheel flats likely")
    if (kpis.get("safety_timer_trips") or 0) > 0:
        n = kpis["safety_timer_trips"]
        out.append(f"the WSP safety timer tripped {n} time{'s' if n != 1 else ''} (continuous venting cut off)")
    if (kpis.get("cylinder_shortfall_s") or 0.0) > shortfall_limit(healthy_shortfall_s):
        healthy = "" if healthy_shortfall_s is None else f", a healthy brake of the train {healthy_shortfall_s:.1f} s"
        out.append(f"a brake cylinder stayed more than 0.2 bar below its demand for {kpis['cylinder_shortfall_s']:.1f} s "
                   f"(WSP valves at rest{healthy}): the air did not reach it in time")
    reservoir = kpis.get("min_main_reservoir_bar")
    if min_working_bar is not None and reservoir is not None and reservoir < min_working_bar:
        out.append(f"the main reservoir fell to {reservoir:.2f} bar g, below the train's minimum working pressure "
                   f"{min_working_bar:g} bar g (air_supply.min_working_bar): the brake used more air than the "
                   "compressors and reservoirs give")
    margin = kpis.get("min_supply_margin_bar")
    if margin is not None and margin < 0.0:
        out.append(f"a supply reservoir fell {-margin:.2f} bar below its car's cylinder demand (lowest supply "
                   f"{kpis['min_supply_bar']:.2f} bar g): the brake could not get its pressure")
    if kpis.get("adhesion_outside_validity"):
        out.append(f"forced outside the adhesion condition's validity: {kpis['adhesion_outside_validity']}")
    error = kpis.get("air_balance_error")
    if error is not None and error > AIR_BALANCE_LIMIT:
        out.append(f"air balance error {error:.2g} above {AIR_BALANCE_LIMIT:g}: the air model lost mass")
    for key, value in kpis.items():
        if isinstance(value, float) and value != value:
            out.append(f"{key} is not a number")
    return out
