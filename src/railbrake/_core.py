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
    if override and not Path(override).is_file():
        raise ImportError(f"RAILBRAKE_CORE_LIBRARY = {override!r}: no such file (from {os.getcwd()}); unset it to "
                          "use the installed core")
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


def channel_list(count, info, n_cars: int) -> list[tuple[str, str]]:
    """(name, SI unit) of every channel of a recorded time series, from its C layout functions."""
    name, unit = ctypes.create_string_buffer(64), ctypes.create_string_buffer(16)
    out = []
    for i in range(count(n_cars)):
        call(info, i, n_cars, name, 64, unit, 16)
        out.append((name.value.decode(), unit.value.decode()))
    return out


def ptr(array: np.ndarray):
    return array.ctypes.data_as(c_double_p)


def _declare(name, restype, *argtypes):
    function = getattr(lib, name)
    function.restype = restype
    function.argtypes = list(argtypes)
    return function


_err_p = POINTER(RbError)

rb_version = _declare("rb_version", ctypes.c_char_p)
rb_build_hash = _declare("rb_build_hash", ctypes.c_char_p)

# ---------------------------------------------------------------- contact (rb_contact.h)


class Hertz(Structure):
    _fields_ = [(n, c_double) for n in
                ("a", "b", "p0", "normal_force", "youngs_modulus", "poisson", "shear_modulus")]


class PolachParamsC(Structure):
    _fields_ = [(n, c_double) for n in ("mu0", "A", "B", "kA", "kS", "v_ref_inv")]


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


class ConditioningEnergy(Structure):
    _fields_ = [(n, c_double) for n in ("leading_factor", "reference_energy")]


rb_conditioning_energy_check = _declare("rb_conditioning_energy_check", c_int, POINTER(ConditioningEnergy), _err_p)
rb_conditioning_energy_size = _declare("rb_conditioning_energy_size", c_size_t)
rb_dissipated_energy_density = _declare("rb_dissipated_energy_density", c_double, c_double, c_double, c_double,
                                        c_double)
rb_conditioning_energy_factor = _declare("rb_conditioning_energy_factor", c_double, POINTER(ConditioningEnergy),
                                         c_double)
if ctypes.sizeof(ConditioningEnergy) != rb_conditioning_energy_size():
    raise ImportError("rb_conditioning_energy: ctypes size differs from the C core's; src/railbrake/_core.py is out of date")
rb_polach_check = _declare("rb_polach_check", c_int, POINTER(PolachParamsC), _err_p)

# ---------------------------------------------------------------- vehicle (rb_vehicle.h)

MAX_TABLE = 64
MAX_STOP_GRADIENTS = 16
MAX_ED_TERMS = 8
MAX_CARS = 20
MAX_COMPRESSORS = 4
ED_OFF, ED_MAX, ED_BLENDED = 0, 1, 2


class SpeedTable(Structure):
    _fields_ = [("n", c_int), ("speed", c_double * MAX_TABLE), ("value", c_double * MAX_TABLE)]


class PadFriction(Structure):
    _fields_ = [("table", SpeedTable), ("fade_onset", c_double), ("fade_rate", c_double)]


class Caliper(Structure):
    _fields_ = [(n, c_double) for n in
                ("cylinder_area", "return_spring", "lever_ratio", "efficiency", "atmospheric_pressure")]


class AxleBrake(Structure):
    _fields_ = [("discs", c_int), ("mounting", c_int), ("mean_radius", c_double),
                ("caliper", Caliper), ("pad", PadFriction)]


class Wheelset(Structure):
    _fields_ = [(n, c_double) for n in ("wheel_radius", "inertia", "axle_load")]


class Resistance(Structure):
    _fields_ = [(n, c_double) for n in ("A", "B", "C")]


class EdCurve(Structure):
    _fields_ = [("table", SpeedTable), ("terms", c_int), ("c0", c_double * MAX_ED_TERMS),
                ("c1", c_double * MAX_ED_TERMS), ("c2", c_double * MAX_ED_TERMS),
                ("scale", c_double), ("fade_speed", c_double)]


class Coupler(Structure):
    _fields_ = [(n, c_double) for n in ("slack", "stiffness", "stiffness_cubic", "damping")]


class Car(Structure):
    _fields_ = [("motor", c_int), ("axles", c_int), ("mass", c_double), ("wheelset", Wheelset),
                ("brake", AxleBrake), ("ed", EdCurve), ("supply_pressure", c_double)]


class TrainC(Structure):
    _fields_ = [("n_cars", c_int), ("cars", Car * MAX_CARS), ("resistance", Resistance)]


class BrakeCommand(Structure):
    _fields_ = [("p_motor", SpeedTable), ("p_trailer", SpeedTable), ("ed_mode", c_int),
                ("ed_demand", SpeedTable)]


class StopOptions(Structure):
    _fields_ = [("v0", c_double), ("v_end", c_double), ("gradient", c_double), ("delay", c_double),
                ("build_up", c_double), ("equivalent_response", c_int), ("dt", c_double),
                ("dt_out", c_double), ("t_max", c_double), ("n_gradients", c_int),
                ("gradient_start", c_double * MAX_STOP_GRADIENTS), ("gradient_value", c_double * MAX_STOP_GRADIENTS)]


def speed_table(speed, value) -> SpeedTable:
    """A SpeedTable from two equal-length sequences (at most MAX_TABLE points)."""
    speed, value = list(speed), list(value)
    if len(speed) != len(value) or len(speed) > MAX_TABLE:
        raise InputError(f"table of {len(speed)} speeds and {len(value)} values: "
                         f"needs equal lengths of at most {MAX_TABLE}")
    table = SpeedTable()
    table.n = len(speed)
    for i, (v, y) in enumerate(zip(speed, value)):
        table.speed[i], table.value[i] = float(v), float(y)
    return table


_size_p = POINTER(c_size_t)
rb_speed_table_at = _declare("rb_speed_table_at", c_double, POINTER(SpeedTable), c_double)
rb_speed_table_check = _declare("rb_speed_table_check", c_int, POINTER(SpeedTable), ctypes.c_char_p,
                                c_double, c_double, _err_p)
rb_pad_friction_at = _declare("rb_pad_friction_at", c_double, POINTER(PadFriction), c_double)
class DynoStop(Structure):
    _fields_ = ([(n, c_double) for n in ("initial_speed", "mass", "pad_force", "friction_radius", "wheel_radius",
                                         "heat_capacity", "surface_capacity", "surface_conductance")]
                + [("cooling", SpeedTable), ("ambient_temperature", c_double), ("dt", c_double)])


class DynoResult(Structure):
    _fields_ = [(n, c_double) for n in ("mean_friction", "max_surface_temperature", "max_mean_temperature", "heat",
                                        "stored", "cooled", "distance", "time")]


rb_pad_friction_eval = _declare("rb_pad_friction_eval", c_double, POINTER(PadFriction), c_double, c_double)
rb_dyno_stop_run = _declare("rb_dyno_stop_run", c_int, POINTER(PadFriction), POINTER(DynoStop), POINTER(DynoResult),
                            _err_p)
rb_pad_friction_sintered = _declare("rb_pad_friction_sintered", c_int, c_double, POINTER(PadFriction),
                                    _err_p)
rb_caliper_check = _declare("rb_caliper_check", c_int, POINTER(Caliper), _err_p)
rb_caliper_pad_force = _declare("rb_caliper_pad_force", c_double, POINTER(Caliper), c_double)
rb_axle_brake_torque = _declare("rb_axle_brake_torque", c_double, POINTER(AxleBrake), c_double, c_double)
rb_wheelset_equivalent_mass = _declare("rb_wheelset_equivalent_mass", c_double, POINTER(Wheelset))
rb_equivalent_rotating_mass = _declare("rb_equivalent_rotating_mass", c_int, POINTER(Wheelset),
                                       c_size_t, c_double_p, _err_p)
rb_running_resistance = _declare("rb_running_resistance", c_double, POINTER(Resistance), c_double)
rb_ed_brake_force_max = _declare("rb_ed_brake_force_max", c_double, POINTER(EdCurve), c_double)
rb_coupler_force = _declare("rb_coupler_force", c_double, POINTER(Coupler), c_double, c_double)
rb_coupler_check = _declare("rb_coupler_check", c_int, POINTER(Coupler), _err_p)
rb_train_check = _declare("rb_train_check", c_int, POINTER(TrainC), _err_p)
rb_train_mass = _declare("rb_train_mass", c_double, POINTER(TrainC))
rb_train_rotating_mass = _declare("rb_train_rotating_mass", c_double, POINTER(TrainC))
rb_train_ed_force_max = _declare("rb_train_ed_force_max", c_double, POINTER(TrainC), c_double)
rb_train_deceleration_curve = _declare("rb_train_deceleration_curve", c_int, POINTER(TrainC),
                                       c_double_p, c_double_p, c_double_p, c_int, c_double_p,
                                       c_size_t, c_double, c_double_p, _err_p)
rb_size_target_pressure = _declare("rb_size_target_pressure", c_int, POINTER(TrainC), c_double_p,
                                   c_double_p, c_size_t, c_double, c_double_p, c_double_p,
                                   c_double_p, c_double_p, _err_p)
rb_size_target_pressure_ed = _declare("rb_size_target_pressure_ed", c_int, POINTER(TrainC), c_double_p,
                                      c_double_p, c_size_t, c_double, c_int, c_double_p, c_double_p,
                                      c_double_p, c_double_p, _err_p)
rb_size_car_demand = _declare("rb_size_car_demand", c_int, POINTER(TrainC), c_int, c_double_p, c_double_p,
                              c_size_t, c_double, c_double_p, c_double_p, c_double_p, _err_p)
rb_stop_train = _declare("rb_stop_train", c_int, POINTER(TrainC), POINTER(BrakeCommand),
                         POINTER(StopOptions), c_double_p, c_double_p, c_double_p, c_size_t, _size_p,
                         c_double_p, c_double_p, _err_p)
class TrainDiscs(Structure):
    _fields_ = [(n, c_double * MAX_CARS) for n in ("heat_capacity", "surface_capacity", "surface_conductance")] + [
        ("cooling", SpeedTable * MAX_CARS), ("ambient_temperature", c_double)]


rb_stop_train_heated = _declare("rb_stop_train_heated", c_int, POINTER(TrainC), POINTER(BrakeCommand),
                                POINTER(TrainDiscs), POINTER(StopOptions), c_double_p, c_double_p, c_double_p,
                                c_size_t, _size_p, c_double_p, c_double_p, c_double_p, _err_p)
rb_stop_profile = _declare("rb_stop_profile", c_int, POINTER(SpeedTable), POINTER(StopOptions),
                           c_double_p, c_double_p, c_double_p, c_size_t, _size_p, c_double_p,
                           c_double_p, _err_p)
rb_stop_constant = _declare("rb_stop_constant", c_int, c_double, c_double, c_double, c_double_p,
                            c_double_p, _err_p)

# ---------------------------------------------------------------- whole-train plant (rb_plant.h, rb_bcu.h, rb_run.h)

from ctypes import c_char_p, c_long, c_uint8, c_uint64, c_void_p  # noqa: E402

PLANT_MAX_CARS = 16
AXLES_PER_CAR = 4
PLANT_MAX_AXLES = PLANT_MAX_CARS * AXLES_PER_CAR
MAX_CONDITIONS = 4
MAX_ZONES = 8
MAX_FAULTS = 16
MAX_DEMAND_STEPS = 16
MAX_SPEED_MARKS = 16   # RB_MAX_SPEED_MARKS
MAX_GRADIENTS = 16
MAX_SANDERS = 8


def _doubles(*names):
    return [(n, c_double) for n in names]


class PlantCar(Structure):
    _fields_ = ([("vehicle", Car), ("length", c_double), ("axle_position", c_double * AXLES_PER_CAR),
                 ("contact", CreepContact), ("ed_tau", c_double)]
                + _doubles("ed_slide_slip", "ed_slide_release", "ed_cut_rate", "ed_restore_rate")
                + _doubles("supply_volume", "pilot_volume", "relay_volume", "cylinder_volume", "pipe_volume",
                           "charge_area", "ep_area", "ep_tau", "ep_band", "ep_supply_margin", "ep_bleed_area",
                           "relay_supply_area", "relay_exhaust_area", "relay_band", "relay_tau", "relay_sweep",
                           "relay_travel",
                           "hold_area", "vent_area", "valve_delay",
                           "pipe_area", "disc_heat_capacity")
                + [("disc_cooling", SpeedTable)]
                + _doubles("emergency_delay", "emergency_area", "emergency_limit")
                + _doubles("disc_surface_capacity", "disc_surface_conductance"))


class PlantCondition(Structure):
    _fields_ = [("polach", PolachParamsC)] + _doubles("leading_factor", "recovery_axles", "reference_energy")


class TrackZone(Structure):
    _fields_ = _doubles("x_start", "x_end") + [("condition", c_int)]


class Fault(Structure):
    _fields_ = [("kind", c_int), ("car", c_int), ("axle", c_int)] + _doubles("start_time", "value")


FAULT_KINDS = ("hold_stuck_open", "hold_stuck_closed", "vent_stuck_open", "vent_stuck_closed",
               "sensor_lost", "sensor_noisy", "cylinder_leak", "ep_valve_failed", "ed_lost",
               "car_isolated", "compressor_off", "emergency_valve_failed", "emergency_loop_lost",
               "relay_valve_failed", "pressure_limiter_failed", "axle_isolated", "pipe_leak")


class PlantParams(Structure):
    _fields_ = ([("n_cars", c_int), ("dt", c_double), ("substeps", c_int)]
                + _doubles("temperature", "atmosphere", "discharge_coefficient", "critical_ratio")
                + [("car", PlantCar * PLANT_MAX_CARS), ("coupler", Coupler), ("resistance", Resistance)]
                + [("compressor_car", c_int)]
                + _doubles("main_reservoir_volume", "main_reservoir_area", "compressor_flow",
                           "governor_on", "governor_off", "initial_pressure", "initial_speed")
                + [("n_conditions", c_int), ("condition", PlantCondition * MAX_CONDITIONS),
                   ("n_zones", c_int), ("zone", TrackZone * MAX_ZONES), ("creep_speed_min", c_double),
                   ("n_faults", c_int), ("fault", Fault * MAX_FAULTS), ("noise_seed", c_uint64),
                   ("kernel", c_int)]
                + [("n_compressors", c_int), ("compressor_position", c_int * MAX_COMPRESSORS),
                   ("compressor_delivery", c_double * MAX_COMPRESSORS),
                   ("n_gradients", c_int), ("gradient_start", c_double * MAX_GRADIENTS),
                   ("gradient", c_double * MAX_GRADIENTS), ("ambient_temperature", c_double)]
                + [("wall_time", c_double), ("rail_cell_length", c_double)]
                + [("n_sanders", c_int), ("sander_axle", c_int * MAX_SANDERS), ("sander_trigger", c_int * MAX_SANDERS),
                   ("sander_rate", SpeedTable * MAX_SANDERS), ("sander_start", c_double * MAX_SANDERS),
                   ("sand_reference", c_double), ("sand_entrained", c_double), ("sand_retention", c_double)])


# rb_plant_kernel: the wheelset kernel asked for (rb_plant_params.kernel) and the one in use.
KERNELS = {"auto": 0, "portable": 1}


class WspInputs(Structure):
    _fields_ = (_doubles("time", "cycle") + [("n_axles", c_int)]
                + [(n, c_double * PLANT_MAX_AXLES) for n in ("wheel_speed", "cylinder", "demand")]
                + [("atmosphere", c_double), ("body_decel", c_double)])


class WspCommands(Structure):
    _fields_ = [(n, c_uint8 * PLANT_MAX_AXLES) for n in ("hold", "vent", "active")]


WSP_FUNCTION = ctypes.CFUNCTYPE(None, c_void_p, POINTER(WspInputs), POINTER(WspCommands))


class WspParams(Structure):
    _fields_ = _doubles("ref_decel_max", "ref_accel_max", "speed_threshold", "slip_threshold",
                        "decel_threshold", "reaccel_threshold", "release_fraction", "reapply_on",
                        "reapply_off", "reapply_time", "filter_time",
                        "safety_time", "min_speed") + [("controller", c_int)] + _doubles(
        "setpoint_speed", "setpoint_slip", "setpoint_band", "lead_time", "ref_decel_margin", "setpoint_release",
        "setpoint_memory", "setpoint_ramp",
        "ds_speed_threshold", "ds_slip_threshold", "ds_decel_threshold", "ds_reaccel_threshold") + [
        ("conditioning_mode", c_int), ("conditioning_ratio", c_double)]


class BcuParams(Structure):
    _fields_ = ([("n_cars", c_int)]
                + _doubles("cycle", "atmosphere", "service_decel", "emergency_decel")
                + [("ed_in_emergency", c_int)]
                + [(n, c_double * PLANT_MAX_CARS) for n in ("car_mass", "pressure_offset", "pressure_gain",
                                                      "pressure_max")]
                + [("motor", c_int * PLANT_MAX_CARS), ("wsp_enabled", c_int), ("wsp_per_bogie", c_int),
                   ("wsp", WSP_FUNCTION),
                   ("wsp_context", c_void_p)]
                + [("demand_tables", c_int), ("ed_in_service", c_int)]
                + [(n, SpeedTable * PLANT_MAX_CARS) for n in ("emergency_force", "service_force",
                                                             "pressure_per_newton")]
                + [("emergency_profile", SpeedTable), ("service_profile", SpeedTable)]
                + [("service_jerk", c_double)])


class Scenario(Structure):
    _fields_ = ([("n_demand", c_int)]
                + [(n, c_double * MAX_DEMAND_STEPS) for n in ("demand_time", "demand_service",
                                                              "demand_emergency")]
                + _doubles("max_time", "stop_speed", "record_interval", "adhesion_interval")
                + [("n_speed_marks", c_int), ("speed_mark", c_double * MAX_SPEED_MARKS)])


KPI_NAMES = ("stopping_distance_m", "stopping_time_s", "mean_deceleration", "max_slip",
             "wheel_lock_events", "max_lock_duration_s", "air_consumed_kg", "adhesion_utilisation",
             "safety_timer_trips", "air_balance_error", "stopped",
             "min_main_reservoir", "min_supply", "air_drawn_kg", "air_vented_kg", "cylinder_shortfall_s",
             "worst_axle", "brake_energy", "max_disc_temperature", "min_supply_margin")
# after the speed marks in rb_kpis
KPI_TAIL_NAMES = ("valve_switchings", "max_sliding_energy", "sliding_energy", "mean_pad_friction",
                  "max_disc_surface_temperature")
SHORTFALL_PA = 0.2e5  # RB_SHORTFALL_PA


class Kpis(Structure):
    _fields_ = _doubles(*KPI_NAMES) + [("mark_time_s", c_double * MAX_SPEED_MARKS),
                                       ("mark_distance_m", c_double * MAX_SPEED_MARKS)] + _doubles(*KPI_TAIL_NAMES)


rb_plant_params_size = _declare("rb_plant_params_size", c_size_t)
rb_plant_state_size = _declare("rb_plant_state_size", c_size_t)
rb_run_state_size = _declare("rb_run_state_size", c_size_t)
rb_plant_check = _declare("rb_plant_check", c_int, POINTER(PlantParams), _err_p)
rb_wsp_default_params = _declare("rb_wsp_default_params", None, POINTER(WspParams))
rb_wsp_check = _declare("rb_wsp_check", c_int, POINTER(WspParams), _err_p)
rb_plant_bounds_check = _declare("rb_plant_bounds_check", c_int, POINTER(PlantParams), _err_p)


class Bound(Structure):
    """rb_bound (rb_bounds.h): one plausibility bound of the C table."""
    _fields_ = [("name", c_char_p), ("unit", c_char_p), ("min", c_double), ("max", c_double), ("why", c_char_p)]


rb_bound_count = _declare("rb_bound_count", c_int)
rb_bound_at = _declare("rb_bound_at", POINTER(Bound), c_int)


def _read_bounds() -> dict:
    table = {}
    for i in range(rb_bound_count()):
        b = rb_bound_at(i).contents
        table[b.name.decode()] = (b.min, b.max, b.unit.decode(), b.why.decode())
    return table


# The one table of plausibility bounds (core/src/bounds.c), SI: name -> (min, max, unit, why).
BOUNDS = _read_bounds()


def bound(name: str) -> tuple[float, float]:
    """(min, max) in SI of the C bound `name`, e.g. "coupler.damping", "car.mass"."""
    low, high, _, _ = BOUNDS[name]
    return low, high
rb_bcu_pressure_map = _declare("rb_bcu_pressure_map", None, POINTER(PlantParams), c_double,
                               POINTER(BcuParams))
rb_run_init = _declare("rb_run_init", c_int, POINTER(PlantParams), POINTER(BcuParams), POINTER(WspParams),
                       POINTER(Scenario), c_void_p, _err_p)
rb_run_advance = _declare("rb_run_advance", c_int, POINTER(PlantParams), POINTER(BcuParams),
                          POINTER(Scenario), c_void_p, c_double, c_double_p, c_size_t, POINTER(c_int), _err_p)
rb_run_kpis = _declare("rb_run_kpis", None, POINTER(PlantParams), c_void_p, POINTER(Kpis))
rb_run_retune = _declare("rb_run_retune", c_int, POINTER(PlantParams), POINTER(WspParams), c_void_p, _err_p)
rb_run_channel_count = _declare("rb_run_channel_count", c_int, c_int)
rb_run_channel_info = _declare("rb_run_channel_info", c_int, c_int, c_int, c_char_p, c_size_t, c_char_p,
                               c_size_t, _err_p)
rb_plant_bench = _declare("rb_plant_bench", c_int, POINTER(PlantParams), c_double, c_long, c_double_p,
                          c_double_p, c_double_p, c_double_p, c_char_p, c_size_t, _err_p)
MAX_BATCH = 4096   # RB_MAX_BATCH
rb_run_batch = _declare("rb_run_batch", c_int, c_int, POINTER(PlantParams), POINTER(BcuParams), POINTER(WspParams),
                        POINTER(Scenario), c_void_p, POINTER(Kpis), POINTER(c_int), POINTER(RbError), _err_p)


class RunBenchResult(Structure):
    _fields_ = _doubles("steps", "run_us", "plant_us") + [("kernel", ctypes.c_char * 16)]


rb_run_bench = _declare("rb_run_bench", c_int, POINTER(PlantParams), POINTER(BcuParams), POINTER(WspParams),
                        POINTER(Scenario), c_int, c_void_p, c_void_p, c_size_t, POINTER(RunBenchResult), _err_p)
rb_plant_valve_air = _declare("rb_plant_valve_air", c_int, POINTER(PlantParams), c_double, c_double, c_double_p,
                              c_int, c_double_p, _err_p)

for _struct, _size in ((BcuParams, "rb_bcu_params_size"), (Kpis, "rb_kpis_size")):
    if ctypes.sizeof(_struct) != _declare(_size, c_size_t)():
        raise ImportError(f"{_size[:-5]}: ctypes size {ctypes.sizeof(_struct)} differs from the C core's; "
                          "src/railbrake/_core.py is out of date")
if ctypes.sizeof(PlantParams) != rb_plant_params_size():
    raise ImportError(f"rb_plant_params: ctypes size {ctypes.sizeof(PlantParams)} differs from the C core's "
                      f"{rb_plant_params_size()}; src/railbrake/_core.py is out of date")

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
rb_wall_conductance = _declare("rb_wall_conductance", c_double, *[c_double] * 4)
WALL_REFERENCE_PRESSURE = 5e5   # Pa abs, as RB_WALL_REFERENCE_PRESSURE (rb_pneumatics.h)
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

# ---------------------------------------------------------------- detailed train model (rb_detailed.h)

DETAILED_MAX_SUBSTEPS = 256


class DetailedParams(Structure):
    _fields_ = [(n, c_double) for n in (
        "pilot_volume", "pilot_orifice_area", "nozzle_diameter", "armature_mass", "armature_spring_rate",
        "armature_preload", "armature_damping", "airgap_open", "flapper_travel")] + [
        ("solenoid", ForceTable), ("current_max", c_double)] + [(n, c_double) for n in (
        "piston_area", "piston_mass", "piston_spring_rate", "piston_preload", "piston_damping",
        "piston_friction", "piston_friction_velocity", "piston_travel", "seat_lap",
        "epv_inlet_diameter", "epv_exhaust_diameter")] + [
        ("membrane_points", c_int), ("membrane_x", c_double * MEMBRANE_MAX_POINTS),
        ("membrane_volume", c_double * MEMBRANE_MAX_POINTS)] + [(n, c_double) for n in (
        "membrane_mass", "membrane_spring_rate", "membrane_preload", "membrane_damping", "membrane_travel",
        "relay_inlet_diameter", "relay_exhaust_diameter", "thermal_time", "trim_time", "rtol", "atol",
        "mechanics_dt")]


rb_detailed_state_size = _declare("rb_detailed_state_size", c_size_t)
rb_detailed_check = _declare("rb_detailed_check", c_int, POINTER(DetailedParams), _err_p)
rb_detailed_init = _declare("rb_detailed_init", c_int, POINTER(PlantParams), POINTER(DetailedParams),
                            POINTER(BcuParams), POINTER(WspParams), POINTER(Scenario), c_void_p, _err_p)
rb_detailed_advance = _declare("rb_detailed_advance", c_int, POINTER(PlantParams), POINTER(DetailedParams),
                               POINTER(BcuParams), POINTER(Scenario), c_void_p, c_double, c_double_p, c_size_t,
                               POINTER(c_int), _err_p)
rb_detailed_kpis = _declare("rb_detailed_kpis", None, POINTER(PlantParams), c_void_p, POINTER(Kpis))
rb_detailed_epv_current = _declare("rb_detailed_epv_current", c_int, POINTER(PlantParams),
                                   POINTER(DetailedParams), c_double, c_double, c_double_p, _err_p)
rb_detailed_valve_run = _declare("rb_detailed_valve_run", c_int, POINTER(PlantParams), POINTER(DetailedParams),
                                 c_double, c_double, c_double_p, c_double_p, _err_p)
rb_detailed_valve_air = _declare("rb_detailed_valve_air", c_int, POINTER(PlantParams), POINTER(DetailedParams),
                                 c_double, c_double, c_double_p, c_int, c_double_p, _err_p)
rb_detailed_stats = _declare("rb_detailed_stats", None, c_void_p, POINTER(OdeStats))

# ---------------------------------------------------------------- hil and real time (rb_hil.h, rb_rt.h)

from ctypes import c_float, c_uint32  # noqa: E402

FRAME_MAX_CARS = 16
FRAME_MAX_AXLES = 64
HIL_LOG_TEXT = 120
HIL_EVENT_KINDS = ("malformed", "late", "lost", "safe_on", "safe_off", "foreign", "mismatch", "forged", "keyed",
                   "order", "fault_on", "fault_off")
HIL_FAULT_INJECT, HIL_FAULT_CLEAR = 1, 2
ERROR_MESSAGE_SIZE = _ERROR_MESSAGE_SIZE
HIL_KEY_SIZE = 16
RT_MEMORY_LOCKED = 1
RT_FIFO_PRIORITY = 2


class PlantInputs(Structure):
    _fields_ = [(n, c_double * PLANT_MAX_CARS) for n in ("pressure_demand", "ed_demand")] + [
        (n, c_uint8 * PLANT_MAX_AXLES) for n in ("hold", "vent")] + [("emergency", c_double)]


class HilConfig(Structure):
    _fields_ = (_doubles("hold_time", "late_time", "duration", "stop_speed", "record_interval")
                + [("paced", c_int), ("safe", BcuParams), ("adhesion_interval", c_double),
                   ("session", c_uint32), ("config", c_uint32), ("secret", c_uint8 * HIL_KEY_SIZE),
                   ("chunk_time", c_double)])


HIL_COUNTERS = ("steps", "frames_sent", "send_errors", "datagrams", "received", "lost", "late", "malformed",
                "safe_state_steps", "overruns", "foreign", "forged", "duplicate", "out_of_order", "replayed",
                "challenges", "stale_challenges", "hellos")
# the BCU's loss (rb_hil_result): how often, when (steps), for how long, and what it cost
HIL_LOSS = ("losses", "lost_step", "last_valid_step", "lost_steps", "lost_lock_events")
HIL_TIMING = ("wakeup_p50_us", "wakeup_p99_us", "wakeup_max_us", "wakeup_mean_us", "work_mean_us",
              "work_p99_us", "work_max_us")


class HilResult(Structure):
    _fields_ = ([(n, c_uint64) for n in HIL_COUNTERS + HIL_LOSS] + _doubles("lost_lock_time", "lost_distance")
                + _doubles(*HIL_TIMING)
                + _doubles("time", "stopping_distance", "stopping_time")
                + [("braking", c_int), ("stopped", c_int), ("finished", c_int), ("events", c_uint64),
                   ("mismatch", c_int), ("bcu_config", c_uint32), ("bcu_cars", c_int), ("bcu_axles", c_int)])


class HilEvent(Structure):
    _fields_ = [("step", c_uint64), ("kind", c_int), ("text", c_char * HIL_LOG_TEXT)]


class FrameHeader(Structure):
    _fields_ = [("session", c_uint32), ("config", c_uint32), ("sequence", c_uint32), ("step", c_uint64),
                ("nonce", c_uint64), ("plant_nonce", c_uint64), ("n_cars", c_uint8), ("n_axles", c_uint8),
                ("type", c_uint8)]


class PlantFrame(Structure):
    _fields_ = ([("header", FrameHeader)] + [(n, c_float) for n in ("train_speed", "position",
                                                                    "main_reservoir_pressure")]
                + [(n, c_float * FRAME_MAX_AXLES) for n in ("wheel_speed", "cylinder_pressure")]
                + [("supply_pressure", c_float * FRAME_MAX_CARS)])


class BcuFrame(Structure):
    _fields_ = [("header", FrameHeader), ("brake_demand", c_float), ("pressure_demand", c_float * FRAME_MAX_CARS),
                ("hold", c_uint8 * FRAME_MAX_AXLES), ("vent", c_uint8 * FRAME_MAX_AXLES)]


_u8_p = POINTER(c_uint8)
rb_crc32 = _declare("rb_crc32", c_uint32, c_char_p, c_size_t)
rb_plant_frame_size = _declare("rb_plant_frame_size", c_size_t, c_int, c_int)
rb_bcu_frame_size = _declare("rb_bcu_frame_size", c_size_t, c_int, c_int)
rb_challenge_frame_size = _declare("rb_challenge_frame_size", c_size_t)
rb_plant_frame_encode = _declare("rb_plant_frame_encode", c_int, POINTER(PlantFrame), c_char_p, c_char_p, c_size_t,
                                 POINTER(c_size_t), _err_p)
rb_bcu_frame_encode = _declare("rb_bcu_frame_encode", c_int, POINTER(BcuFrame), c_char_p, c_char_p, c_size_t,
                               POINTER(c_size_t), _err_p)
rb_challenge_frame_encode = _declare("rb_challenge_frame_encode", c_int, POINTER(FrameHeader), c_char_p, c_char_p,
                                     c_size_t, POINTER(c_size_t), _err_p)
rb_frame_check = _declare("rb_frame_check", c_int, c_char_p, c_size_t, POINTER(FrameHeader), _err_p)
rb_frame_authentic = _declare("rb_frame_authentic", c_int, c_char_p, c_size_t, c_char_p)
rb_siphash24 = _declare("rb_siphash24", c_uint64, c_char_p, c_char_p, c_size_t)
rb_hil_session_key = _declare("rb_hil_session_key", None, c_char_p, c_uint32, c_uint64, c_uint64, c_char_p)
rb_plant_frame_decode = _declare("rb_plant_frame_decode", c_int, c_char_p, c_size_t, POINTER(PlantFrame), _err_p)
rb_bcu_frame_decode = _declare("rb_bcu_frame_decode", c_int, c_char_p, c_size_t, POINTER(BcuFrame), _err_p)
rb_hil_config_digest = _declare("rb_hil_config_digest", c_uint32, c_char_p, c_int, c_int, c_double)

rb_rt_request = _declare("rb_rt_request", c_int, c_int)
rb_hil_runner_size = _declare("rb_hil_runner_size", c_size_t)
rb_hil_safe_bcu = _declare("rb_hil_safe_bcu", c_int, POINTER(BcuParams), POINTER(BcuParams), _err_p)
rb_hil_runner_open = _declare("rb_hil_runner_open", c_int, POINTER(PlantParams), POINTER(HilConfig), c_char_p,
                              c_int, c_char_p, c_int, c_void_p, _err_p)
rb_hil_runner_advance = _declare("rb_hil_runner_advance", c_int, POINTER(PlantParams), POINTER(HilConfig),
                                 c_void_p, c_uint64, c_double_p, c_size_t, POINTER(c_size_t), POINTER(c_int),
                                 _err_p)
rb_hil_runner_kpis = _declare("rb_hil_runner_kpis", None, POINTER(PlantParams), c_void_p, POINTER(Kpis))
rb_hil_runner_result = _declare("rb_hil_runner_result", None, c_void_p, POINTER(HilResult))
rb_hil_runner_event = _declare("rb_hil_runner_event", c_int, c_void_p, c_uint64, POINTER(HilEvent))
rb_hil_runner_close = _declare("rb_hil_runner_close", None, c_void_p)


class HilFaultCommand(Structure):
    _fields_ = [("action", c_int), ("fault", Fault)]


rb_hil_runner_post_fault = _declare("rb_hil_runner_post_fault", c_int, c_void_p, POINTER(HilFaultCommand))
rb_hil_runner_fault_answer = _declare("rb_hil_runner_fault_answer", c_int, c_void_p, POINTER(c_uint64), c_char_p,
                                      c_size_t)
rb_hil_runner_port = _declare("rb_hil_runner_port", c_int, c_void_p)
rb_hil_channel_count = _declare("rb_hil_channel_count", c_int, c_int)
rb_hil_channel_info = _declare("rb_hil_channel_info", c_int, c_int, c_int, c_char_p, c_size_t, c_char_p,
                               c_size_t, _err_p)
rb_hil_bcu_size = _declare("rb_hil_bcu_size", c_size_t)
rb_hil_bcu_open = _declare("rb_hil_bcu_open", c_int, POINTER(BcuParams), POINTER(WspParams), POINTER(Scenario),
                           c_uint32, c_char_p, c_char_p, c_char_p, c_int, c_void_p, _err_p)
rb_hil_bcu_refusal = _declare("rb_hil_bcu_refusal", c_int, c_void_p, POINTER(c_uint32), POINTER(c_int),
                              POINTER(c_int), c_char_p, c_size_t)
rb_hil_bcu_port = _declare("rb_hil_bcu_port", c_int, c_void_p)
rb_hil_bcu_serve = _declare("rb_hil_bcu_serve", c_int, POINTER(BcuParams), POINTER(Scenario), c_void_p, c_double,
                            c_double, c_double, POINTER(c_int), _err_p)
rb_hil_bcu_close = _declare("rb_hil_bcu_close", None, c_void_p)
HIL_BCU_COUNTERS = ("received", "malformed", "stale", "sent", "send_errors", "cycles", "foreign", "refused", "forged",
                    "challenges")
rb_hil_bcu_counters = _declare("rb_hil_bcu_counters", None, c_void_p, c_uint64 * len(HIL_BCU_COUNTERS))

HIL_SNAPSHOT_COUNTERS = ("received", "lost", "late", "malformed", "foreign", "forged", "overruns")


class HilSnapshot(Structure):
    _fields_ = ([("step", c_uint64)] + _doubles("time", "speed", "position", "main_reservoir", "brake_demand")
                + [("safe", c_int), ("n_cars", c_int), ("n_axles", c_int)]
                + [(n, c_uint64) for n in HIL_SNAPSHOT_COUNTERS]
                + [(n, c_double * PLANT_MAX_CARS) for n in ("supply", "pressure_demand")]
                + [(n, c_double * PLANT_MAX_AXLES) for n in ("wheel_speed", "slip", "cylinder")]
                + [(n, c_uint8 * PLANT_MAX_AXLES) for n in ("hold", "vent")])


rb_hil_runner_snapshot = _declare("rb_hil_runner_snapshot", c_int, c_void_p, POINTER(HilSnapshot), c_int)

for _struct, _size in ((HilConfig, "rb_hil_config_size"), (HilResult, "rb_hil_result_size"),
                       (HilEvent, "rb_hil_event_size"), (HilSnapshot, "rb_hil_snapshot_size")):
    if ctypes.sizeof(_struct) != _declare(_size, c_size_t)():
        raise ImportError(f"{_size[:-5]}: ctypes size {ctypes.sizeof(_struct)} differs from the C core's; "
                          "src/railbrake/_core.py is out of date")

# ---------------------------------------------------------------- solenoid design model (rb_solenoid.h)

BH_MAX_POINTS = 32


class Solenoid(Structure):
    _fields_ = [(n, c_double) for n in ("turns", "resistance_20c", "resistance_tempco", "iron_length",
                                        "iron_area")] + [
        ("bh_points", c_int), ("bh_h", c_double * BH_MAX_POINTS), ("bh_b", c_double * BH_MAX_POINTS),
        ("pole_diameter", c_double), ("working_gaps", c_int)] + [
        (n, c_double) for n in ("fringing", "parasitic_gap", "parasitic_area", "leakage_permeance")]


class SolenoidState(Structure):
    _fields_ = [(n, c_double) for n in ("flux", "gap_flux", "flux_linkage", "inductance",
                                        "incremental_inductance", "force", "energy", "coenergy",
                                        "iron_flux_density")]


class SolenoidDrive(Structure):
    _fields_ = [(n, c_double) for n in ("voltage", "pwm_frequency", "duty", "temperature_c", "mass",
                                        "spring_rate", "spring_preload", "damping", "load_force", "gap_max",
                                        "gap_min")]


SOLENOID_SAMPLE_FIELDS = ("t", "voltage", "current", "flux_linkage", "gap", "velocity", "force", "e_electric",
                          "e_copper", "e_magnetic", "e_mechanical", "e_damping", "e_impact")


class SolenoidSample(Structure):
    _fields_ = [(n, c_double) for n in SOLENOID_SAMPLE_FIELDS]


rb_solenoid_check = _declare("rb_solenoid_check", c_int, POINTER(Solenoid), _err_p)
rb_solenoid_eval = _declare("rb_solenoid_eval", c_int, POINTER(Solenoid), c_double, c_double,
                            POINTER(SolenoidState), _err_p)
rb_solenoid_force_table = _declare("rb_solenoid_force_table", c_int, POINTER(Solenoid), c_double_p, c_int,
                                   c_double_p, c_int, POINTER(ForceTable), _err_p)
rb_solenoid_simulate = _declare("rb_solenoid_simulate", c_int, POINTER(Solenoid), POINTER(SolenoidDrive),
                                c_double, c_double, POINTER(SolenoidSample), c_size_t, _err_p)
rb_solenoid_steady_temperature = _declare("rb_solenoid_steady_temperature", c_int, POINTER(Solenoid), c_double,
                                          c_double, c_double, c_double, c_double_p, _err_p)
rb_solenoid_thermal_transient = _declare("rb_solenoid_thermal_transient", c_int, POINTER(Solenoid), c_double,
                                         c_double, c_double, c_double, c_double, c_double, c_size_t, c_double_p,
                                         c_size_t, _err_p)

for _struct, _size in ((Solenoid, "rb_solenoid_size"), (SolenoidState, "rb_solenoid_state_size"),
                       (SolenoidDrive, "rb_solenoid_drive_size"), (SolenoidSample, "rb_solenoid_sample_size")):
    if ctypes.sizeof(_struct) != _declare(_size, c_size_t)():
        raise ImportError(f"{_size[:-5]}: ctypes size {ctypes.sizeof(_struct)} differs from the C core's; "
                          "src/railbrake/_core.py is out of date")

# ---------------------------------------------------------------- reduced valve model (rb_valve_reduced.h)


class ReducedValve(Structure):
    _fields_ = [(n, c_double) for n in ("supply", "atmosphere", "volume", "temperature", "discharge_coefficient",
                                        "critical_ratio", "tau", "band", "area")]


rb_reduced_valve_steps = _declare("rb_reduced_valve_steps", c_int, POINTER(ReducedValve), c_double_p, c_double_p,
                                  c_size_t, c_double, c_double_p, c_size_t, c_double, c_double_p, _err_p)
if ctypes.sizeof(ReducedValve) != _declare("rb_reduced_valve_size", c_size_t)():
    raise ImportError("rb_reduced_valve: ctypes size differs from the C core's; src/railbrake/_core.py is out of date")
