"""Orifice mass flow (ISO 6358 form, choked and laminar limits), vectorised over the C law."""

from __future__ import annotations

import ctypes

import numpy as np

from railbrake import _core
from railbrake.errors import InputError

AIR_R = 287.05  # J/(kg K), as RB_AIR_R
AIR_GAMMA = 1.4
AMBIENT_PRESSURE = 101325.0  # Pa
CRITICAL_RATIO_NOZZLE = 0.528


def orifice_c(area=None, discharge_coefficient=1.0, critical_ratio=CRITICAL_RATIO_NOZZLE,
              sonic_conductance=None) -> _core.Orifice:
    """The C description of an orifice: by area and Cd, or by ISO 6358 C (m^3/(s Pa)) and b."""
    if sonic_conductance is not None:
        return _core.Orifice(0.0, 1.0, float(sonic_conductance), float(critical_ratio))
    if area is None:
        raise InputError("orifice: give area (m^2) or sonic_conductance (m^3/(s Pa))")
    return _core.Orifice(float(area), float(discharge_coefficient), 0.0, float(critical_ratio))


def orifice_mass_flow(p_up, T_up, p_down, area=None, discharge_coefficient=1.0,
                      critical_ratio=CRITICAL_RATIO_NOZZLE, T_down=None, sonic_conductance=None):
    """Mass flow (kg/s) from 'up' to 'down' (negative when it runs backwards).

    Pressures in Pa (> 0), temperatures in K; the upstream side's temperature is used, so
    T_down (default T_up) matters only for reverse flow. Give either area (m^2) with
    discharge_coefficient, or the ISO 6358 sonic_conductance C (m^3/(s Pa)) with critical_ratio b.
    """
    orifice = orifice_c(area, discharge_coefficient, critical_ratio, sonic_conductance)
    T_down = T_up if T_down is None else T_down
    p1, t1, p2, t2 = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in (p_up, T_up, p_down, T_down)))
    out = np.empty(p1.shape)
    value = ctypes.c_double()
    for index in np.ndindex(p1.shape):
        _core.call(_core.rb_orifice_mass_flow, p1[index], t1[index], p2[index], t2[index],
                   ctypes.byref(orifice), ctypes.byref(value))
        out[index] = value.value
    return out if out.ndim else float(out)


def sonic_conductance(area, discharge_coefficient=1.0) -> float:
    """ISO 6358 sonic conductance (m^3/(s Pa)) equivalent to an orifice of area A and Cd."""
    return _core.rb_sonic_conductance(float(area), float(discharge_coefficient))
