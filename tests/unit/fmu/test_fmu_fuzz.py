"""The FMI call-sequence fuzzer (tests/fuzz/fmi_fuzz.c) against the FMU's own sources, built under
AddressSanitizer + UBSan: random sequences of FMI 2 / FMI 3 calls with random arguments; no
sanitizer report, no call accepted in a state the standard forbids, no OK with a non-finite output.

A bounded smoke run here (a few seconds per version); `make fuzz` sets
RAILBRAKE_FUZZ_FMI_CALLS=1000000 per version."""

import os
import subprocess
import zipfile
from pathlib import Path

import pytest

from railbrake.fmu import export_fmu
from railbrake.fmu.binaries import FMI_HEADERS
from railbrake.fmu.export import c_sources_dir

FUZZER = Path(__file__).resolve().parents[2] / "fuzz" / "fmi_fuzz.c"
CALLS = int(os.environ.get("RAILBRAKE_FUZZ_FMI_CALLS", "30000"))
SEED = int(os.environ.get("RAILBRAKE_FUZZ_SEED", "1"))
SANITIZE = ["-g", "-O1", "-fsanitize=address,undefined", "-fno-omit-frame-pointer", "-fno-sanitize-recover=all"]
WARNINGS = ["-Wall", "-Wextra", "-Werror", "-Wshadow"]


def _cc(*args, cwd):
    done = subprocess.run(["cc", "-std=c99", *SANITIZE, *WARNINGS, *args], capture_output=True, text=True, cwd=cwd)
    assert done.returncode == 0, done.stderr


@pytest.fixture(scope="module")
def plant_objects(tmp_path_factory):
    """The 2-car plant's FMU sources (coupler parameters live), compiled once for both versions:
    (folder, object files without the FMI layer)."""
    folder = tmp_path_factory.mktemp("fmi_fuzz")
    fmu = export_fmu("emergency-250-dry", folder / "plant.fmu", "2", cars=2, binary=False)
    with zipfile.ZipFile(fmu) as zf:
        zf.extractall(folder / "fmu")
    sources = folder / "fmu" / "sources"
    common = sorted(p for p in sources.glob("*.c") if p.name != "fmi2.c")
    _cc("-c", f"-I{sources}", "-isystem", str(FMI_HEADERS), *map(str, common), cwd=folder)
    return folder, [str(folder / (p.stem + ".o")) for p in common]


@pytest.mark.slow
@pytest.mark.parametrize("version", ["2", "3"])
def test_fmi_call_sequences(version, plant_objects):
    folder, objects = plant_objects
    sources = folder / "fmu" / "sources"
    fuzzer = folder / f"fmi{version}_fuzz"
    _cc(f"-DFUZZ_FMI={version}", f"-I{sources}", "-isystem", str(FMI_HEADERS), str(FUZZER),
        str(c_sources_dir() / "fmi" / f"fmi{version}.c"), *objects, "-o", str(fuzzer), "-lm", cwd=folder)
    env = dict(os.environ, ASAN_OPTIONS="detect_leaks=1", UBSAN_OPTIONS="print_stacktrace=1", LD_PRELOAD="")
    done = subprocess.run([str(fuzzer), str(CALLS), str(SEED)], capture_output=True, text=True, env=env,
                          timeout=3600)
    print(done.stdout)
    assert done.returncode == 0, done.stdout + done.stderr[-4000:]
    assert f"FMI {version}: calls" in done.stdout and "violations 0" in done.stdout
    assert "Sanitizer" not in done.stderr and "runtime error" not in done.stderr
