"""Every shell command block of README.md and docs/*.md (a fence marked sh, bash, shell or console)
runs as written on the installed package, as a new user types it in a fresh clone: one folder for
all of them (holding `examples/` as the clone does), the blocks in the order README.md, then the
pages by name, each block as one bash script (`set -e`: its first failing command fails it), so a
command may use what an earlier one wrote (`railbrake plot out/rain8` after `railbrake run ... --out
out/rain8`) and a server started with `&` answers the commands after it (the README's BCU).

Shortened, and only so (SHORTEN, each with its reason): long runs get a documented option that
shortens them (`bench --runs`, `validate --fast`, `hil --duration`, `wsp tune --budget`, `etcs
braking-model --samples`, `etcs curves --samples`); the EN 15595 study is replaced by a copy of it
with fewer levels (same assessment and tuning ranges); the README's fixed UDP port by a free one.
Files the pages name as the user's own (`my-scenario.yaml`, `my-fmeca.yaml`, ...) are copies of
shipped files (FIXTURES).
The blocks not run are listed in NOT_RUN with the reason; a new block must be run or listed.
"""

from __future__ import annotations

import os
import re
import shutil
import signal
import socket
import subprocess
import sys
from pathlib import Path

import pytest
import yaml

import railbrake

REPO = Path(__file__).resolve().parents[3]
DATA = Path(railbrake.__file__).parent / "data"
FENCE = re.compile(r"^[ \t]*(`{3,}|~{3,})[ \t]*([^\s`]*)")
SHELL = {"sh", "bash", "shell", "console"}

# (file, the block's first line) -> why it is not run here
NOT_RUN = {
    ("README.md", "make demo"): "the repository's make targets: `make test` runs this test (and every other)",
    ("docs/campaigns.md", "dask scheduler"): "a cluster over several hosts (HEAD, study.yaml are the reader's): "
                                             "tests/unit/campaign runs studies on a scheduler address",
    ("docs/fmu.md", "python tools/build_fmusim.py"): "builds fmusim and the FMU checker from their sources "
                                                    "(downloaded): tests/unit/fmu/test_fmu_tools.py",
    ("docs/hil.md", "$ printf"): "a line sent to a running `hil --control` (its token and port are printed "
                                 "at its start): tests/unit/hil test the control socket",
}

# (pattern, replacement, why): the only changes made to a command
SHORTEN = [
    (r"(railbrake bench(?=\s)[^\n#&]*?)(\s*(#|$))", r"\1 --runs 1 --steps 2000\2", "bench: one timed run"),
    (r"(railbrake validate\b[^\n#&]*?)(\s*(#|$))", r"\1 --fast\2", "validate: the quick cases (--fast)"),
    (r"(railbrake hil(?=\s)[^\n#&]*?)(\s*(#|$))", r"\1 --duration 2\2", "hil: 2 s of the paced stop"),
    (r"--budget \d+", "--budget 2", "wsp tune: the default WSP and one trial"),
    (r"(railbrake etcs braking-model\b[^\n#&]*?)(\s*(#|$))",
     r"\1 --cars 4 --speed 40 --samples 4 --rare-samples 4 --run-budget 0 --force-conditions --workers 1\2",
     "etcs: 4 cars (the shipped common causes span 4) from 40 km/h (one speed step), 4 scatter runs per failure "
     "state (the fewest from which a state's regression on the pad friction leaves a bound below 1: "
     "railbrake.etcs.conditional), no runs added for the bounds, in the command's process (the test's workers fill the cores); the "
     "EN 15595 test condition forced below its 120 km/h (recorded in the warnings)"),
    (r"(railbrake etcs curves [^\n#&]*?)(\s*(#|$))", r"\1 --national short-nv.yaml\2",
     "etcs curves at M_NVEBCL 8 (the last --national given counts): the shortened 4-car models have no "
     "Kdry_rst at level 9 (see short_nv)"),
    (r"(railbrake etcs curves (?!out/)[^\n#&]*?)(\s*(#|$))",
     r"\1 --cars 4 --speed 80 --samples 4 --rare-samples 4 --run-budget 0 --workers 1 --force-conditions\2",
     "etcs curves of a train (its braking model made on the fly): 4 cars from 80 km/h (the last --speed given "
     "counts; the EN 15595 condition forced below 120 km/h), 4 scatter runs per failure state, no runs added for "
     "the bounds, in the command's process"),
    (r"\bwsp-en15595\b", "short-en15595.yaml", "the EN 15595 study: a copy with fewer levels (short_study)"),
]


def blocks() -> list[tuple[str, int, str]]:
    """(file, line, text) of every shell block, README.md first, then docs/*.md by name."""
    found = []
    for path in [REPO / "README.md", *sorted((REPO / "docs").glob("*.md"))]:
        lines = path.read_text(encoding="utf-8").splitlines()
        i = 0
        while i < len(lines):
            m = FENCE.match(lines[i])
            if not m:
                i += 1
                continue
            j = i + 1
            while j < len(lines) and not lines[j].strip().startswith(m.group(1)):
                j += 1
            if m.group(2) in SHELL:
                found.append((str(path.relative_to(REPO)), i + 1, "\n".join(lines[i + 1:j])))
            i = j + 1
    return found


def first_line(text: str) -> str:
    return next(line.strip() for line in text.splitlines() if line.strip())


def not_run(file: str, text: str) -> str | None:
    return next((why for (f, start), why in NOT_RUN.items() if f == file and first_line(text).startswith(start)),
                None)


def shortened(text: str, port: int) -> str:
    text = re.sub(r"\\\n\s*", " ", text)   # a command continued over lines: one line
    for pattern, replacement, _ in SHORTEN:
        text = re.sub(pattern, replacement, text, flags=re.M)
    text = text.replace("udp://127.0.0.1:5005", f"udp://127.0.0.1:{port}")
    return text


def short_nv(path: Path) -> None:
    """The national default values at M_NVEBCL 8: the shortened 4-car models' Kdry_rst at level 9 is 0
    (the shipped common-cause group of 4 cars is the whole shortened train), which has no curve."""
    text = (DATA / "etcs" / "national-default.yaml").read_text(encoding="utf-8")
    path.write_text(re.sub(r"(?m)^M_NVEBCL: 9\b", "M_NVEBCL: 8", text), encoding="utf-8")


def short_study(folder: Path) -> None:
    """wsp-en15595 with one controller, speed, brake and load and two adhesion cases, 2 cars."""
    study = yaml.safe_load((DATA / "studies" / "wsp-en15595.yaml").read_text(encoding="utf-8"))
    study["name"] = "short-en15595"
    study["set"]["train.cars"] = 2
    factors = study["factors"]
    factors["wsp.controller"] = ["threshold"]
    factors["initial_speed"] = ["200 km/h"]
    factors["adhesion_case"] = factors["adhesion_case"][:2]
    factors["brake"] = factors["brake"][:1]
    factors["train.load_case"] = ["crush"]
    study["assessment"]["criteria"]["utilisation_cases"] = ["low"]
    (folder / "short-en15595.yaml").write_text(yaml.safe_dump(study, sort_keys=False), encoding="utf-8")


FIXTURES = {   # files the pages name as the reader's own: copies of shipped ones
    "my-scenario.yaml": DATA / "scenarios" / "emergency-250-dry.yaml",
    "my-fmeca.yaml": DATA / "etcs" / "reliability-hs-emu.yaml",
    "my-tolerances.yaml": DATA / "etcs" / "scatter-hs-emu.yaml",
    "my-nv.yaml": DATA / "etcs" / "national-default.yaml",
}


@pytest.fixture(scope="module")
def clone(tmp_path_factory) -> Path:
    folder = tmp_path_factory.mktemp("fresh-clone")
    shutil.copytree(REPO / "examples", folder / "examples")
    for name, source in FIXTURES.items():
        shutil.copy(source, folder / name)
    short_nv(folder / "short-nv.yaml")
    short_study(folder)
    return folder


def free_udp_port() -> int:
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def run_block(script: str, cwd: Path, timeout: float = 600) -> subprocess.CompletedProcess:
    env = dict(os.environ, PATH=f"{Path(sys.executable).parent}{os.pathsep}{os.environ.get('PATH', '')}",
               MPLBACKEND="Agg")
    process = subprocess.Popen(["bash", "-e", "-x", "-c", script + "\nwait\n"], cwd=cwd, env=env, text=True,
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, start_new_session=True)
    try:
        out, err = process.communicate(timeout=timeout)
    finally:   # the block's servers (`... &`) end with it
        try:
            os.killpg(process.pid, signal.SIGTERM)
        except ProcessLookupError:
            pass
    return subprocess.CompletedProcess(process.args, process.returncode, out, err)


ALL = blocks()


def test_every_block_is_run_or_listed_with_its_reason():
    listed = {not_run(f, t) for f, _, t in ALL} - {None}
    assert len(listed) == len(NOT_RUN), f"NOT_RUN names a block that is gone: {sorted(NOT_RUN)} vs {sorted(listed)}"
    assert sum(not not_run(f, t) for f, _, t in ALL) >= 6   # the extraction finds the blocks


@pytest.mark.slow
@pytest.mark.parametrize("file, line, text", [b for b in ALL if not not_run(b[0], b[2])],
                         ids=[f"{f}:{n}" for f, n, t in ALL if not not_run(f, t)])
def test_block_runs_as_written(clone, file, line, text):
    script = "\n".join(re.sub(r"^\s*\$ ", "", row) for row in shortened(text, free_udp_port()).splitlines())
    done = run_block(script, clone)
    assert done.returncode == 0, (f"{file}, line {line}: exit {done.returncode}\n--- script\n{script}\n"
                                  f"--- stderr (tail)\n{done.stderr[-3000:]}")


def test_vehicle_page_error_examples_are_what_the_commands_print(tmp_path):
    """docs/vehicle.md's `$ railbrake ...` examples print the error lines under them, line number
    and all (my-train.yaml: the crh380a-8 preset's file with the motor car's tare in kg)."""
    preset = (DATA / "trains" / "crh380a-8.yaml").read_text(encoding="utf-8")
    motor = preset.index("\n  motor:")
    tare = preset.index("tare_t: 44.7", motor)
    (tmp_path / "my-train.yaml").write_text(preset[:tare] + "tare_t: 44700" + preset[tare + 12:], encoding="utf-8")
    page = (REPO / "docs" / "vehicle.md").read_text(encoding="utf-8")
    examples = re.findall(r"^    \$ (railbrake .*)\n    (error: .*)$", page, re.M)
    assert len(examples) == 3
    for command, expected in examples:
        done = run_block(command, tmp_path, timeout=120)
        assert done.returncode == 2 and expected in done.stderr.splitlines(), (command, done.stderr[-2000:])
