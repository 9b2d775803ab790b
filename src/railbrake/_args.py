"""Argument checks at the boundary of the public Python API: a bad argument raises TypeError (not
a number, not an array of numbers) or ValueError (railbrake.errors.InputError: not finite, out of
range) naming the argument as the caller wrote it, before any C call. No law lives here."""

from __future__ import annotations

import math
import numbers
import os

import numpy as np

from railbrake.errors import InputError


NAME_MAX, PATH_MAX = 255, 4096   # bytes of one path component and of a whole path (POSIX, Linux)


def show(value) -> str:
    """value's repr, cut to 60 characters (a 10 kB argument is named, not echoed)."""
    text = repr(value)
    return text if len(text) <= 60 else f"{text[:50]}... ({len(text)} characters)"


def _bound_text(low, high, low_open, high_open) -> str:
    parts = []
    if low is not None:
        parts.append(f"{'>' if low_open else '>='} {low:g}")
    if high is not None:
        parts.append(f"{'<' if high_open else '<='} {high:g}")
    return " and ".join(parts)


def real(name: str, value, low: float | None = None, high: float | None = None, *, low_open: bool = False,
         high_open: bool = False, allow_inf: bool = False) -> float:
    """value as a float: a real number (not a Boolean, string or None), finite (unless allow_inf:
    then +inf passes the bounds check as a limit) and inside the bounds."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real):
        raise TypeError(f"{name} = {show(value)}: must be a number, not {type(value).__name__}")
    try:
        x = float(value)
    except OverflowError:
        raise InputError(f"{name} = {show(value)}: too large for a float") from None
    if math.isnan(x) or (math.isinf(x) and not (allow_inf and x > 0)):
        raise InputError(f"{name} = {x}: must be a finite number")
    if math.isinf(x):   # allowed: +inf stands for a limit (a flat body), beyond any upper bound
        return x
    if (low is not None and (x < low or (low_open and x == low))) or \
            (high is not None and (x > high or (high_open and x == high))):
        raise InputError(f"{name} = {x:g}: must be {_bound_text(low, high, low_open, high_open)}")
    return x


def reals(name: str, values, low: float | None = None, high: float | None = None, *,
          low_open: bool = False) -> np.ndarray:
    """values (a number or an array-like of numbers) as a float array, every element finite and
    inside the bounds; the message names the first bad element name[i]."""
    return _reals(name, values, low, high, low_open)


def _reals(name, values, low, high, low_open) -> np.ndarray:
    if isinstance(values, (str, bytes, bool, np.bool_)) or values is None:
        raise TypeError(f"{name} = {show(values)}: must be a number or an array of numbers")
    try:
        array = np.asarray(values)
    except (ValueError, TypeError):   # ragged nesting
        raise TypeError(f"{name}: must be a number or a rectangular array of numbers") from None
    if array.dtype.kind not in "iuf":
        raise TypeError(f"{name} = {show(values)}: must be a number or an array of numbers, not {array.dtype}")
    array = array.astype(float)
    bad = ~np.isfinite(array)
    if low is not None:
        bad |= array <= low if low_open else array < low
    if high is not None:
        bad |= array > high
    if bad.any():
        where = np.unravel_index(int(np.argmax(bad)), array.shape) if array.ndim else ()
        label = f"{name}[{', '.join(map(str, where))}]" if where else name
        x = float(array[where]) if where else float(array)
        limits = _bound_text(low, high, low_open, False)
        raise InputError(f"{label} = {x:g}: must be finite{' and ' + limits if limits else ''}")
    return array


def whole(name: str, value, low: int | None = None, high: int | None = None) -> int:
    """value as an int: a whole number (not a Boolean, not a float), inside [low, high]."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Integral):
        raise TypeError(f"{name} = {show(value)}: must be a whole number, not {type(value).__name__}")
    n = int(value)
    if (low is not None and n < low) or (high is not None and n > high):
        raise InputError(f"{name} = {n}: must be {_bound_text(low, high, False, False)}")
    return n


def flag(name: str, value) -> bool:
    if not isinstance(value, (bool, np.bool_)):
        raise TypeError(f"{name} = {show(value)}: must be True or False")
    return bool(value)


def name_or_path(name: str, value) -> str:
    """A preset name or a file path (str or os.PathLike) as text."""
    if isinstance(value, os.PathLike):
        value = os.fspath(value)
    if not isinstance(value, str):
        raise TypeError(f"{name} = {show(value)}: must be a name or a file path, not {type(value).__name__}")
    if "\0" in value:
        raise InputError(f"{name} = {show(value)}: a name or path holds no NUL character")
    if len(value.encode()) > PATH_MAX or any(len(part.encode()) > NAME_MAX for part in value.split("/")):
        raise InputError(f"{name} = {show(value)}: too long for a name or path (at most {NAME_MAX} bytes per "
                         f"name, {PATH_MAX} in all)")
    return value


def choice(name: str, value, options) -> str:
    if not isinstance(value, str) or value not in options:
        raise InputError(f"{name} = {show(value)}: must be one of {', '.join(map(str, options))}")
    return value


def function(name: str, value):
    """A callable or None."""
    if value is not None and not callable(value):
        raise TypeError(f"{name} = {show(value)}: must be a function or None")
    return value


def text(name: str, value) -> str:
    if not isinstance(value, str):
        raise TypeError(f"{name} = {show(value)}: must be a string")
    return value


def instance(name: str, value, kind):
    if not isinstance(value, kind):
        raise TypeError(f"{name}: must be a {kind.__name__}, not {type(value).__name__}")
    return value


def path(name: str, value) -> "Path":
    """A file or folder path (str or os.PathLike, not empty, no NUL, each part at most NAME_MAX
    bytes and the whole at most PATH_MAX: refused here, naming the argument, rather than by the
    operating system as "File name too long")."""
    from pathlib import Path
    text = name_or_path(name, value)
    if not text.strip():
        raise InputError(f"{name} = {show(value)}: must name a file or folder")
    parts = Path(text).parts
    longest = max((len(p.encode()) for p in parts), default=0)
    if longest > NAME_MAX or len(text.encode()) > PATH_MAX:
        raise InputError(f"{name} = {show(value)}: too long a path (at most {NAME_MAX} bytes per name, "
                         f"{PATH_MAX} in all)")
    return Path(text)


def items(name: str, value, kind, low: int = 1) -> list:
    """value as a list of at least `low` instances of kind (a list or tuple; the message names
    the first wrong one name[i])."""
    what = " or ".join(k.__name__ for k in kind) if isinstance(kind, tuple) else kind.__name__
    if not isinstance(value, (list, tuple)):
        raise TypeError(f"{name} = {show(value)}: must be a list of {what}, not {type(value).__name__}")
    if len(value) < low:
        raise InputError(f"{name}: must hold at least {low} {what}")
    for i, item in enumerate(value):
        if not isinstance(item, kind):
            raise TypeError(f"{name}[{i}] = {show(item)}: must be a {what}, not {type(item).__name__}")
    return list(value)


def mapping(name: str, value) -> dict:
    if not isinstance(value, dict):
        raise TypeError(f"{name} = {show(value)}: must be a dict, not {type(value).__name__}")
    return value
