"""The ETCS train data as OSRD loads it, and as a list of SUBSET-026 variables.

OSRD (OpenRailAssociation/osrd) reads a gamma train's braking model as `EtcsBrakeParams`
(editoast/schemas/src/rolling_stock/etcs_brake_params.rs; the core's RJSEtcsBrakeParams): eleven
required fields, `serde(deny_unknown_fields)`, no defaults. Curves are `SpeedIntervalValueCurve`s:
`boundaries` in m/s strictly increasing, one more `values`, all >= 0; k_dry and k_wet take
gamma_emergency's boundaries and values in [0, 1]; k_n_pos and k_n_neg values in [0, 10] m/s^2.
In OSRD's current rolling-stock layout the parameters sit in the ETCS entry of the rolling stock's
signalling systems (editoast/schemas/src/rolling_stock/supported_signaling_system.rs:
`SupportedSignalingSystem::EtcsLevel2 { brake_params }`, serde tag "type" = "ETCS_LEVEL2");
OSRD's railjson 3.x rolling stocks (e.g. its tests/data/rolling_stocks/etcs_level2_rolling_stock.json,
railjson_version 3.3) carry them at the top as `etcs_brake_params` (layout "legacy").

OSRD reads k_dry as it is: the confidence level is the data's, so it is exported at one M_NVEBCL,
by default OSRD's national default 9 (1 - 1e-9, NationalDefaultData).
"""

from __future__ import annotations

import math

from railbrake.errors import InputError
from railbrake.etcs import confidence
from railbrake.units import KMH

SCHEMA_FILES = ("editoast/schemas/src/rolling_stock/etcs_brake_params.rs at commit f902e39fbe59",
                "editoast/schemas/src/rolling_stock/supported_signaling_system.rs at commit 502288eeef65")
OSRD_VERSION = ("OSRD main branch, 2025 (OpenRailAssociation/osrd: the SupportedSignalingSystem enum with "
                "ETCS_LEVEL2 brake_params; EtcsBrakeParams with its 11 fields, as in railjson 3.3)")
FIELDS = ("gamma_emergency", "gamma_service", "gamma_normal_service", "k_dry", "k_wet", "k_n_pos", "k_n_neg",
          "t_traction_cut_off", "t_bs1", "t_bs2", "t_be")
CURVES = FIELDS[:7]
LAYOUTS = ("current", "legacy")
DEFAULT_LEVEL = 9   # OSRD's national default M_NVEBCL (1 - 1e-9)
K_RANGE = (0.0, 1.0)
KN_RANGE = (0.0, 10.0)


def _curve(boundaries: list, values: list) -> dict:
    return {"boundaries": list(boundaries), "values": [float(v) for v in values]}


def brake_params(model: dict, service: dict, level: int = DEFAULT_LEVEL) -> tuple[dict, list]:
    """OSRD's EtcsBrakeParams of a braking model (its JSON) and its service data
    (railbrake.etcs.service.service_data), k_dry at M_NVEBCL = level; and the notes of what was
    changed to fit OSRD's ranges (a coded factor above 1 exported as 1: the safe side)."""
    confidence.ebcl(level)
    steps = model["A_brake_emergency"]["V_lower_kmh"]
    if list(service["V_lower_kmh"]) != list(steps):
        raise InputError(f"service data on speed steps {service['V_lower_kmh']} km/h, the braking model's are {steps}")
    boundaries = [v * KMH for v in steps[1:]]
    notes = []

    def capped(name: str, values: list) -> list:
        out = []
        for v, x in zip(steps, values):
            if x > K_RANGE[1]:
                notes.append(f"{name} from {v:g} km/h: {x:g} exported as {K_RANGE[1]:g} (OSRD's range [0, 1]; "
                             "less deceleration promised: the safe side)")
            out.append(min(x, K_RANGE[1]))
        return out

    kdry = capped("k_dry", model["Kdry_rst"][level]["coded"])
    kwet = capped("k_wet", [model["Kwet_rst"]["coded"]] * len(steps))
    params = {
        "gamma_emergency": _curve(boundaries, model["A_brake_emergency"]["A_m_s2"]),
        "gamma_service": _curve(boundaries, service["A_brake_service"]),
        "gamma_normal_service": _curve(boundaries, service["A_brake_normal_service"]),
        "k_dry": _curve(boundaries, kdry),
        "k_wet": _curve(boundaries, kwet),
        "k_n_pos": _curve(boundaries, [service["Kn_plus_m_s2"]] * len(steps)),
        "k_n_neg": _curve(boundaries, [service["Kn_minus_m_s2"]] * len(steps)),
        "t_traction_cut_off": float(service["T_traction_cut_off_s"]),
        "t_bs1": float(service["T_bs1_s"]),
        "t_bs2": float(service["T_bs2_s"]),
        "t_be": float(model["T_brake_emergency_s"]),
    }
    return params, notes


def document(model: dict, service: dict, level: int = DEFAULT_LEVEL, layout: str = "current") -> dict:
    """The export file: the rolling stock's part OSRD reads (in `layout`), and what it follows."""
    if layout not in LAYOUTS:
        raise InputError(f"--osrd-layout = {layout!r}: one of {', '.join(LAYOUTS)}")
    params, notes = brake_params(model, service, level)
    about = {"osrd_version": OSRD_VERSION, "schema_files": list(SCHEMA_FILES), "layout": layout,
             "M_NVEBCL_of_k_dry": level, "EBCL": confidence.EBCL[level], "train": model["train"], "notes": notes,
             "how": "merge the other keys into the OSRD rolling stock (its mass, effort curves, ... are not "
                    "this file's); this 'railbrake' key is not OSRD's: drop it"}
    if layout == "legacy":
        return {"railbrake": about, "etcs_brake_params": params}
    return {"railbrake": about, "supported_signaling_systems": [{"type": "ETCS_LEVEL2", "brake_params": params}]}


def params_of(doc: dict, where: str = "the OSRD file") -> dict:
    """The EtcsBrakeParams of an export file, in either layout; where: the file, for the error."""
    if isinstance(doc, dict) and isinstance(doc.get("etcs_brake_params"), dict):
        return doc["etcs_brake_params"]
    for entry in doc.get("supported_signaling_systems", []) if isinstance(doc, dict) else []:
        if isinstance(entry, dict) and entry.get("type") == "ETCS_LEVEL2" and isinstance(entry.get("brake_params"), dict):
            return entry["brake_params"]
    raise InputError(f"{where}: no etcs_brake_params object (legacy layout) and no supported_signaling_systems "
                     "entry of type ETCS_LEVEL2 with a brake_params object (current layout)")


def check(params: dict, max_speed: float | None = None, documented: bool = True) -> list[str]:
    """OSRD's rules on an EtcsBrakeParams: the list of every rule broken. Its deserializer enforces
    the fields and each curve's form (one more value than boundaries, >= 0, boundaries strictly
    increasing); documented=True adds the rules its type documents ("should"): k_dry and k_wet on
    gamma_emergency's boundaries, factors in [0, 1], Kn in [0, 10] m/s^2, decelerations > 0 and
    boundaries below the maximum speed (m/s). OSRD's own ETCS test rolling stock gives k_dry on
    other boundaries than gamma_emergency's: OSRD loads it (documented=False)."""
    errors = []
    if not isinstance(params, dict):
        return [f"brake_params = {params!r}: must be an object"]
    errors += [f"missing field {f}" for f in FIELDS if f not in params]
    errors += [f"unknown field {f}" for f in params if f not in FIELDS]
    for name in CURVES:
        c = params.get(name)
        if c is None:
            continue
        if not isinstance(c, dict) or set(c) != {"boundaries", "values"}:
            errors.append(f"{name}: must be an object with exactly boundaries and values")
            continue
        b, v = c["boundaries"], c["values"]
        if not v:
            errors.append(f"{name}: at least one value")
        if len(b) != len(v) - 1:
            errors.append(f"{name}: {len(v)} values for {len(b)} boundaries (one more value than boundaries)")
        if any(not math.isfinite(x) or x < 0.0 for x in [*b, *v]):
            errors.append(f"{name}: boundaries and values must be finite and >= 0")
        if any(x >= y for x, y in zip(b, b[1:])):
            errors.append(f"{name}: boundaries must be strictly increasing")
        if not documented:
            continue
        if max_speed is not None and b and b[-1] >= max_speed:
            errors.append(f"{name}: boundary {b[-1]:g} m/s at or above the maximum speed {max_speed:g} m/s")
        if name.startswith("gamma") and any(x <= 0.0 for x in v):
            errors.append(f"{name}: decelerations must be > 0 m/s^2")
        if name in ("k_dry", "k_wet"):
            if "gamma_emergency" in params and b != params["gamma_emergency"].get("boundaries"):
                errors.append(f"{name}: boundaries must be gamma_emergency's")
            if any(not K_RANGE[0] <= x <= K_RANGE[1] for x in v):
                errors.append(f"{name}: values must lie in [0, 1]")
        if name in ("k_n_pos", "k_n_neg") and any(not KN_RANGE[0] <= x <= KN_RANGE[1] for x in v):
            errors.append(f"{name}: values must lie in [0, 10] m/s^2")
    for name in FIELDS[7:]:
        x = params.get(name)
        if x is None:
            continue
        if isinstance(x, bool) or not isinstance(x, (int, float)) or not math.isfinite(x) or x < 0.0:
            errors.append(f"{name} = {x!r}: must be a finite number of seconds >= 0")
    return errors


def train_data(model: dict, service: dict, level: int = DEFAULT_LEVEL) -> dict:
    """Every SUBSET-026 train-data variable of the braking model (gamma train), its value, unit and
    clause (UNISIG SUBSET-026-3 v4.0.0)."""
    steps = model["A_brake_emergency"]["V_lower_kmh"]

    def var(name, value, unit, clause, what):
        return {"name": name, "value": value, "unit": unit, "clause": clause, "what": what}

    return {"train": model["train"], "speed_steps_V_lower_kmh": steps, "variables": [
        var("A_brake_emergency", model["A_brake_emergency"]["A_m_s2"], "m/s^2 per speed step", "3.13.2.2.9",
            "nominal emergency brake deceleration, step function of speed"),
        var("T_brake_emergency", model["T_brake_emergency_s"], "s", "3.13.2.2.9; T_be 3.13.6.3",
            "equivalent emergency brake build-up time"),
        var("Kdry_rst", [{"M_NVEBCL": lv["M_NVEBCL"], "coded": lv["coded"]} for lv in model["Kdry_rst"]],
            "1 per speed step and M_NVEBCL", "3.13.2.2.9; A_brake_safe 3.13.6.2.1",
            "dry-rail correction factor at each confidence level"),
        var("Kwet_rst", model["Kwet_rst"]["coded"], "1", "3.13.2.2.9; A_brake_safe 3.13.6.2.1",
            "wet-rail correction factor"),
        var("A_brake_service", service["A_brake_service"], "m/s^2 per speed step", "3.13.2.2.9",
            "full service brake deceleration, step function of speed"),
        var("A_brake_normal_service", service["A_brake_normal_service"], "m/s^2 per speed step", "3.13.2.2.9; 3.13.6.4",
            f"normal service deceleration (guidance curve): the service brake at {service['normal_service_demand']:g} "
            "of full demand"),
        var("T_brake_service", service["T_brake_service_s"], "s", "3.13.2.2.9; T_bs 3.13.6.3",
            "equivalent service brake build-up time"),
        var("T_bs1", service["T_bs1_s"], "s", "3.13.9.3.3", "service brake time from SBD to SBI1 (= T_bs without feedback)"),
        var("T_bs2", service["T_bs2_s"], "s", "3.13.9.3.3", "service brake time from EBI to SBI2 (= T_bs without feedback)"),
        var("Kn+", service["Kn_plus_m_s2"], "m/s^2", "3.13.6.4", "gradient correction of the normal service deceleration, uphill"),
        var("Kn-", service["Kn_minus_m_s2"], "m/s^2", "3.13.6.4", "gradient correction of the normal service deceleration, downhill"),
        var("M_rotating_nom", service["M_rotating_nom_percent"], "%", "3.13.4.3", "nominal rotating mass (A_gradient)"),
        var("T_traction_cut_off", service["T_traction_cut_off_s"], "s", "3.13.9.3.2.3",
            f"traction cut-off command to no traction acceleration ({service['T_traction_cut_off_source']})"),
    ], "osrd_k_dry_level": level}


def _value(curve: dict, speed: float) -> float:
    """OSRD's SpeedIntervalValueCurve.getValue: the first interval whose boundary is >= speed."""
    for boundary, value in zip(curve["boundaries"], curve["values"]):
        if speed <= boundary:
            return value
    return curve["values"][-1]


def from_osrd(params: dict, max_speed: float, name: str = "osrd") -> tuple[dict, dict]:
    """A braking model and service data (the JSON forms railbrake.etcs.curves reads) from an OSRD
    EtcsBrakeParams and the rolling stock's max_speed (m/s): every curve on the union of all
    boundaries; k_dry, the level OSRD was given, at every M_NVEBCL; no M_rotating_nom (SUBSET-026's
    fixed values then apply); T_bs = t_bs2."""
    errors = check(params, max_speed, documented=False)
    if errors:
        raise InputError(f"{name}: not an EtcsBrakeParams OSRD loads: {'; '.join(errors)}")
    edges = sorted({b for c in CURVES for b in params[c]["boundaries"]})
    lower = [0.0, *edges]
    upper = [*edges, max_speed]
    mids = [(a + b) / 2.0 for a, b in zip(lower, upper)]   # OSRD's intervals are (b_i, b_i+1]

    def step(curve: str) -> list:
        return [float(_value(params[curve], v)) for v in mids]

    kdry = step("k_dry")
    steps_kmh = [v / KMH for v in lower]
    model = {"train": name, "A_brake_emergency": {"V_lower_kmh": steps_kmh, "A_m_s2": step("gamma_emergency")},
             "T_brake_emergency_s": float(params["t_be"]),
             "Kdry_rst": [{"M_NVEBCL": i, "coded": kdry} for i in range(len(confidence.EBCL))],
             "Kwet_rst": {"coded": min(step("k_wet"))}}
    if len(set(step("k_wet"))) > 1:
        raise InputError(f"{name}: k_wet varies with speed; railbrake's braking model has one Kwet_rst")
    kn_pos, kn_neg = step("k_n_pos"), step("k_n_neg")
    service = {"V_lower_kmh": steps_kmh, "A_brake_service": step("gamma_service"),
               "A_brake_normal_service": step("gamma_normal_service"),
               "T_bs_s": float(params["t_bs2"]), "T_bs1_s": float(params["t_bs1"]), "T_bs2_s": float(params["t_bs2"]),
               "Kn_plus_m_s2": min(kn_pos), "Kn_minus_m_s2": max(kn_neg), "M_rotating_nom_percent": None,
               "T_traction_cut_off_s": float(params["t_traction_cut_off"]), "traction_cut_off_implemented": True,
               "initial_speed_kmh": max_speed / KMH, "max_speed_kmh": max_speed / KMH}
    return model, service
