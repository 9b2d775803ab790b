"""`make wheel`'s wheel installs and runs on every CPython it is for: one py3-none wheel tagged
manylinux2014 (manylinux_2_17: its C core, loaded with ctypes, needs glibc 2.17 at most), installed
with its dependencies into a fresh venv of each CPython 3.10-3.13 found on this machine (PATH, or
pyenv's versions), where `railbrake run` runs a stop on the wheel's own core.

The wheel is given by RAILBRAKE_WHEEL: `make wheel-test` builds it and runs these (minutes: a
fresh venv per Python, with numpy, scipy, pyarrow, dask, ... from the package index)."""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import zipfile
from pathlib import Path

import pytest

WHEEL = os.environ.get("RAILBRAKE_WHEEL")
pytestmark = [pytest.mark.slow,
              pytest.mark.skipif(not WHEEL, reason="RAILBRAKE_WHEEL not set: `make wheel-test` builds the wheel "
                                                   "and runs these")]
VERSIONS = ("3.10", "3.11", "3.12", "3.13")


def interpreter(version: str) -> str | None:
    """A CPython `version` that runs: pyenv's installed versions, else on PATH (a pyenv shim of a
    version not selected exits 127: not taken)."""
    root = Path(os.environ.get("PYENV_ROOT", Path.home() / ".pyenv")) / "versions"
    candidates = [str(p) for p in sorted(root.glob(f"{version}.*/bin/python{version}"))] if root.is_dir() else []
    candidates += [found] if (found := shutil.which(f"python{version}")) else []
    return next((c for c in candidates if subprocess.run([c, "-c", "pass"], capture_output=True).returncode == 0),
                None)


def test_the_wheel_is_tagged_manylinux_2_17_for_every_python_3():
    name = Path(WHEEL).name
    m = re.fullmatch(r"railbrake-[^-]+-(?P<py>[^-]+)-(?P<abi>[^-]+)-(?P<plat>[^-]+)\.whl", name)
    assert m, name
    assert m["py"] == "py3" and m["abi"] == "none"
    assert "manylinux_2_17_" in m["plat"] and "manylinux2014_" in m["plat"], m["plat"]
    with zipfile.ZipFile(WHEEL) as zf:
        assert any(n.endswith("railbrake/_lib/librailbrake_core.so") for n in zf.namelist())
        assert any(n.endswith("LICENSE") for n in zf.namelist())


@pytest.mark.parametrize("version", VERSIONS)
def test_the_wheel_installs_and_runs_in_a_fresh_venv(version, tmp_path):
    python = interpreter(version)
    if python is None:
        pytest.skip(f"no CPython {version} on this machine (PATH, pyenv)")
    venv = tmp_path / "venv"
    subprocess.run([python, "-m", "venv", str(venv)], check=True)
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "RAILBRAKE_CORE_LIBRARY")}
    install = subprocess.run([str(venv / "bin" / "python"), "-m", "pip", "install", "-q", WHEEL],
                             capture_output=True, text=True, env=env)
    assert install.returncode == 0, install.stderr[-3000:]
    where = subprocess.run([str(venv / "bin" / "python"), "-c", "from railbrake import _core; print(_core.lib._name)"],
                           capture_output=True, text=True, env=env, cwd=tmp_path)
    assert where.returncode == 0 and where.stdout.strip().startswith(str(venv)), (where.stdout, where.stderr)
    run = subprocess.run([str(venv / "bin" / "railbrake"), "run", "emergency-250-dry", "--cars", "1", "--json"],
                         capture_output=True, text=True, env=env, cwd=tmp_path)
    assert run.returncode == 0, run.stderr[-3000:]
    assert json.loads(run.stdout)["stopped"] is True
