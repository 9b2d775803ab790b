"""Preset runs bit for bit against the code before the layering refactor (issue 42).

The refactor moved modules and C functions between files; it must change no value. The digests in
tests/data/bit_for_bit.json were computed by this file's `digests()` at the commit it names, before
the change: each run's KPIs (exactly, as JSON numbers round-trip) and a SHA-256 over its output
channels' names and float64 bytes. A later change of the model that moves a value on purpose
regenerates them (`python tests/unit/architecture/test_bit_for_bit.py`, with the reason in the
commit); the figures are a regression guard, never a validation.
"""

from __future__ import annotations

import hashlib
import json
import subprocess
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest

DATA = Path(__file__).resolve().parents[2] / "data" / "bit_for_bit.json"
STUDY = Path(__file__).resolve().parents[1] / "campaign" / "data" / "small.yaml"
# (scenario, cars, kernel, overrides): 1 and 8 cars, dry and wet, rail cleaned cell by cell, a fault, a
# service step, the three WSP controllers, the conditioning mode
RUNS = [("emergency-250-dry", 1, None, ()), ("emergency-250-dry", 8, None, ()),
        ("emergency-250-dry", 2, "portable", ()), ("emergency-300-heavy-rain", 1, None, ()),
        ("service-200-wet", 1, None, ()), ("emergency-300-leaves-patch", 1, None, ()),
        ("fault-vent-valve-stuck", 4, None, ()),
        ("emergency-300-heavy-rain", 1, None, ("wsp.controller=slip_setpoint",)),
        ("emergency-300-heavy-rain", 2, None, ("wsp.controller=decel_slip_speed", "wsp.conditioning_mode=true"))]


def _key(scenario: str, cars: int, kernel: str | None, sets: tuple) -> str:
    return "/".join([scenario, str(cars), kernel or "auto", *sets])


# channels added after the digests' commit, outside the digest so that it still covers every
# earlier channel unchanged: each axle's WSP state (issue 40, the MDF4 wsp_trip events)
ADDED_CHANNELS = ("wsp_mode_",)


def _outputs_digest(result) -> str:
    digest = hashlib.sha256()
    for name in sorted(n for n in result.outputs if not n.startswith(ADDED_CHANNELS)):
        digest.update(name.encode())
        digest.update(np.ascontiguousarray(result.outputs[name], dtype=np.float64).tobytes())
    return digest.hexdigest()


def _run(scenario: str, cars: int, kernel: str | None, sets: tuple) -> dict:
    from railbrake.resolve import resolve
    from railbrake.simulation import run
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")   # the conditions' validity notes: not the point here
        result = run(resolve(scenario, cars, sets), kernel=kernel)
    return {"kpis": result.kpis, "rows": len(result.time), "outputs": _outputs_digest(result)}


def _study() -> list:
    """The KPIs of a small study's runs (1 car, 2 speeds x 2 conditions x 2 seeds), as a worker
    makes them: resolved with the plan's overrides, run together in one C call."""
    from railbrake.campaign.plan import plan
    from railbrake.campaign.study import load
    from railbrake.campaign.worker import execute_batch
    study = load(STUDY)
    runs = [{"key": r.key, "index": r.index, "point": r.point, "replicate": r.replicate, "seed": r.seed,
             "block": r.block, "sample": r.sample, "sets": r.sets, "factors": r.factors} for r in plan(study)]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        rows = execute_batch(study.spec.base, runs, {"timeseries": False})["rows"]
    # not the run's key: it hashes the core's build, which a moved C function changes
    return [{"point": r["point"], "replicate": r["replicate"], "seed": r["seed"], "status": r["status"],
             "kpis": r.get("kpis")} for r in rows]


def digests() -> dict:
    return {"runs": {_key(*r): _run(*r) for r in RUNS}, "study": _study()}


def _canonical(value):
    return json.loads(json.dumps(value))   # tuples -> lists, as stored


@pytest.fixture(scope="module")
def stored():
    return json.loads(DATA.read_text())


@pytest.mark.parametrize("run", RUNS, ids=lambda r: _key(*r))
def test_preset_run_bit_for_bit(stored, run):
    key = _key(*run)
    now, before = _canonical(_run(*run)), stored["runs"][key]
    assert now["rows"] == before["rows"], f"{key}: rows changed (code of {stored['commit']})"
    assert now["kpis"] == before["kpis"], f"{key}: KPIs changed (code of {stored['commit']})"
    assert now["outputs"] == before["outputs"], f"{key}: output arrays changed (code of {stored['commit']})"


def test_study_kpis_bit_for_bit(stored):
    assert _canonical(_study()) == stored["study"], f"study KPIs changed (code of {stored['commit']})"


if __name__ == "__main__":   # regenerate, recording the commit the digests come from
    commit = subprocess.run(["git", "rev-parse", "HEAD"], capture_output=True, text=True, check=True,
                            cwd=DATA.parent).stdout.strip()
    DATA.write_text(json.dumps({"commit": commit, "note": "digests() of test_bit_for_bit.py at this commit",
                                **digests()}, indent=1, sort_keys=True) + "\n")
    print(f"{DATA}: written at {commit}", file=sys.stderr)
