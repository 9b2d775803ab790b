"""Loading valve parameters: packaged YAML defaults, deep-merged with user overrides."""

from __future__ import annotations

import math
from importlib import resources
from pathlib import Path

import yaml

from railbrake import _args, config
from railbrake.errors import InputError

BAR = 1e5   # Pa per bar
MM, MM2, CM3, L, NH, DEG_C = 1e-3, 1e-6, 1e-6, 1e-3, 1e-9, 273.15   # SI per file unit; degC offset

# The plausibility range of every number of the valve design files, by key name (a list: each
# item): (C bound of core/src/bounds.c, SI per file unit, offset, unit as written, integer).
# supply_bar and control_step_bar: _check_pressures.
_RANGES = {
    "ambient_pa": ("train.atmosphere", 1.0, 0.0, "Pa"),
    "discharge_coefficient": ("train.discharge_coefficient", 1.0, 0.0, ""),
    "current_max_a": ("valve.current", 1.0, 0.0, "A"), "rated_current_a": ("valve.current", 1.0, 0.0, "A"),
    "mass": ("valve.moving_mass", 1.0, 0.0, "kg"), "piston_mass": ("valve.moving_mass", 1.0, 0.0, "kg"),
    "spring_rate": ("valve.spring_rate", 1.0, 0.0, "N/m"), "spring_preload": ("valve.spring_preload", 1.0, 0.0, "N"),
    "damping": ("valve.damping", 1.0, 0.0, "N s/m"), "friction": ("valve.friction", 1.0, 0.0, "N"),
    "friction_velocity": ("valve.friction_velocity", 1.0, 0.0, "m/s"),
    "airgap_mm": ("valve.gap", MM, 0.0, "mm"), "flapper_travel_mm": ("valve.travel", MM, 0.0, "mm"),
    "travel_mm": ("valve.travel", MM, 0.0, "mm"), "stroke_mm": ("train.cylinder_stroke", MM, 0.0, "mm"),
    "seat_lap_mm": ("valve.lap", MM, 0.0, "mm"),
    "x_mm": ("valve.membrane_position", MM, 0.0, "mm"), "volume_cm3": ("valve.membrane_volume", CM3, 0.0, "cm3"),
    **{key: ("valve.port_diameter", MM, 0.0, "mm") for key in (
        "nozzle_diameter_mm", "pilot_orifice_diameter_mm", "control_orifice_diameter_mm", "inlet_seat_diameter_mm",
        "exhaust_seat_diameter_mm", "hold_diameter_mm", "vent_diameter_mm")},
    "diameter_mm": ("valve.piston_diameter", MM, 0.0, "mm"), "pole_diameter_mm": ("valve.piston_diameter", MM, 0.0, "mm"),
    "pilot_volume_cm3": ("valve.volume", CM3, 0.0, "cm3"), "control_volume_l": ("valve.volume", L, 0.0, "l"),
    "output_volume_l": ("valve.volume", L, 0.0, "l"), "dead_volume_l": ("train.cylinder_dead_volume", L, 0.0, "l"),
    "count": ("valve.cylinder_count", 1.0, 0.0, "", True),
    "response_delay_s": ("car.valve_delay", 1.0, 0.0, "s"),
    "turns": ("valve.turns", 1.0, 0.0, "", True), "resistance_20c_ohm": ("valve.coil_resistance", 1.0, 0.0, "ohm"),
    "resistance_tempco_per_k": ("valve.resistance_tempco", 1.0, 0.0, "1/K"),
    "iron_path_length_mm": ("valve.iron_length", MM, 0.0, "mm"), "iron_area_mm2": ("valve.iron_area", MM2, 0.0, "mm2"),
    "working_gaps": ("valve.working_gaps", 1.0, 0.0, "", True), "fringing": ("valve.fringing", 1.0, 0.0, ""),
    "parasitic_gap_mm": ("valve.parasitic_gap", MM, 0.0, "mm"), "parasitic_area_mm2": ("valve.iron_area", MM2, 0.0, "mm2"),
    "leakage_permeance_nh": ("valve.leakage_permeance", NH, 0.0, "nH"),
    "h_a_per_m": ("valve.magnetic_field", 1.0, 0.0, "A/m"), "b_t": ("valve.flux_density", 1.0, 0.0, "T"),
    "current_a": ("valve.table_current", 1.0, 0.0, "A"),
    "supply_voltage_v": ("valve.drive_voltage", 1.0, 0.0, "V"), "pwm_frequency_hz": ("valve.pwm_frequency", 1.0, 0.0, "Hz"),
    "temperature_c": ("valve.coil_temperature", 1.0, DEG_C, "degC"),
    "step_time_s": ("valve.study_time", 1.0, 0.0, "s"), "transient_time_s": ("valve.study_time", 1.0, 0.0, "s"),
    "step_dt_s": ("valve.solver_step", 1.0, 0.0, "s"),
    "heat_capacity_j_per_k": ("valve.heat_capacity", 1.0, 0.0, "J/K"),
    "conductance_w_per_k": ("valve.thermal_conductance", 1.0, 0.0, "W/K"),
    "hot_spot_allowance_k": ("valve.hot_spot", 1.0, 0.0, "K"),
}
# sections whose every entry is one quantity (the insulation classes' limits)
_SECTIONS = {"class_limits_c": ("valve.coil_temperature", 1.0, DEG_C, "degC")}
_TEXT = {"source", "solenoid_table", "insulation_class"}
# lists that are the axis or the monotone values of a curve
_INCREASING = {"x_mm": "the membrane's positions", "volume_cm3": "a membrane's volume grows with its stroke "
               "(effective area dV/dx > 0)", "h_a_per_m": "a B-H curve", "b_t": "a B-H curve",
               "airgap_mm": "a table axis", "current_a": "a table axis"}

DATA = resources.files("railbrake") / "data" / "valves"


def _merge(base: dict, override: dict, locate, path=()) -> dict:
    merged = dict(base)
    for key, value in override.items():
        dotted = ".".join(map(str, path + (key,)))
        if key not in base:
            raise InputError(f"{locate(path + (key,))}: unknown parameter {dotted!r}; known here: {sorted(base)}")
        if isinstance(base[key], dict):
            if not isinstance(value, dict):
                raise InputError(f"{locate(path + (key,))}: {dotted} = {value!r}: must be a section with the "
                                 f"keys {sorted(base[key])}")
            merged[key] = _merge(base[key], value, locate, path + (key,))
            continue
        if value is None:
            raise InputError(f"{locate(path + (key,))}: {dotted} = null: give a value (the default is "
                             f"{base[key]!r}) or leave the key out")
        shape = "a list" if isinstance(base[key], list) else "a single value"
        if isinstance(value, dict) or isinstance(value, list) != isinstance(base[key], list):
            raise InputError(f"{locate(path + (key,))}: {dotted} = {value!r}: must be {shape}, as in the "
                             f"default ({base[key]!r})")
        merged[key] = value
    return merged


def _check_ranges(override: dict, locate, path=(), spec=None) -> None:
    """Each number the override sets inside its plausibility range, in the file's unit."""
    for key, value in override.items():
        here = path + (key,)
        if isinstance(value, dict):
            _check_ranges(value, locate, here, _SECTIONS.get(key))
            continue
        rule = spec or _RANGES.get(key)
        if rule is None:
            if key not in _TEXT and key not in ("supply_bar", "control_step_bar"):
                raise InputError(f"{locate(here)}: {'.'.join(map(str, here))}: no range known for this key "
                                 "(railbrake.valves.params._RANGES)")
            continue
        items = list(enumerate(value)) if isinstance(value, list) else [(None, value)]
        if not items:
            raise InputError(f"{locate(here)}: {'.'.join(map(str, here))} = []: needs at least one value")
        for i, item in items:
            _check_number(item, rule, locate(here if i is None else here + (i,)),
                          ".".join(map(str, here)) + ("" if i is None else f"[{i}]"))
        if key in _INCREASING and isinstance(value, list):
            for i in range(1, len(value)):
                if not value[i] > value[i - 1]:
                    raise InputError(f"{locate(here + (i,))}: {'.'.join(map(str, here))}[{i}] = {value[i]!r} after "
                                     f"{value[i - 1]!r}: must be strictly increasing ({_INCREASING[key]})")


def _check_number(value, rule, where: str, name: str) -> None:
    bound, per, offset, unit, *integer = rule
    allowed = config.range_text(bound, unit, per, offset)
    interval = allowed.replace("must lie in ", "", 1)
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise InputError(f"{where}: {name} = {value!r}: must be a number in {interval}")
    if integer and math.isfinite(value) and value != int(value):
        raise InputError(f"{where}: {name} = {value!r}: must be a whole number in {interval}")
    if not config.within(bound, value * per + offset):
        raise InputError(f"{where}: {name} = {value!r}: {allowed}")


def load(default_name: str, override=None, argument: str = "override") -> dict:
    """The default parameters `default_name`.yaml, updated by a dict or a YAML file path (the
    caller's argument: named in errors)."""
    params = yaml.safe_load((DATA / f"{default_name}.yaml").read_text())
    if override is None:
        return params
    origin, lines = argument, {}
    if isinstance(override, (str, Path)):
        if not _args.path(argument, override).is_file():
            raise InputError(f"{override}: no such file ({argument}: the {default_name} valve's parameters)")
        origin = str(override)
        text = config.read_text(override)
        override = config.load_mapping(text, origin) if text.strip() else {}
        lines = config.line_index(text) if text.strip() else {}
    if not isinstance(override, dict):
        raise InputError(f"{argument} = {_args.show(origin if origin != argument else override)}: must be a mapping of {default_name} valve "
                         f"parameters or a YAML file of them")
    locate = config.locator(origin, lines)
    merged = _merge(params, override, locate)
    _check_ranges(override, locate)
    _check_table(override, locate)
    _check_pressures(merged, override, locate)
    return merged


def _check_table(override: dict, locate) -> None:
    """The EP valve's solenoid force table names a file (as given, or one of the packaged tables)."""
    name = override.get("solenoid_table")
    if name is None:
        return
    if not isinstance(name, str) or not (Path(name).is_file() or (DATA / name).is_file()):
        packaged = sorted(p.name for p in DATA.iterdir() if p.name.endswith(".csv"))
        raise InputError(f"{locate(('solenoid_table',))}: solenoid_table = {name!r}: no such force table file "
                         f"(a CSV path, or one of {packaged}; 'railbrake valve solenoid --table' writes one)")


def _check_pressures(params: dict, override: dict, locate) -> None:
    """The supply inside the model's validity (C bound valve.supply_gauge) and a control step the
    supply can give; only what the override changed can be wrong (the defaults are checked by tests)."""
    if "supply_bar" not in params:   # the solenoid: no pressures
        return
    if not isinstance(params["supply_bar"], (int, float)) or isinstance(params["supply_bar"], bool):
        raise InputError(f"{locate(('supply_bar',))}: supply_bar = {params.get('supply_bar')!r}: must be a number (bar gauge)")
    supply = params["supply_bar"]
    if not config.within("valve.supply_gauge", supply * BAR):
        raise InputError(f"{locate(('supply_bar',))}: supply_bar = {supply!r}: "
                         f"{config.range_text('valve.supply_gauge', 'bar gauge', BAR)}")
    step = params.get("control_step_bar")
    if step is None:
        return
    key = "control_step_bar" if "control_step_bar" in override else "supply_bar"
    if isinstance(step, bool) or not isinstance(step, (int, float)) or not 0.0 < step <= supply:
        raise InputError(f"{locate((key,))}: control_step_bar = {step!r}: must lie in (0, supply_bar = {supply:g}] "
                         "bar gauge: the relay valve cannot give more than its supply")
