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

# ---------------------------------------------------------------- pneumatics (rb_pneumatics.h, rb_ode.h, rb_network.h)

_c_int_p = POINTER(c_int)
SCHEDULE_MAX = 16
FORCE_TABLE_MAX = 16
MEMBRANE_MAX_POINTS = 32
BODY_FACES = 4


class Orifice(Structure):
    _fields_ = [(n, c_double) for n in ("area", "discharge_coefficient", "sonic_conductance",
                                        "critical_ratio")]


class Membrane(Structure):
    _fields_ = [("n", c_int), ("x", c_double * MEMBRANE_MAX_POINTS),
                ("volume", c_double * MEMBRANE_MAX_POINTS), ("slope", c_double * MEMBRANE_MAX_POINTS)]


class OdeOptions(Structure):
    _fields_ = [("rtol", c_double), ("atol", c_double), ("atol_scale", c_double_p), ("h_initial", c_double), ("h_max", c_double),
                ("max_steps", ctypes.c_long)]


class OdeStats(Structure):
    _fields_ = [("steps", ctypes.c_long), ("rejected", ctypes.c_long), ("rhs_calls", ctypes.c_long)]


class Schedule(Structure):
    _fields_ = [("n", c_int), ("delay", c_double), ("t", c_double * SCHEDULE_MAX),
                ("value", c_double * SCHEDULE_MAX)]


class ForceTable(Structure):
    _fields_ = [("n_gap", c_int), ("n_current", c_int), ("gap", c_double * FORCE_TABLE_MAX),
                ("current", c_double * FORCE_TABLE_MAX),
                ("force", c_double * (FORCE_TABLE_MAX * FORCE_TABLE_MAX))]


class NetNode(Structure):
    _fields_ = [("kind", c_int)] + [(n, c_double) for n in (
        "pressure", "temperature", "volume", "volume_rate", "heat_conductance", "wall_temperature")]


class NetLink(Structure):
    _fields_ = [("kind", c_int), ("from_", c_int), ("to", c_int), ("orifice", Orifice), ("body", c_int),
                ("diameter", c_double), ("offset", c_double), ("direction", c_double),
                ("shape", c_double), ("opening", Schedule)]


class NetBody(Structure):
    _fields_ = [(n, c_double) for n in (
        "mass", "spring_rate", "spring_preload", "damping", "friction", "friction_velocity", "x_min",
        "x_max", "stop_stiffness", "stop_damping", "x_initial", "force", "ambient_pressure")] + [
        ("n_faces", c_int), ("face_node", c_int * BODY_FACES), ("face_membrane", c_int * BODY_FACES),
        ("face_area", c_double * BODY_FACES), ("face_direction", c_double * BODY_FACES),
        ("force_table", c_int), ("airgap_initial", c_double), ("current", Schedule)]


class Network(Structure):
    _fields_ = [("nodes", POINTER(NetNode)), ("n_nodes", c_size_t),
                ("links", POINTER(NetLink)), ("n_links", c_size_t),
                ("bodies", POINTER(NetBody)), ("n_bodies", c_size_t),
                ("tables", POINTER(ForceTable)), ("n_tables", c_size_t),
                ("membranes", POINTER(Membrane)), ("n_membranes", c_size_t)]


rb_orifice_mass_flow = _declare("rb_orifice_mass_flow", c_int, c_double, c_double, c_double, c_double,
                                POINTER(Orifice), c_double_p, _err_p)
rb_orifice_mass_flow_fast = _declare("rb_orifice_mass_flow_fast", c_double, *[c_double] * 7)
rb_sonic_conductance = _declare("rb_sonic_conductance", c_double, c_double, c_double)
rb_membrane_init = _declare("rb_membrane_init", c_int, POINTER(Membrane), c_double_p, c_double_p, c_int,
                            _err_p)
rb_membrane_eval = _declare("rb_membrane_eval", None, POINTER(Membrane), c_double, c_double_p, c_double_p)
rb_force_table_check = _declare("rb_force_table_check", c_int, POINTER(ForceTable), _err_p)
rb_force_table_eval = _declare("rb_force_table_eval", c_double, POINTER(ForceTable), c_double, c_double)
rb_network_workspace_size = _declare("rb_network_workspace_size", c_size_t, POINTER(Network), c_size_t,
                                     POINTER(c_size_t))
rb_network_simulate = _declare("rb_network_simulate", c_int, POINTER(Network), c_double_p, c_size_t,
                               POINTER(OdeOptions), c_double_p, c_size_t, _c_int_p, c_double_p,
                               c_double_p, c_double_p, c_double_p, c_double_p, c_double_p,
                               POINTER(OdeStats), _err_p)
