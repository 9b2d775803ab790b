"""1000 instantiate/free cycles (every 100th with a short run) and the wrong calls of
fmu_driver.c, compiled with the FMU's own sources under AddressSanitizer + UBSan: no leak
(LeakSanitizer), no invalid access, every check held."""

import os
import subprocess
import zipfile
from pathlib import Path

from fmpy import read_model_description

from railbrake.fmu.binaries import FMI_HEADERS

DRIVER = Path(__file__).with_name("fmu_driver.c")


def test_instantiate_free_cycles_leak_nothing(fmu2, tmp_path):
    with zipfile.ZipFile(fmu2) as zf:
        zf.extractall(tmp_path)
    guid = read_model_description(str(tmp_path)).guid
    sources = sorted(str(p) for p in (tmp_path / "sources").glob("*.c"))
    driver = tmp_path / "driver"
    # the core's own warning flags (core/CMakeLists.txt); the FMI headers are the standard's
    built = subprocess.run(["cc", "-std=c99", "-g", "-O1", "-fsanitize=address,undefined", "-fno-omit-frame-pointer",
                            "-fno-sanitize-recover=all", "-Wall", "-Wextra", "-Werror", "-Wshadow",
                            "-Wstrict-prototypes", f"-I{tmp_path / 'sources'}", "-isystem", str(FMI_HEADERS),
                            str(DRIVER), *sources, "-o", str(driver), "-lm"], capture_output=True, text=True)
    assert built.returncode == 0, built.stderr
    env = dict(os.environ, ASAN_OPTIONS="detect_leaks=1:abort_on_error=0", LD_PRELOAD="")
    done = subprocess.run([str(driver), guid, "1000"], capture_output=True, text=True, env=env, timeout=120)
    assert done.returncode == 0, done.stdout + done.stderr
    assert "cycles 1000" in done.stdout and "failed checks 0" in done.stdout
    assert "LeakSanitizer" not in done.stderr
