"""YAML mutator over every preset file (scenarios, trains, adhesion conditions, profiles) and the
valve files: each variant is loaded as a user's file would be. Checks: no traceback (only
InputError), no hang (30 s per load), every error names the key that was mutated (or, for a
file-level mutation, the file and line), no non-finite number, Boolean or string is ever read as a
number, and every physically meaningless variant is refused.

The classes of the issue are all in: non-UTF-8 bytes, deep nesting, an alias bomb, duplicate keys,
NaN and infinities, 1e308, 1e-9 and 1e12 with units, Booleans and "1_000" where a number goes,
wrong types, unknown and missing keys, truncation; and per number of a preset, in its own unit:
negative, huge (x 1e10), tiny (x 1e-12) and percent-for-fraction (x 100); plus the inconsistent
pairs (PAIRS: overlapping zones, emergency with service, a fault's unused field, a demand that
never brakes, a train slower than the scenario, a supply above its reservoir, a relay step above
the supply, an error inside a referenced adhesion file). Each variant has a class; MEANINGLESS
classes must be refused, and every accepted variant must be of a class reviewed in ACCEPTED (the
reasons: tests/unit/fuzz/accepted_variants.md). A bounded sample in `make test`
(RAILBRAKE_FUZZ_CONFIG_VARIANTS, default 1000; the pairs are always in); `make fuzz` runs 20 000."""

from __future__ import annotations

import json
import math
import os
import random
import re
import signal
from importlib import resources

import pytest
import yaml

from railbrake import adhesion, scenario, sizing, vehicle
from railbrake.errors import InputError
from railbrake.valves import load_epv, load_relay

VARIANTS = int(os.environ.get("RAILBRAKE_FUZZ_CONFIG_VARIANTS", "1000"))
HANG_S = 30


def _valve(load):
    return lambda path: load(path)


LOADERS = {"scenarios": scenario.load, "trains": vehicle.load_train, "adhesion": adhesion.load_condition,
           "profiles": sizing.load_profile, "epv": _valve(load_epv), "relay": _valve(load_relay)}

# replacement values for a leaf, as YAML text; NOT_A_NUMBER must never be read as a number
NOT_A_NUMBER = [".nan", ".inf", "-.inf", "true", "false", '"1_000"', '"12"', "null", "[]", "{}", "abc"]
ODD_NUMBERS = ["1e308", "-1e308", "-1", "0", "5e-324", "1e-9", "1e12", "17", "-0.0", "123456789012345678901234567890"]
ODD_QUANTITIES = ["1e-9 s", "1e12 m/s", "-1 m/s", "0 s", "1e308 km/h", "nan s", "inf m/s", "250 kmh", "250"]

# Keys whose value may be negative: positions along the track, gradients, the ED curve's
# polynomial coefficients (a falling branch), a signed creep-force coefficient, degC.
SIGNED = {"start", "end", "gradient", "c0", "c1", "c2", "value", "air_temperature_c",
          "x_mm", "volume_cm3"}   # a relay membrane's positions and volumes either side of its centre
# Keys that are not physical quantities: no plausibility bound beyond their type.
NOT_PHYSICAL = {"seed"}
# Fractions (0..1): a value x 100 is a percent given where a fraction is asked.
FRACTIONS = {"service", "slip_threshold", "efficiency", "discharge_coefficient", "critical_ratio",
             "leading_factor", "sintered_low_speed", "release_fraction", "rel_tolerance", "peak",
             "peak_creep", "kA", "kS", "A", "mu0", "scale"}

# Text keys that name a preset, a file or one of a set of choices.
REFERENCES = {"preset", "condition", "profile", "design", "mounting", "kind", "formation", "load_case", "type",
              "solenoid_table"}

# classes that must be refused, whatever the key
MEANINGLESS = {"nan/inf", "not a number", "negative", "huge", "percent for a fraction", "inconsistent pair",
               "file-level", "dangling reference"}
# classes an accepted variant may belong to, each reviewed (tests/unit/fuzz/accepted_variants.md)
ACCEPTED = {
    "tiny": "x 1e-12 of a value whose range starts at 0 (a start time, a stop speed, a damping): "
            "physically the value 0, which is meaningful",
    "zero": "0 where 0 is inside the range (no damping, no slack, a demand at 0 s, no payload)",
    "odd number in range": "17, 1e-9, -1, 5e-324 or 0 where the key's range holds it (a gradient of "
                           "-1 permille is not given here: numbers without a unit are refused for quantities)",
    "percent, not a fraction": "x 100 of a value <= 1 of a key that is not a fraction and whose range "
                               "holds it (a 0.3 s ED response as 30 s is refused; 0.5 l as 50 l is a valid volume)",
    "negative of a signed key": "a zone or gradient start behind the train's front, a falling ED branch",
    "null for an optional key": "null where the key is optional: the documented default",
    "text key": "free text replaced by other text: an assumption, the conditions of a validity",
    "other Boolean": "true for false or false for true (ED blending, emergency)",
    "missing key": "an optional key left out (assumptions, validity, targets, title, faults): its default",
    "file-level, still valid": "a byte flip or truncation inside a comment or the source text",
}


def preset_files() -> list:
    data = resources.files("railbrake") / "data"
    kinds = {"scenarios": "scenarios", "trains": "trains", "adhesion": "adhesion", "profiles": "profiles"}
    files = [(kind, data / folder / p.name) for kind, folder in kinds.items()
             for p in sorted((data / folder).iterdir(), key=lambda q: q.name) if p.name.endswith(".yaml")]
    return files + [(kind, data / "valves" / f"{kind}.yaml") for kind in ("epv", "relay")]   # as overrides


def leaves(node, path=()):
    """(key path, node) of every scalar of a composed YAML document."""
    if isinstance(node, yaml.MappingNode):
        for key, value in node.value:
            yield from leaves(value, path + (key.value,))
    elif isinstance(node, yaml.SequenceNode):
        for i, item in enumerate(node.value):
            yield from leaves(item, path + (i,))
    else:
        yield path, node


def replace_value(text: str, node, new: str) -> str:
    """text with the scalar `node` replaced by `new` (by its character span)."""
    lines = text.splitlines(keepends=True)
    start = sum(len(l) for l in lines[:node.start_mark.line]) + node.start_mark.column
    end = sum(len(l) for l in lines[:node.end_mark.line]) + node.end_mark.column
    return text[:start] + new + text[end:]


def drop_block(lines, key):
    """lines without the top-level `key` and its indented block."""
    dropping = False
    for line in lines:
        if line.startswith(f"{key}:"):
            dropping = True
            continue
        if dropping and (line[:1] in (" ", "-", "\t") or not line.strip()):
            continue
        dropping = False
        yield line


def key_name(path) -> str:
    """The name an error about `path` must carry: its last key (a list item: its list's key)."""
    for part in reversed(path):
        if isinstance(part, str):
            return part
    return ""


_QUANTITY = re.compile(r"^([-+]?[0-9.]+(?:[eE][-+]?\d+)?)\s+(\S+)$")


def _number_of(node):
    """(number, unit or None) of a numeric scalar (a plain number or "<number> <unit>"), else None."""
    if node.tag.endswith((":int", ":float")):
        return float(node.value), None
    match = _QUANTITY.match(node.value) if node.tag.endswith(":str") else None
    return (float(match.group(1)), match.group(2)) if match else None


def _written(x: float, unit) -> str:
    text = repr(float(x)) if "e" in repr(float(x)) or "." in repr(float(x)) else f"{x:.1f}"
    text = text.replace("e", ".0e") if "e" in text and "." not in text.split("e")[0] else text
    text = re.sub(r"e(\d)", r"e+\1", text)   # YAML 1.1 floats: a dot and a signed exponent
    return f"{text} {unit}" if unit else text


def physical_variants(path, node):
    """(class, value text) of the physical classes of one numeric leaf, in its own unit."""
    found = _number_of(node)
    if found is None:
        return
    x, unit = found
    key = key_name(path)
    if key in NOT_PHYSICAL or x == 0.0:
        return
    yield ("negative of a signed key" if key in SIGNED else "negative"), _written(-abs(x), unit)
    yield "huge", _written(x * 1e10, unit)
    yield "tiny", _written(x * 1e-12, unit)
    if 0.0 < abs(x) <= 1.0:
        yield ("percent for a fraction" if key in FRACTIONS else "percent, not a fraction"), _written(x * 100, unit)


def generic_class(value: str, original, key: str) -> str:
    """The class of a generic replacement of a leaf whose original scalar is `original`."""
    if original.tag.endswith(":bool"):
        return "other Boolean" if value in ("true", "false") else "not a number"
    numeric = _number_of(original)
    if numeric is None and key in REFERENCES:   # names a preset, file or choice: other text names nothing
        return "null for an optional key" if value == "null" else "dangling reference"
    if numeric is None:   # free text (assumptions, the conditions of a validity)
        return "null for an optional key" if value == "null" else "text key"
    if value in (".nan", ".inf", "-.inf", "nan s", "inf m/s"):
        return "nan/inf"
    if value in ("1e308", "-1e308", "1e308 km/h", "123456789012345678901234567890", "1e12", "1e12 m/s"):
        return "huge"
    if value == "null":
        return "null for an optional key"
    if value in NOT_A_NUMBER:
        return "not a number"
    has_unit = numeric[1] is not None
    if value in ("0", "-0.0", "0 s"):
        return "zero"
    if has_unit != (" " in value):   # a unit missing, or one where a plain number goes
        return "not a number"
    return "odd number in range"


def _pair(text, old, new, count=1):
    assert old in text, (old, text[:80])
    return text.replace(old, new, count)


def pairs(kind: str, name: str, text: str, tmp_path):
    """(description, text, key an error must name) of the inconsistent pairs for one preset."""
    if kind == "scenarios":
        first = re.search(r"\{time: 0 s, (emergency: true|service: 1\.0)\}", text).group(0)
        yield "emergency with service", _pair(text, first, "{time: 0 s, emergency: true, service: 0.5}"), "demand"
        yield "demand never brakes", _pair(text, first, "{time: 0 s, service: 0.0}"), "demand"
        yield "demand after max_time", _pair(text, first, first + "\n  - {time: 3000 s, service: 0.5}"), "time"
        speed = re.search(r"initial_speed: (\d+) km/h", text)
        yield "stop speed above the start", _pair(text, "speed: 0.05 m/s", f"speed: {speed.group(1)} km/h"), "speed"
        zone = "\n  zones:\n    - {start: 100 m, end: 400 m, condition: wet}\n    - {start: 300 m, end: 500 m, condition: leaves}"
        cond = re.search(r"adhesion: \{condition: ([\w-]+)\}|adhesion:\n  condition: ([\w-]+)", text)
        body = re.sub(r"adhesion: \{condition: ([\w-]+)\}", r"adhesion:\n  condition: \1", text)
        body = re.sub(r"\n  zones:\n(    - .*\n)+", "\n", body)
        yield "overlapping zones", body.replace(f"condition: {cond.group(1) or cond.group(2)}",
                                                f"condition: {cond.group(1) or cond.group(2)}{zone}", 1), "zones"
        faults = "faults:\n  - {type: %s, car: 2, axle: 1, start: 1 s, %s}\n"
        for kind_, extra in (("hold_stuck_open", "leak_area: 5 mm^2"), ("cylinder_leak", "noise: 1 km/h"),
                             ("sensor_noisy", "leak_area: 5 mm^2"), ("car_isolated", "leak_area: 5 mm^2")):
            body = re.sub(r"faults:\n(  - .*\n)+", "", text)
            yield f"{kind_} with {extra.split(':')[0]}", body + faults % (kind_, extra), extra.split(":")[0]
        yield "ep_valve_failed on one axle", re.sub(r"faults:\n(  - .*\n)+", "", text) + \
            "faults:\n  - {type: ep_valve_failed, car: 2, axle: 1}\n", "axle"
        bad = tmp_path / f"{name}-bad-adhesion.yaml"
        bad.write_text((resources.files("railbrake") / "data" / "adhesion" / "wet.yaml").read_text()
                       .replace("mu0: ", "mu0: -", 1))
        yield "error inside a referenced adhesion file", re.sub(
            r"condition: ([\w-]+)", f"condition: {bad}", text, count=1), "mu0"
        slow = tmp_path / f"{name}-slow-train.yaml"
        train = re.search(r"preset: ([\w-]+)", text).group(1)
        slow.write_text((resources.files("railbrake") / "data" / "trains" / f"{train}.yaml").read_text()
                        .replace("max_speed_kmh: ", "max_speed_kmh: 51 #", 1))
        yield "train slower than the scenario", text.replace(f"preset: {train}", f"preset: {slow}", 1), "initial_speed"
        plain = re.sub(r"outputs:.*\n", "", text)
        yield "record of 1 ns", plain + "outputs: {record_interval: 1e-9 s}\n", "record_interval"
        yield "record over the size bound", re.sub(r"max_time: [\d.]+ s", "max_time: 3600 s", plain) + \
            "outputs: {record_interval: 1 ms}\n", "record_interval"
    elif kind == "trains":
        yield "supply above the main reservoir", re.sub(r"supply_pressure_bar: [\d.]+", "supply_pressure_bar: 8.0",
                                                        text), "supply_pressure_bar"
        yield "charged above the governor", re.sub(r"charged_bar: [\d.]+", "charged_bar: 9.8", text), "charged_bar"
        yield "pad friction in percent", re.sub(r"value: \[0\.4\d*,", "value: [42,", text, count=1), "value"
    elif kind == "adhesion":
        yield "validity reversed", re.sub(r"speed_kmh: \[(\d+), (\d+)\]", r"speed_kmh: [\2, \1]", text, count=1) \
            if "validity" in text else text + "validity: {speed_kmh: [200, 40], conditions: x, source: x}\n", \
            "speed_kmh"
    elif kind == "relay":
        yield "relay step above the supply", "control_step_bar: 9.0\n", "control_step_bar"
        yield "relay supply above the model's validity", "supply_bar: 80\n", "supply_bar"
    elif kind == "epv":
        yield "EP valve supply above the model's validity", "supply_bar: 12\n", "supply_bar"


def variants(kind: str, text: str, rng: random.Random):
    """(class, description, text or bytes, key that an error must name or None) for one preset file."""
    node = yaml.compose(text)
    scalars = [(p, n) for p, n in leaves(node) if p and key_name(p) not in ("source", "title", "schema", "name")
               and n.style not in (">", "|")]   # folded or literal blocks: prose (sources, findings)
    for path, leaf in scalars:
        dotted = ".".join(map(str, path))
        for value in NOT_A_NUMBER + ODD_NUMBERS + ODD_QUANTITIES:
            yield generic_class(value, leaf, key_name(path)), f"{dotted} = {value}", replace_value(text, leaf, value), key_name(path)
        for cls, value in physical_variants(path, leaf):
            yield cls, f"{dotted} = {value}", replace_value(text, leaf, value), key_name(path)
    lines = text.splitlines(keepends=True)
    top_keys = [n.value for n, _ in node.value]
    first_value = next(l for l in lines if re.match(r"^\w[\w-]*:", l)).split(":", 1)[1].split("#")[0].strip()
    for key in top_keys:
        yield "file-level", f"duplicate {key}", text + f"{key}: {first_value}\n", key
        kept = "".join(drop_block(lines, key))
        yield "missing key", f"missing {key}", kept, key   # refused unless optional
    yield "file-level", "unknown key", text + "no_such_key: 1\n", "no_such_key"
    yield "file-level", "non-UTF-8", text.encode()[:40] + b"\xff\xfe\xc3" + text.encode()[40:], None
    yield "file-level", "deep nesting", text + "deep: " + "[" * 3000 + "]" * 3000 + "\n", None
    bomb = ["a0: &a0 [x, x, x, x]"] + [f"a{i}: &a{i} [*a{i - 1}, *a{i - 1}, *a{i - 1}, *a{i - 1}]" for i in range(1, 13)]
    yield "file-level", "alias bomb", text + "\n".join(bomb) + "\n", None
    for _ in range(8):
        cut = rng.randrange(len(text))
        yield "file-level, still valid", f"truncated at {cut}", text[:cut], None
    raw = bytearray(text.encode())
    for _ in range(8):
        at = rng.randrange(len(raw))
        flipped = bytearray(raw)
        flipped[at] = rng.randrange(256)
        yield "file-level, still valid", f"byte {at} = 0x{flipped[at]:02x}", bytes(flipped), None


class _Hang(Exception):
    pass


def _alarm(signum, frame):
    raise _Hang()


def load(kind, path):
    previous = signal.signal(signal.SIGALRM, _alarm)
    signal.alarm(HANG_S)
    try:
        return LOADERS[kind](path), None
    except InputError as exc:
        return None, str(exc)
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, previous)


def numbers_read(obj, seen=None):
    """Every float reachable in a loaded object (dataclasses, pydantic models, lists, dicts)."""
    seen = set() if seen is None else seen
    if id(obj) in seen:
        return
    seen.add(id(obj))
    if isinstance(obj, float):
        yield obj
    elif isinstance(obj, dict):
        for v in obj.values():
            yield from numbers_read(v, seen)
    elif isinstance(obj, (list, tuple)):
        for v in obj:
            yield from numbers_read(v, seen)
    elif hasattr(obj, "__dict__") and not isinstance(obj, type):
        for v in vars(obj).values():
            yield from numbers_read(v, seen)


def build_pool(tmp_path, rng):
    """The inconsistent pairs (always run) and the sampled leaf and file-level variants."""
    fixed, pool = [], []
    for kind, path in preset_files():
        text = path.read_text()
        fixed += [(kind, path.name, "inconsistent pair", what, content, key)
                  for what, content, key in pairs(kind, path.name[:-5], text, tmp_path)]
        pool += [(kind, path.name, *v) for v in variants(kind, text, rng)]
    rng.shuffle(pool)
    return fixed, pool


def run_variants(chosen, tmp_path):
    """Outcome lists of loading each variant."""
    out = {k: [] for k in ("tracebacks", "hangs", "unnamed", "read_as_number", "accepted", "meaningless")}
    for n, (kind, name, cls, what, content, key) in enumerate(chosen):
        file = tmp_path / f"v{n}.yaml"
        file.write_bytes(content if isinstance(content, bytes) else content.encode())
        try:
            result, message = load(kind, file)
        except _Hang:
            out["hangs"].append(f"{name}: {what}")
            continue
        except Exception as exc:   # noqa: BLE001 - the test counts them
            out["tracebacks"].append(f"{name}: {what}: {type(exc).__name__}: {exc}")
            continue
        if message is not None:
            if str(file) not in message and "preset" not in message and "train " not in message:
                out["unnamed"].append(f"{name}: {what}: no file in {message!r}")
            elif key and key not in message:
                out["unnamed"].append(f"{name}: {what}: {message!r}")
            continue
        out["accepted"].append((cls, f"{name}: {what}"))
        if cls in MEANINGLESS or cls not in ACCEPTED:
            out["meaningless"].append(f"[{cls}] {name}: {what}")
        value = what.split(" = ", 1)[-1]
        if value in NOT_A_NUMBER and any(not math.isfinite(x) for x in numbers_read(result)):
            out["read_as_number"].append(f"{name}: {what}")
    return out


@pytest.mark.slow   # about 40 s for 1000 variants on a free core; not repeated under the sanitizers
def test_config_mutator(tmp_path):
    rng = random.Random(int(os.environ.get("RAILBRAKE_FUZZ_SEED", "1")))
    fixed, pool = build_pool(tmp_path, rng)
    chosen = fixed + pool[:max(VARIANTS - len(fixed), 0)]
    out = run_variants(chosen, tmp_path)
    accepted = out["accepted"]
    counts = {}
    for cls, _ in accepted:
        counts[cls] = counts.get(cls, 0) + 1
    print(f"{len(chosen)} variants of {len(fixed) + len(pool)} ({len(fixed)} pairs): {len(accepted)} accepted, "
          f"{len(chosen) - len(accepted)} refused; accepted by class: {counts}")
    print("accepted (for review):", *[f"[{c}] {w}" for c, w in accepted[:80]], sep="\n  ")
    listing = os.environ.get("RAILBRAKE_FUZZ_ACCEPTED_LIST")   # the whole list, for the review
    if listing:
        with open(listing, "w") as handle:
            handle.writelines(f"[{c}] {w}\n" for c, w in sorted(accepted))
    assert len(chosen) >= min(VARIANTS, 1000)
    assert not out["tracebacks"], out["tracebacks"][:10]
    assert not out["hangs"], out["hangs"]
    assert not out["unnamed"], out["unnamed"][:10]
    assert not out["read_as_number"], out["read_as_number"][:10]
    assert not out["meaningless"], out["meaningless"][:20]
    record = {"target": "config", "variants": len(chosen), "pool": len(fixed) + len(pool), "pairs": len(fixed),
              "accepted": len(accepted), "refused": len(chosen) - len(accepted), "classes_accepted": len(counts),
              "seed": os.environ.get("RAILBRAKE_FUZZ_SEED", "1")}
    print("fuzz-result", json.dumps(record))   # for docs/robustness.md (tools/fuzz_record.py, make fuzz-python)


def test_every_pair_is_refused_naming_its_key(tmp_path):
    """The inconsistent pairs alone (fast): each refused, naming its key."""
    fixed, _ = build_pool(tmp_path, random.Random(1))
    out = run_variants(fixed, tmp_path)
    assert len(fixed) >= 60
    assert not out["tracebacks"] and not out["unnamed"], (out["tracebacks"] + out["unnamed"])[:10]
    assert not out["accepted"], out["accepted"]
