"""Wheel-rail contact: Hertz ellipse, Kalker coefficients and Polach's creep-force model.

The laws are implemented once, in the C core (``core/src/contact_*.c``); this module
validates, vectorises and documents them.

Sources (docs/references.md): Johnson, *Contact Mechanics* (1985) ch. 4 for Hertz;
Kalker (1990) Table E.3 for c11, c22, c23; Polach, Wear 258 (2005) 992-1000 for the creep force.
"""

from __future__ import annotations

import ctypes
import math
from dataclasses import dataclass

import numpy as np

from railbrake import _core, config
from railbrake._args import instance, real, reals
from railbrake.errors import InputError
from railbrake.units import G_STANDARD

STEEL_YOUNGS_MODULUS = 2.1e11  # Pa
STEEL_POISSON = 0.3

# Default high-speed wheelset (used where contact=None): 0.46 m wheel radius (920 mm wheel,
# CRH3C / Velaro), 17 t axle load, conical tread on a rail head of 0.3 m transverse radius.
DEFAULT_WHEEL_RADIUS = 0.46  # m
DEFAULT_AXLE_LOAD = 17e3  # kg
DEFAULT_RAIL_HEAD_RADIUS = 0.3  # m


@dataclass(frozen=True)
class HertzContact:
    """Hertz contact ellipse; ``a`` lies in the rolling direction, ``b`` across it (SI)."""

    a: float
    b: float
    p0: float
    normal_force: float
    youngs_modulus: float
    poisson: float
    shear_modulus: float

    @property
    def a_over_b(self) -> float:
        return self.a / self.b

    @property
    def c11(self) -> float:
        return kalker_c11(self.a_over_b, self.poisson)

    def creep_contact(self, shear_modulus: float | None = None) -> _core.CreepContact:
        g = self.shear_modulus if shear_modulus is None else shear_modulus
        return _core.CreepContact(self.a, self.b, self.c11, g)


@dataclass(frozen=True)
class PolachParams:
    """Polach's five parameters: mu0, A, B [s/m], kA, kS (Polach 2005, Table 2 for dry/wet), and
    optionally v_ref [m/s], the rolling speed at which mu0 is halved: wet rail's friction falling
    with the train speed v itself, mu0 / (1 + v / v_ref) (rb_contact.h). v_ref = None (the default):
    Polach's law."""

    mu0: float
    A: float
    B: float
    kA: float
    kS: float
    v_ref: float | None = None

    def __post_init__(self):
        for key in ("mu0", "A", "B", "kA", "kS"):
            object.__setattr__(self, key, real(key, getattr(self, key)))
        if self.v_ref is not None:
            object.__setattr__(self, "v_ref", real("v_ref", self.v_ref, *config.bound_in("adhesion.v_ref")[:2]))
        _core.call(_core.rb_polach_check, ctypes.byref(self.to_c()))

    @property
    def v_ref_inv(self) -> float:
        """1 / v_ref (s/m), 0 without the rolling-speed factor: the C core's form."""
        return 0.0 if self.v_ref is None else 1.0 / self.v_ref

    def to_c(self) -> _core.PolachParamsC:
        return _core.PolachParamsC(self.mu0, self.A, self.B, self.kA, self.kS, self.v_ref_inv)

    def as_dict(self) -> dict:
        """The parameters; v_ref (m/s) only where the rolling-speed factor is on."""
        out = {"mu0": self.mu0, "A": self.A, "B": self.B, "kA": self.kA, "kS": self.kS}
        return out if self.v_ref is None else {**out, "v_ref": self.v_ref}


def relative_radius(*radii: float) -> float:
    """Radius of relative curvature 1/r = sum(1/R_i); an infinite radius (flat) adds nothing."""
    curvature = 0.0
    for i, radius in enumerate(radii):
        radius = real(f"radius {i + 1} of relative_radius", radius, *RADIUS_RANGE, allow_inf=True)
        curvature += 0.0 if math.isinf(radius) else 1.0 / radius
    if curvature == 0.0:
        raise InputError(f"radii {', '.join(f'{r:g}' for r in radii)}: all infinite, the bodies are flat and have "
                         "no point contact")
    return 1.0 / curvature


def hertz_contact(normal_force: float, rx: float, ry: float,
                  youngs_modulus: float = STEEL_YOUNGS_MODULUS,
                  poisson: float = STEEL_POISSON) -> HertzContact:
    """Exact Hertz contact of two bodies of one material.

    rx, ry: radii of relative curvature in the rolling and lateral directions, e.g.
    ``rx = relative_radius(wheel_radius, rail_longitudinal_radius)`` and
    ``ry = relative_radius(wheel_profile_radius, rail_head_radius)``.
    """
    out = _core.Hertz()
    _core.call(_core.rb_hertz_contact, real("normal_force", normal_force, *FORCE_RANGE),
               real("rx", rx, *RADIUS_RANGE), real("ry", ry, *RADIUS_RANGE),
               real("youngs_modulus", youngs_modulus, 0.0, low_open=True),
               real("poisson", poisson, 0.0, 0.5, high_open=True), ctypes.byref(out))
    return HertzContact(out.a, out.b, out.p0, out.normal_force, out.youngs_modulus,
                        out.poisson, out.shear_modulus)


def wheel_rail_contact(wheel_radius: float = DEFAULT_WHEEL_RADIUS,
                       axle_load: float = DEFAULT_AXLE_LOAD,
                       rail_head_radius: float = DEFAULT_RAIL_HEAD_RADIUS,
                       wheel_profile_radius: float = math.inf,
                       youngs_modulus: float = STEEL_YOUNGS_MODULUS,
                       poisson: float = STEEL_POISSON) -> HertzContact:
    """Contact of one wheel on a straight rail; axle_load in kg is shared by two wheels."""
    axle_load = real("axle_load", axle_load, FORCE_RANGE[0] / G_STANDARD, FORCE_RANGE[1] / G_STANDARD)
    radii = {"wheel_radius": wheel_radius, "wheel_profile_radius": wheel_profile_radius,
             "rail_head_radius": rail_head_radius}
    for name, value in radii.items():
        real(name, value, *RADIUS_RANGE, allow_inf=name != "wheel_radius")
    try:
        rx = relative_radius(wheel_radius)
        ry = relative_radius(wheel_profile_radius, rail_head_radius)
        return hertz_contact(axle_load * G_STANDARD / 2.0, rx, ry, youngs_modulus, poisson)
    except InputError as exc:   # name the caller's arguments, not rx, ry
        given = ", ".join(f"{k} = {v:g} m" for k, v in radii.items())
        raise InputError(f"{given}: {exc}") from None


def default_contact() -> HertzContact:
    """The default high-speed wheelset: 0.46 m wheel, 17 t axle load, 0.3 m rail head."""
    return wheel_rail_contact()


def _kalker(which: int, a_over_b: float, poisson: float) -> float:
    out = ctypes.c_double()
    _core.call(_core.rb_kalker, which, real("a_over_b", a_over_b, 1e-12, 1e6),
               real("poisson", poisson, 0.0, 0.5), ctypes.byref(out))
    return out.value


def kalker_c11(a_over_b: float, poisson: float) -> float:
    """Kalker's longitudinal creepage coefficient C11 (Table E.3 with asymptotes)."""
    return _kalker(11, a_over_b, poisson)


def kalker_c22(a_over_b: float, poisson: float) -> float:
    """Kalker's lateral creepage coefficient C22."""
    return _kalker(22, a_over_b, poisson)


def kalker_c23(a_over_b: float, poisson: float) -> float:
    """Kalker's spin coefficient C23."""
    return _kalker(23, a_over_b, poisson)


# Argument ranges the closed forms are evaluated over (outside them the results overflow or
# vanish below the smallest float): forces 1 mN to 1 GN, radii 1 um to 1000 km, |creep| <= 1000.
FORCE_RANGE = (1e-3, 1e9)            # N
RADIUS_RANGE = (1e-6, 1e9)           # m
CREEP_LIMIT = 1e3
SPEED_LIMIT = 1e3                    # m/s


def _contact_args(normal_force, contact, params, shear_modulus) -> None:
    real("normal_force", normal_force, *FORCE_RANGE)
    instance("contact", contact, HertzContact)
    instance("params", params, PolachParams)
    if shear_modulus is not None:
        real("shear_modulus", shear_modulus, 0.0, low_open=True)


def polach_coefficient(creep, speed, normal_force: float, contact: HertzContact,
                       params: PolachParams, shear_modulus: float | None = None):
    """Creep force over normal force, F/Q, with the sign of the creep.

    creep: longitudinal creepage (braking is negative; -1 is a locked wheel);
    speed: train speed in m/s (>= 0). Both broadcast; the result has their shape.
    """
    _contact_args(normal_force, contact, params, shear_modulus)
    try:
        creep_b, speed_b = np.broadcast_arrays(reals("creep", creep, -CREEP_LIMIT, CREEP_LIMIT),
                                               reals("speed", speed, 0.0, SPEED_LIMIT))
    except ValueError as exc:
        if isinstance(exc, InputError):
            raise
        raise InputError(f"creep and speed: shapes {np.shape(creep)} and {np.shape(speed)} do not broadcast") from None
    creep_c = _core.as_double_array(creep_b.ravel())
    speed_c = _core.as_double_array(speed_b.ravel())
    out = np.empty_like(creep_c)
    _core.call(_core.rb_polach_coefficient, _core.ptr(creep_c), _core.ptr(speed_c), creep_c.size,
               float(normal_force), ctypes.byref(contact.creep_contact(shear_modulus)),
               ctypes.byref(params.to_c()), _core.ptr(out))
    result = out.reshape(creep_b.shape)
    return float(result) if result.ndim == 0 else result


def polach_peak(speed: float, normal_force: float, contact: HertzContact, params: PolachParams,
                shear_modulus: float | None = None) -> tuple[float, float]:
    """(peak F/Q, creep at the peak) over creep in (0, 1] at one speed in m/s."""
    _contact_args(normal_force, contact, params, shear_modulus)
    peak, at = ctypes.c_double(), ctypes.c_double()
    _core.call(_core.rb_polach_peak, real("speed", speed, 0.0, SPEED_LIMIT), float(normal_force),
               ctypes.byref(contact.creep_contact(shear_modulus)), ctypes.byref(params.to_c()),
               ctypes.byref(peak), ctypes.byref(at))
    return peak.value, at.value
