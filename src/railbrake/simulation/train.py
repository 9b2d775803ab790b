"""Train data for the whole-train simulation.

PENDING (replace by railbrake.vehicle.load_train and railbrake.sizing.target_pressure when the
vehicle concern lands on main): the presets below carry the published figures of
shared/reference/README.md section 2 and typical values [T] for what is not published.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from railbrake.errors import InputError


@dataclass(frozen=True)
class TrainData:
    name: str
    cars: int
    mass_t: float                 # whole train with load [P]
    motor_cars: tuple             # 1-based indices of motor cars
    wheel_radius: float           # m
    car_length: float = 25.0      # m [T]
    rotating_mass_factor: float = 0.06   # [P] CRH380AL, includes the wheelsets
    wheelset_inertia: float = 120.0      # kg m^2 [T] 80-150
    discs_per_axle: int = 3              # [P/T] CRH3C trailer axles
    disc_radius: float = 0.247           # m [P/T]
    pad_friction: float = 0.35           # [T]
    pad_friction_low: float = 0.42       # [T] rising below 100 km/h
    resistance_kn: tuple = (3.3, 0.0469, 0.000921)   # A, B, C with V in km/h, whole train [P]
    resistance_cars: int = 16
    ed_train_kn: str = "crh380al"
    ed_train_motor_cars: int = 14
    source: str = field(default="shared/reference/README.md section 2")


PRESETS = {
    "crh380al-16": TrainData("crh380al-16", 16, 903.0, tuple(c for c in range(1, 17) if c not in (1, 16)), 0.43),
    "crh380a-8": TrainData("crh380a-8", 8, 388.4, (2, 3, 4, 5, 6, 7), 0.43, resistance_cars=16),
    "velaro-8": TrainData("velaro-8", 8, 8 * 66.0, (2, 4, 5, 7), 0.46),
}


def load_train(name: str) -> TrainData:
    if name not in PRESETS:
        raise InputError(f"train = {name!r}: not a preset ({', '.join(sorted(PRESETS))})")
    return PRESETS[name]


def ed_force_train(speed: float) -> float:
    """CRH380AL ED brake force of the whole train (N) at speed (m/s), TB/T 1407.2 [P]."""
    if speed <= 0.0:
        return 509.6e3
    return 1e3 * min(509.6, 544.34 - 1.787 * speed, 42942.9 / speed - 121.0, 33033.0 / speed)
