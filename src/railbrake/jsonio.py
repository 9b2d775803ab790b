"""JSON output that is JSON: NaN and infinities become null (json.dumps writes them as `NaN`,
which no JSON parser accepts). Used by the CLI's --json and by kpis.json."""

from __future__ import annotations

import json
import math

import numpy as np


def finite(value):
    """value with every non-finite float (also inside numpy arrays, lists, dicts) replaced by None."""
    if isinstance(value, dict):
        return {k: finite(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [finite(v) for v in value]
    if isinstance(value, np.ndarray):
        return finite(value.tolist())
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


def dumps(data, **kwargs) -> str:
    return json.dumps(finite(data), allow_nan=False, **kwargs)
