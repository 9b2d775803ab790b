"""The one binding module between Python and the C core (ctypes over the shared library).

Each C function is declared once here with its argument types. Fallible functions take a
trailing ``rb_error *``; :func:`call` passes one and turns a non-zero status into
:class:`railbrake.errors.InputError` carrying the C core's message (which names the argument).
"""

from __future__ import annotations

import ctypes
import os
from ctypes import POINTER, Structure, c_char, c_double, c_int, c_size_t
from pathlib import Path

import numpy as np

from railbrake.errors import InputError

_LIB_DIR = Path(__file__).resolve().parent / "_lib"
_ERROR_MESSAGE_SIZE = 256

c_double_p = POINTER(c_double)


def _load_library() -> ctypes.CDLL:
    override = os.environ.get("RAILBRAKE_CORE_LIBRARY")
    candidates = [Path(override)] if override else sorted(_LIB_DIR.glob("*railbrake_core*"))
    for path in candidates:
        if path.is_file():
            return ctypes.CDLL(str(path))
    raise ImportError(
        f"railbrake C core not found in {_LIB_DIR}; install the package with 'pip install .' "
        "(or 'make demo'), which compiles it"
    )


lib = _load_library()


class RbError(Structure):
    _fields_ = [("code", c_int), ("message", c_char * _ERROR_MESSAGE_SIZE)]


def call(function, *args):
    """Call a fallible C function; raise InputError with its message on failure."""
    err = RbError()
    status = function(*args, ctypes.byref(err))
    if status != 0:
        raise InputError(err.message.decode("utf-8", "replace"))
    return status


def as_double_array(values) -> np.ndarray:
    """A C-contiguous float64 copy-or-view of values, ready to pass by pointer."""
    return np.ascontiguousarray(values, dtype=np.float64)


def ptr(array: np.ndarray):
    return array.ctypes.data_as(c_double_p)


def _declare(name, restype, *argtypes):
    function = getattr(lib, name)
    function.restype = restype
    function.argtypes = list(argtypes)
    return function


_err_p = POINTER(RbError)

rb_version = _declare("rb_version", ctypes.c_char_p)

# ---------------------------------------------------------------- contact (rb_contact.h)


class Hertz(Structure):
    _fields_ = [(n, c_double) for n in
                ("a", "b", "p0", "normal_force", "youngs_modulus", "poisson", "shear_modulus")]


class PolachParamsC(Structure):
    _fields_ = [(n, c_double) for n in ("mu0", "A", "B", "kA", "kS")]


class CreepContact(Structure):
    _fields_ = [(n, c_double) for n in ("a", "b", "c11", "shear_modulus")]


rb_elliptic_ke = _declare("rb_elliptic_ke", None, c_double, c_double_p, c_double_p, c_double_p)
rb_hertz_contact = _declare("rb_hertz_contact", c_int, c_double, c_double, c_double, c_double,
                            c_double, POINTER(Hertz), _err_p)
rb_kalker = _declare("rb_kalker", c_int, c_int, c_double, c_double, c_double_p, _err_p)
rb_polach_coefficient = _declare("rb_polach_coefficient", c_int, c_double_p, c_double_p, c_size_t,
                                 c_double, POINTER(CreepContact), POINTER(PolachParamsC),
                                 c_double_p, _err_p)
rb_polach_peak = _declare("rb_polach_peak", c_int, c_double, c_double, POINTER(CreepContact),
                          POINTER(PolachParamsC), c_double_p, c_double_p, _err_p)
rb_conditioning_factor = _declare("rb_conditioning_factor", c_double, c_double, c_double, c_double)
rb_polach_check = _declare("rb_polach_check", c_int, POINTER(PolachParamsC), _err_p)
