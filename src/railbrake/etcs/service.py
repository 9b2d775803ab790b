"""The service brake's ETCS train data from whole-train runs (SUBSET-026 3.13.2.2.9, docs/etcs.md).

- A_brake_service(V): the nominal train's full service stop from the analysis' initial speed on
  dry rail, as a step function on the emergency model's speed steps, the speed kept for
  T_brake_service (the same reading as A_brake_emergency: railbrake.etcs.model.step_decelerations).
- A_brake_normal_service(V): the same from the normal service demand of data/etcs/service.yaml.
- T_brake_service: EN 14531-1's te = ta + tb/2 of the full service stop's total brake force
  (railbrake.simulation.response, as T_brake_emergency), with the BCU's service jerk limit when
  the train file gives one (brake_steps.service.jerk_limit_m_s3). T_bs = T_brake_service (SUBSET-026
  3.13.6.3); T_bs1 = T_bs2 = T_bs when the service brake feedback is not used (Q_NVSBFBPERM = No,
  and a train without that feedback): T_bs1 shifts the SBD to SBI1, T_bs2 the EBI to SBI2.
- Kn+ and Kn-: the gradient correction of the normal service deceleration (SUBSET-026 3.13.6.4:
  A_normal_service = A_brake_normal_service + A_gradient - Kn grad/1000): the gradient's own
  acceleration on the train, g M / (M + M_rot), so that the guidance curve is the train's normal
  service brake on any gradient (a driver holds the deceleration); M the train's mass, M_rot its
  wheelsets' equivalent rotating mass. M_rotating_nom = 100 M_rot / M (%).
- T_traction_cut_off: the train file's etcs block (with its source).

Every run is a whole run in the C core (simulation.run_structs, simulation.run).
"""

from __future__ import annotations

import warnings
from functools import cache
from importlib import resources

import numpy as np
import yaml

from railbrake import simulation, sizing
from railbrake.errors import InputError
from railbrake.etcs.model import step_decelerations
from railbrake.resolve import resolve
from railbrake.simulation import response
from railbrake.units import G_STANDARD, KMH


@cache
def settings() -> dict:
    return yaml.safe_load((resources.files("railbrake") / "data" / "etcs" / "service.yaml").read_text())


def _stop(train: str, cars: int, v0: float, condition: str, demand: float, marks: tuple) -> dict:
    sc = response.service_scenario(train, v0, condition, demand)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", sizing.SupplyWarning)
        four = simulation.structs(resolve(sc, cars))
    four[3].n_speed_marks = len(marks)
    for i, v in enumerate(marks):
        four[3].speed_mark[i] = v
    row = simulation.run_structs([four])[0]
    if isinstance(row, Exception) or row["stopping_distance_m"] is None:
        raise InputError(f"train {train}: the service stop ({demand:g}) from {v0 / KMH:.0f} km/h on {condition} "
                         f"did not stop ({row})")
    marks_m = row["speed_marks"]["distance_m"] if marks else []   # no mark below v0: one speed step
    return {"stopping_distance_m": row["stopping_distance_m"], "marks_m": marks_m, "stop_speed": four[3].stop_speed}


def build_up(train_obj, train: str, v0: float, condition: str) -> float:
    """T_brake_service: te = ta + tb/2 of the full service brake's total force (EN 14531-1)."""
    sc = response.service_scenario(train, v0, condition, 1.0, response.settings()["window_s"] + 0.1)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", sizing.SupplyWarning)
        result = simulation.run(sc, cars=len(train_obj.cars), train=train_obj)
        return response.measure(result, train_obj, step=("service", 1.0)).response   # toward full service


def service_data(model: dict) -> dict:
    """The service-brake train data of the train of a braking model (its JSON, as `etcs
    braking-model` writes it): the same train, cars, initial speed, dry rail and speed steps."""
    spec = model["analysis"]
    train_name, cars = spec["train"], spec.get("cars")
    base = simulation.emergency_scenario(train_name, 1.0, spec["dry_condition"])
    train = simulation.scenario_train(base, cars)
    if train.spec.etcs is None:
        raise InputError(f"train {train_name}: its file has no etcs block (traction_cut_off_s, source): "
                         "T_traction_cut_off is train data the brake model cannot give")
    v0 = spec["initial_speed_kmh"] * KMH if spec.get("initial_speed_kmh") else train.max_speed
    steps = model["A_brake_emergency"]["V_lower_kmh"]
    marks = tuple(v * KMH for v in sorted(steps, reverse=True) if 0 < v * KMH < v0)
    condition, n = spec["dry_condition"], len(train.cars)
    t_bs = build_up(train, train_name, v0, condition)
    curves = {}
    for key, demand in (("A_brake_service", 1.0), ("A_brake_normal_service", settings()["normal_service_demand"])):
        row = _stop(train_name, n, v0, condition, demand, marks)
        a = step_decelerations(v0, marks, row["stop_speed"], row, t_bs)
        if not np.all(a > 0.0):
            raise InputError(f"train {train_name}: the service stop ({demand:g}) from {v0 / KMH:.0f} km/h "
                             "did not brake on every speed step")
        curves[key] = [float(x) for x in a]
    mass, rotating = train.mass, train.rotating_mass
    kn = G_STANDARD * mass / (mass + rotating)
    etcs = train.spec.etcs
    return {"V_lower_kmh": list(steps), **curves,
            "normal_service_demand": settings()["normal_service_demand"],
            "T_brake_service_s": t_bs, "T_bs_s": t_bs, "T_bs1_s": t_bs, "T_bs2_s": t_bs,
            "Kn_plus_m_s2": kn, "Kn_minus_m_s2": kn,
            "M_rotating_nom_percent": 100.0 * rotating / mass, "mass_kg": mass, "rotating_mass_kg": rotating,
            "T_traction_cut_off_s": etcs.traction_cut_off_s,
            "traction_cut_off_implemented": etcs.traction_cut_off_implemented,
            "T_traction_cut_off_source": etcs.source,
            "initial_speed_kmh": v0 / KMH, "max_speed_kmh": train.max_speed / KMH, "train": train_name, "cars": n}
