"""EN 15595-style assessment of a campaign's runs (criteria in the study file's `assessment`).

Each case (same factor values but those of the reference, same seed) is compared with its
reference on dry rail:
- deceleration distance s_d = s - v0 te: the stopping distance less the distance run during the
  equivalent build-up time te = ta + tb/2 (EN 14531), te taken from the reference run's cylinder
  pressures so both runs lose the same build-up distance;
- its increase dS % = 100 (s_d - s_d,ref) / s_d,ref and Kwet = 100 / (100 + dS %) (ETCS
  engineering rules: Kwet_rst from EN 15595 tests);
- pass or fail: lock events, safety-timer trips, adhesion utilisation on the reduced-adhesion
  cases named in the criteria (the reference and a short patch are not adhesion-limited over the
  stop), and optional limits on dS % and air.
"""

from __future__ import annotations

import math

from railbrake.campaign.dataset import STATUS_OK

AIR_KPIS = ("air_drawn_kg", "air_consumed_kg")   # the first present is the air drawn


def _air_kpi(row: dict) -> str | None:
    return next((k for k in AIR_KPIS if row.get(k) is not None), None)


def _case_key(row: dict, factors: list[str], reference: dict) -> tuple:
    return tuple(row.get(f) for f in factors if f not in reference) + (row["seed"],)


def _is_reference(row: dict, reference: dict) -> bool:
    return all(row.get(k) == _ref_value(v) for k, v in reference.items())


def _ref_value(value):
    return value["name"] if isinstance(value, dict) else value


def _utilisation_applies(row: dict, criteria, reference: dict, is_reference: bool) -> bool:
    if is_reference:
        return False
    if criteria.utilisation_cases is None:
        return True
    return any(row.get(k) in criteria.utilisation_cases for k in reference)


def _below(value: float, limit: float, decimals: int = 3) -> str:
    """`value` with the decimals (at least `decimals`) that show it below `limit`: 0.8497, not 0.850."""
    while round(value, decimals) >= limit and decimals < 12:
        decimals += 1
    return f"{value:.{decimals}f}"


def _reasons(row: dict, criteria, utilisation_applies: bool) -> list[str]:
    reasons = []
    if (row.get("wheel_lock_events") or 0) > criteria.max_lock_events:
        reasons.append(f"{row['wheel_lock_events']:.0f} lock events > {criteria.max_lock_events}")
    if (row.get("safety_timer_trips") or 0) > criteria.max_safety_timer_trips:
        reasons.append(f"{row['safety_timer_trips']:.0f} safety-timer trips > {criteria.max_safety_timer_trips}")
    utilisation = row.get("adhesion_utilisation")
    if utilisation_applies and utilisation is not None and utilisation < criteria.min_utilisation:
        reasons.append(f"adhesion utilisation {_below(utilisation, criteria.min_utilisation)} < "
                       f"{criteria.min_utilisation}")
    ds = row.get("delta_s_pct")
    if criteria.max_delta_s_pct is not None and ds is not None and ds > criteria.max_delta_s_pct:
        reasons.append(f"dS {ds:.1f} % > {criteria.max_delta_s_pct} %")
    air = row.get("air_drawn_kg_assessed")
    if criteria.max_air_drawn_kg is not None and air is not None and air > criteria.max_air_drawn_kg:
        reasons.append(f"air {air:.2f} kg > {criteria.max_air_drawn_kg} kg")
    return reasons


def reference_values(assessment) -> dict:
    """The factor values of the reference runs ({factor: value or case name})."""
    return {k: _ref_value(v) for k, v in assessment.reference.items()}


def assess(rows: list[dict], factors: list[str], assessment, initial_speed) -> list[dict]:
    """rows: the dataset as dicts (SI); initial_speed(row) -> v0 in m/s. One dict per run."""
    reference = reference_values(assessment)
    refs = {_case_key(r, factors, reference): r for r in rows
            if r["status"] == STATUS_OK and _is_reference(r, reference)}
    out = []
    for row in sorted(rows, key=lambda r: (r.get("point", 0), r.get("replicate", 0))):
        case = dict(row)
        is_ref = _is_reference(row, reference)
        ref = refs.get(_case_key(row, factors, reference))
        case["reference"] = is_ref
        case["delta_s_pct"] = case["kwet"] = case["deceleration_distance_m"] = None
        air = _air_kpi(row)
        case["air_drawn_kg_assessed"] = row.get(air) if air else None
        s = row.get("stopping_distance_m")
        if row["status"] == STATUS_OK and ref is not None and s is not None and ref.get("stopping_distance_m"):
            te = ref.get("equivalent_response_time_s") or 0.0
            v0 = initial_speed(row)
            s_d, s_d_ref = s - v0 * te, ref["stopping_distance_m"] - v0 * te
            case["deceleration_distance_m"] = s_d
            case["delta_s_pct"] = 100.0 * (s_d - s_d_ref) / s_d_ref
            case["kwet"] = 100.0 / (100.0 + case["delta_s_pct"])
        if row["status"] != STATUS_OK:
            case["passed"], case["reasons"] = False, [f"run failed: {row.get('error')}"]
        else:
            applies = _utilisation_applies(row, assessment.criteria, reference, is_ref)
            reasons = _reasons(case, assessment.criteria, applies)
            if not row.get("stopped", 1):
                reasons.append("the train did not stop within the run's time")
            case["passed"], case["reasons"] = not reasons, reasons
        out.append(case)
    return out


def worst(cases: list[dict]) -> dict:
    """The figures a tuning optimises: worst dS % over the reduced-adhesion cases, locks, air."""
    assessed = [c for c in cases if not c["reference"]]
    ds = [c["delta_s_pct"] for c in assessed if c["delta_s_pct"] is not None]
    failed_runs = sum(c["status"] != STATUS_OK for c in cases)
    return {"worst_delta_s_pct": max(ds) if ds and not failed_runs else math.inf,
            "locks": int(sum(c.get("wheel_lock_events") or 0 for c in cases)),
            "air_drawn_kg": float(sum(c.get("air_drawn_kg_assessed") or 0.0 for c in cases)),
            "max_case_air_drawn_kg": float(max((c.get("air_drawn_kg_assessed") or 0.0 for c in cases), default=0.0)),
            "safety_timer_trips": int(sum(c.get("safety_timer_trips") or 0 for c in cases)),
            "passed": all(c["passed"] for c in cases), "failed_runs": failed_runs}


# The ranking's KPIs: (column, direction: +1 the larger the better, -1 the smaller). Kwet is the
# worst dS % transformed, so it is shown beside it but not ranked twice.
RANKED = (("worst_delta_s_pct", -1), ("adhesion_utilisation", +1), ("air_drawn_kg", -1),
          ("valve_switchings", -1), ("max_sliding_energy_kj", -1), ("safety_timer_trips", -1))


def _mean(values: list) -> float | None:
    return sum(values) / len(values) if values else None


def _level_figures(cases: list[dict]) -> dict:
    """One level's figures over its cases: worst dS % and its Kwet, mean utilisation over the
    utilisation cases (marked "utilisation_case"), mean air drawn and valve switchings per stop over the assessed (non-reference)
    cases, the largest sliding energy of one axle, timer trips and lock events over all its runs."""
    assessed = [c for c in cases if not c["reference"]]
    ok = [c for c in assessed if c["status"] == STATUS_OK]
    ds = [c["delta_s_pct"] for c in ok if c["delta_s_pct"] is not None]
    failed = sum(c["status"] != STATUS_OK for c in cases)
    worst_ds = max(ds) if ds and not failed else None
    used = [c for c in ok if c["utilisation_case"]]
    per_stop = lambda key: _mean([c[key] for c in ok if c.get(key) is not None])   # noqa: E731
    slid = [c["max_sliding_energy_kj"] for c in cases if c.get("max_sliding_energy_kj") is not None]
    return {"cases": len(assessed), "failed_cases": sum(not c["passed"] for c in cases), "failed_runs": failed,
            "worst_delta_s_pct": worst_ds, "mean_delta_s_pct": _mean(ds),
            "kwet": None if worst_ds is None else 100.0 / (100.0 + worst_ds),
            "adhesion_utilisation": _mean([c["adhesion_utilisation"] for c in used
                                           if c.get("adhesion_utilisation") is not None]),
            "air_drawn_kg": per_stop("air_drawn_kg_assessed"), "valve_switchings": per_stop("valve_switchings"),
            "max_sliding_energy_kj": max(slid) if slid else None,
            "safety_timer_trips": int(sum(c.get("safety_timer_trips") or 0 for c in cases)),
            "wheel_lock_events": int(sum(c.get("wheel_lock_events") or 0 for c in cases))}


def _ranks(values: list, direction: int) -> list[float]:
    """1 for the best; ties share their mean rank; a level without the figure ranks last."""
    keyed = [(-direction * v if v is not None else math.inf) for v in values]
    return [1.0 + sum(k < x for k in keyed) + 0.5 * (sum(k == x for k in keyed) - 1) for x in keyed]


def rank(cases: list[dict], factor: str, assessment) -> list[dict]:
    """The levels of `factor` (e.g. wsp.controller), best first: each one's figures over its cases
    (_level_figures), its rank on each KPI of RANKED and their mean ("rank"), ties broken by the
    worst dS %. `cases`: assess()'s output."""
    reference = reference_values(assessment)
    utilisation = assessment.criteria.utilisation_cases
    groups: dict = {}
    for c in cases:
        applies = utilisation is None or any(c.get(k) in utilisation for k in reference)
        groups.setdefault(c.get(factor), []).append({**c, "utilisation_case": applies})
    levels = [{factor: level, **_level_figures(group)} for level, group in groups.items()]
    ranked = [key for key, _ in RANKED if any(level[key] is not None for level in levels)]
    for key, direction in RANKED:
        if key in ranked:
            for level, r in zip(levels, _ranks([level[key] for level in levels], direction)):
                level[f"rank_{key}"] = r
    for level in levels:
        level["rank"] = sum(level[f"rank_{key}"] for key in ranked) / len(ranked) if ranked else None
        level["ranked_on"] = ranked
    worst_ds = lambda level: math.inf if level["worst_delta_s_pct"] is None else level["worst_delta_s_pct"]  # noqa: E731
    return sorted(levels, key=lambda level: (level["rank"] if level["rank"] is not None else math.inf, worst_ds(level)))
