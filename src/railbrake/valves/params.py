"""Loading valve parameters: packaged YAML defaults, deep-merged with user overrides."""

from __future__ import annotations

from importlib import resources
from pathlib import Path

import yaml

from railbrake import config
from railbrake.errors import InputError

BAR = 1e5   # Pa per bar

DATA = resources.files("railbrake") / "data" / "valves"


def _merge(base: dict, override: dict, where: str) -> dict:
    merged = dict(base)
    for key, value in override.items():
        if key not in base:
            raise InputError(f"{where}: unknown parameter {key!r}; known: {sorted(base)}")
        merged[key] = _merge(base[key], value, f"{where}.{key}") if isinstance(base[key], dict) else value
    return merged


def load(default_name: str, override=None) -> dict:
    """The default parameters `default_name`.yaml, updated by a dict or a YAML file path."""
    params = yaml.safe_load((DATA / f"{default_name}.yaml").read_text())
    if override is None:
        return params
    origin, lines = "parameters", {}
    if isinstance(override, (str, Path)):
        origin = str(override)
        text = config.read_text(override)
        override = config.load_mapping(text, origin) if text.strip() else {}
        lines = config.line_index(text) if text.strip() else {}
    merged = _merge(params, override, default_name)
    _check_pressures(merged, override, config.locator(origin, lines))
    return merged


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
