"""Orifice mass flow (ISO 6358 form, choked and laminar limits), vectorised over the C law."""

from __future__ import annotations

import ctypes

import numpy as np

from railbrake import _core
from railbrake._args import real, reals
from railbrake.errors import InputError

AIR_R = 287.05  # J/(kg K), as RB_AIR_R
# Argument ranges of the API (outside them the flow overflows or is no gas flow): pressures up to
# 1 GPa, temperatures 1 to 5000 K, areas up to 10 m^2.
PRESSURE_MAX = 1e9     # Pa
TEMPERATURE_RANGE = (1.0, 5000.0)   # K
AREA_MAX = 10.0        # m^2
AIR_GAMMA = 1.4
AMBIENT_PRESSURE = 101325.0  # Pa
CRITICAL_RATIO_NOZZLE = 0.528


def orifice_c(area=None, discharge_coefficient=1.0, critical_ratio=CRITICAL_RATIO_NOZZLE,
              sonic_conductance=None) -> _core.Orifice:
    """The C description of an orifice: by area and Cd, or by ISO 6358 C (m^3/(s Pa)) and b."""
    b = real("critical_ratio", critical_ratio, 0.0, 1.0, high_open=True)
    if sonic_conductance is not None:
        return _core.Orifice(0.0, 1.0, real("sonic_conductance", sonic_conductance, 0.0, 1.0), b)
    if area is None:
        raise InputError("orifice: give area (m^2) or sonic_conductance (m^3/(s Pa))")
    return _core.Orifice(real("area", area, 0.0, AREA_MAX), real("discharge_coefficient", discharge_coefficient, 0.0, 1.0,
                                                          low_open=True), 0.0, b)


def orifice_mass_flow(p_up, T_up, p_down, area=None, discharge_coefficient=1.0,
                      critical_ratio=CRITICAL_RATIO_NOZZLE, T_down=None, sonic_conductance=None):
    """Mass flow (kg/s) from 'up' to 'down' (negative when it runs backwards).

    Pressures in Pa (> 0), temperatures in K; the upstream side's temperature is used, so
    T_down (default T_up) matters only for reverse flow. Give either area (m^2) with
    discharge_coefficient, or the ISO 6358 sonic_conductance C (m^3/(s Pa)) with critical_ratio b.
    """
    orifice = orifice_c(area, discharge_coefficient, critical_ratio, sonic_conductance)
    T_down = T_up if T_down is None else T_down
    checked = [reals("p_up", p_up, 0.0, PRESSURE_MAX, low_open=True), reals("T_up", T_up, *TEMPERATURE_RANGE),
               reals("p_down", p_down, 0.0, PRESSURE_MAX, low_open=True),
               reals("T_down", T_down, *TEMPERATURE_RANGE)]
    try:
        p1, t1, p2, t2 = np.broadcast_arrays(*checked)
    except ValueError:
        raise InputError("p_up, T_up, p_down, T_down: shapes "
                         f"{', '.join(str(np.shape(c)) for c in checked)} do not broadcast") from None
    out = np.empty(p1.shape)
    value = ctypes.c_double()
    for index in np.ndindex(p1.shape):
        _core.call(_core.rb_orifice_mass_flow, p1[index], t1[index], p2[index], t2[index],
                   ctypes.byref(orifice), ctypes.byref(value))
        out[index] = value.value
    return out if out.ndim else float(out)


def sonic_conductance(area, discharge_coefficient=1.0) -> float:
    """ISO 6358 sonic conductance (m^3/(s Pa)) equivalent to an orifice of area A and Cd."""
    return _core.rb_sonic_conductance(real("area", area, 0.0, AREA_MAX),
                                      real("discharge_coefficient", discharge_coefficient, 0.0, 1.0, low_open=True))
