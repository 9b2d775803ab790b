"""`campaign plan` refuses a design above the run limit before drawing it (issue 31, part 4): the
message gives the run count and estimates of time and memory; --max-runs raises the limit. The
wall-clock time of the refusal is measured in bench/bench_plan_limit.py (timings are not asserted
here); its memory is."""

import os
import subprocess
import sys
from pathlib import Path

import pytest
from typer.testing import CliRunner

from railbrake.campaign import budget, study
from railbrake.cli import app
from railbrake.errors import InputError

runner = CliRunner()
RAILBRAKE = str(Path(sys.executable).parent / "railbrake")
HEAD = "schema: railbrake.study/1\nname: big\nbase: emergency-250-dry\n"
LHS = HEAD + "factors:\n  initial_speed: {low: 100 km/h, high: 250 km/h}\ndesign: {kind: latin-hypercube, samples: 1000000000}\n"
GRID = HEAD + ("factors:\n  initial_speed: {low: 100 km/h, high: 250 km/h, levels: 1000}\n"
               "  wsp.slip_threshold: {low: 0.002, high: 0.05, levels: 1000}\n"
               "  wsp.safety_time: {low: 1 s, high: 5 s, levels: 1000}\ndesign: {kind: grid}\n")
SEEDS = HEAD + "factors:\n  initial_speed: [100 km/h, 200 km/h]\ndesign: {kind: grid}\nseeds: 1000000000\n"
LEVELS = HEAD + "factors:\n  initial_speed: {low: 100 km/h, high: 250 km/h, levels: 1000000000}\ndesign: {kind: grid}\n"


@pytest.mark.parametrize("text, where, runs", [
    (LHS, "line 6: design.samples", "1,000,000,000 runs (latin-hypercube of 1000000000 samples x 1 seed)"),
    (GRID, "line 8: design", "1,000,000,000 runs (grid of 1000 x 1000 x 1000 levels x 1 seed)"),
    (SEEDS, "line 7: seeds", "2,000,000,000 runs (grid of 2 levels x 1000000000 seeds)"),
])
def test_a_huge_design_is_refused_with_its_size_and_cost(tmp_path, text, where, runs):
    path = tmp_path / "big.yaml"
    path.write_text(text)
    out = runner.invoke(app, ["campaign", "plan", str(path)])
    assert out.exit_code == 2
    message = " ".join(out.output.split())
    assert f"{path}, {where}: {runs} exceed the limit of {budget.MAX_RUNS:,} runs" in message
    assert "of memory" in message and "of CPU time" in message and "--max-runs N" in message


def test_a_huge_range_is_refused_before_its_levels_are_made(tmp_path):
    path = tmp_path / "big.yaml"
    path.write_text(LEVELS)
    with pytest.raises(InputError, match=r"factors.initial_speed.levels = 1000000000: more levels than the limit"):
        study.load(path)


@pytest.mark.skipif("libasan" in os.environ.get("LD_PRELOAD", ""),
                    reason="under AddressSanitizer the process's RSS holds its shadow memory (make pytest runs it)")
def test_the_refusal_stays_small_in_memory(tmp_path):
    """The whole `campaign plan` process of a 10^9-run design peaks under 200 MB (max RSS)."""
    path = tmp_path / "big.yaml"
    path.write_text(LHS)
    probe = ("import resource, subprocess, sys; "
             f"r = subprocess.run([{RAILBRAKE!r}, 'campaign', 'plan', {str(path)!r}], capture_output=True); "
             "print(r.returncode, resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss)")
    code, max_rss_kb = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True,
                                      timeout=120).stdout.split()
    assert int(code) == 2 and int(max_rss_kb) < 200 * 1024


def test_max_runs_raises_or_lowers_the_limit():
    from railbrake.simulation import WSP_CONTROLLERS   # the preset runs every controller
    c = len(WSP_CONTROLLERS)
    n = c * 2 * 5 * 2 * 3
    with pytest.raises(InputError, match=rf"{n} runs \(grid of {c} x 2 x 5 x 2 x 3 levels x 1 seed\) exceed the "
                                         rf"limit of {n - 1}"):
        study.load("wsp-en15595", max_runs=n - 1)
    assert study.load("wsp-en15595", max_runs=n).max_runs == n
    out = runner.invoke(app, ["campaign", "plan", "wsp-en15595", "--max-runs", str(n)])
    assert out.exit_code == 0 and f"{n} runs" in out.output
    with pytest.raises(InputError, match="max_runs = 0: must be >= 1"):
        study.load("wsp-en15595", max_runs=0)
