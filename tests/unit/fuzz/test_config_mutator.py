"""YAML mutator over every preset file (scenarios, trains, adhesion conditions, profiles): each
variant is loaded as a user's file would be. Checks: no traceback (only InputError), no hang (30 s
per load), every error names the key that was mutated (or, for a file-level mutation, the file and
line), and no non-finite number, Boolean or string is ever read as a number.

The classes of the issue are all in: non-UTF-8 bytes, deep nesting, an alias bomb, duplicate keys,
NaN and infinities, 1e308, 1e-9 and 1e12 with units, negative values, Booleans and "1_000" where a
number goes, wrong types, unknown and missing keys, truncation. A bounded sample in `make test`
(RAILBRAKE_FUZZ_CONFIG_VARIANTS, default 1000); `make fuzz` runs 20 000."""

from __future__ import annotations

import math
import os
import random
import signal
from importlib import resources

import pytest
import yaml

from railbrake import adhesion, scenario, sizing, vehicle
from railbrake.errors import InputError

VARIANTS = int(os.environ.get("RAILBRAKE_FUZZ_CONFIG_VARIANTS", "1000"))
# Train files whose range errors still come from the C core under its own names (no line, no YAML
# key): the train schema (railbrake.vehicle, branch `train`) should check these ranges itself. Each
# is still an InputError naming the file; listed so that a new case fails the test.
KNOWN_C_NAMES = ("low_speed_value = ", "wheelset.wheel_radius = ")
HANG_S = 30

LOADERS = {"scenarios": scenario.load, "trains": vehicle.load_train, "adhesion": adhesion.load_condition,
           "profiles": sizing.load_profile}

# replacement values for a leaf, as YAML text; NOT_A_NUMBER must never be read as a number
NOT_A_NUMBER = [".nan", ".inf", "-.inf", "true", "false", '"1_000"', '"12"', "null", "[]", "{}", "abc"]
ODD_NUMBERS = ["1e308", "-1e308", "-1", "0", "5e-324", "1e-9", "1e12", "17", "-0.0", "123456789012345678901234567890"]
ODD_QUANTITIES = ["1e-9 s", "1e12 m/s", "-1 m/s", "0 s", "1e308 km/h", "nan s", "inf m/s", "250 kmh", "250"]


def preset_files() -> list:
    data = resources.files("railbrake") / "data"
    return [(kind, data / kind / p.name) for kind in LOADERS
            for p in sorted((data / kind).iterdir(), key=lambda q: q.name) if p.name.endswith(".yaml")]


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


def variants(kind: str, text: str, rng: random.Random):
    """(description, text or bytes, key that an error must name or None) for one preset file."""
    node = yaml.compose(text)
    scalars = [(p, n) for p, n in leaves(node) if p and key_name(p) not in ("source", "title", "schema", "name")]
    for path, leaf in scalars:
        for value in NOT_A_NUMBER + ODD_NUMBERS + ODD_QUANTITIES:
            yield f"{'.'.join(map(str, path))} = {value}", replace_value(text, leaf, value), key_name(path)
    lines = text.splitlines(keepends=True)
    top_keys = [n.value for n, _ in node.value]
    for i, key in enumerate(top_keys):
        yield f"duplicate {key}", text + f"{key}: {lines[0].split(':', 1)[1].strip()}\n", key
        kept = "".join(drop_block(lines, key))
        yield f"missing {key}", kept, key
    yield "unknown key", text + "no_such_key: 1\n", "no_such_key"
    yield "non-UTF-8", text.encode()[:40] + b"\xff\xfe\xc3" + text.encode()[40:], None
    yield "deep nesting", text + "deep: " + "[" * 3000 + "]" * 3000 + "\n", None
    bomb = ["a0: &a0 [x, x, x, x]"] + [f"a{i}: &a{i} [*a{i - 1}, *a{i - 1}, *a{i - 1}, *a{i - 1}]" for i in range(1, 13)]
    yield "alias bomb", text + "\n".join(bomb) + "\n", None
    for _ in range(8):
        cut = rng.randrange(len(text))
        yield f"truncated at {cut}", text[:cut], None
    raw = bytearray(text.encode())
    for _ in range(8):
        at = rng.randrange(len(raw))
        flipped = bytearray(raw)
        flipped[at] = rng.randrange(256)
        yield f"byte {at} = 0x{flipped[at]:02x}", bytes(flipped), None


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


@pytest.mark.slow   # about 30 s for 1000 variants on a free core; not repeated under the sanitizers
def test_config_mutator(tmp_path):
    rng = random.Random(int(os.environ.get("RAILBRAKE_FUZZ_SEED", "1")))
    pool = []
    for kind, path in preset_files():
        text = path.read_text()
        pool += [(kind, path.name, *v) for v in variants(kind, text, rng)]
    rng.shuffle(pool)
    chosen = pool[:VARIANTS]
    tracebacks, hangs, unnamed, read_as_number, accepted = [], [], [], [], []
    for n, (kind, name, what, content, key) in enumerate(chosen):
        file = tmp_path / f"v{n}.yaml"
        file.write_bytes(content if isinstance(content, bytes) else content.encode())
        try:
            result, message = load(kind, file)
        except _Hang:
            hangs.append(f"{name}: {what}")
            continue
        except Exception as exc:   # noqa: BLE001 - the test counts them
            tracebacks.append(f"{name}: {what}: {type(exc).__name__}: {exc}")
            continue
        if message is not None:
            if str(file) not in message and "preset" not in message:
                unnamed.append(f"{name}: {what}: no file in {message!r}")
            elif key and key not in message and not any(c in message for c in KNOWN_C_NAMES):
                unnamed.append(f"{name}: {what}: {message!r}")
            continue
        accepted.append(f"{name}: {what}")
        value = what.split(" = ", 1)[-1]
        if value in NOT_A_NUMBER and any(not math.isfinite(x) for x in numbers_read(result)):
            read_as_number.append(f"{name}: {what}")
    print(f"{len(chosen)} variants of {len(pool)}: {len(accepted)} accepted, {len(chosen) - len(accepted)} refused")
    print("accepted (for review):", *accepted[:60], sep="\n  ")
    assert len(chosen) >= min(VARIANTS, 1000)
    assert not tracebacks, tracebacks[:10]
    assert not hangs, hangs
    assert not unnamed, unnamed[:10]
    assert not read_as_number, read_as_number[:10]
