"""Binaries for the targets integrators use, all built on this machine (`--platforms linux64,win64,
aarch64-linux`, the zig toolchain): each exports only the FMI API and is built for its machine; the
linux ones need nothing beyond glibc 2.17; the win64 one, run under Wine by a small C driver
cross-compiled too, gives the linux64 binary's outputs over a whole emergency stop (within 1e-12
relative)."""

import os
import shutil
import subprocess
import sys
import zipfile
from pathlib import Path

import numpy as np
import pytest
from fmpy import read_model_description

from railbrake.fmu import export_fmu
from railbrake.fmu.binaries import FMI_HEADERS, exported_symbols, glibc_versions, have_zig

pytestmark = pytest.mark.skipif(not have_zig(), reason="the cross builds need the zig toolchain (extra 'fmu', "
                                "installed by `make install`)")
DRIVER = Path(__file__).with_name("stop_driver.c")
STOP_SPEED, MAX_TIME = 0.05, 200.0        # m/s, s: emergency-250-dry's stop criteria
OUTPUTS = ("speed", "position", "cylinder_c1a1", "wheel_speed_c1a1")
ELF_MACHINE = {"linux64": 62, "aarch64-linux": 183}   # e_machine: EM_X86_64, EM_AARCH64 (ELF gABI)
PE_AMD64 = 0x8664                                        # IMAGE_FILE_MACHINE_AMD64 (PE format)


def wine():
    """Debian's wine64 loader (make test installs it when missing and run as root), or None."""
    for candidate in (shutil.which("wine64"), shutil.which("wine"), "/usr/lib/wine/wine64"):
        if candidate and Path(candidate).is_file() and os.access(candidate, os.X_OK):
            return candidate
    return None


@pytest.fixture(scope="module")
def unzipped(tmp_path_factory):
    folder = tmp_path_factory.mktemp("platforms")
    path = export_fmu("emergency-250-dry", folder / "plant.fmu", "2", cars=1,
                      platforms=("linux64", "win64", "aarch64-linux"))
    with zipfile.ZipFile(path) as zf:
        zf.extractall(folder / "unzipped")
    return folder / "unzipped"


def binary(unzipped, platform):
    files = list((unzipped / "binaries" / platform).iterdir())
    assert len(files) == 1, files       # the binary alone, no import library or debug file beside it
    return files[0]


@pytest.mark.parametrize("platform", ["linux64", "win64", "aarch64-linux"])
def test_each_binary_is_built_for_its_machine_and_exports_only_the_fmi_api(unzipped, platform):
    path = binary(unzipped, platform)
    head = path.read_bytes()[:4096]
    if platform == "win64":
        pe = int.from_bytes(head[0x3C:0x40], "little")
        assert head[:2] == b"MZ" and head[pe:pe + 4] == b"PE\0\0"
        assert int.from_bytes(head[pe + 4:pe + 6], "little") == PE_AMD64
    else:
        assert head[:4] == b"\x7fELF" and int.from_bytes(head[18:20], "little") == ELF_MACHINE[platform]
        assert max(glibc_versions(path)) <= (2, 17)
    names = exported_symbols(path)
    assert len(names) > 30 and all(n.startswith("fmi2") for n in names), names


def _run_stop(command, unzipped, library, env=None):
    md = read_model_description(str(unzipped))
    vrs = [str(next(v.valueReference for v in md.modelVariables if v.name == n)) for n in OUTPUTS]
    done = subprocess.run([*command, str(library), md.guid, *vrs, str(STOP_SPEED), str(MAX_TIME)],
                          capture_output=True, text=True, timeout=600, env=env)
    assert done.returncode == 0, done.stderr[-2000:]
    return np.loadtxt(done.stdout.splitlines())


@pytest.mark.skipif(wine() is None, reason="Wine is not installed: `make test` installs Debian's wine64 when run "
                    "as root; otherwise install it to run the win64 binary")
def test_win64_binary_under_wine_equals_linux64_over_a_whole_stop(unzipped, tmp_path):
    native_driver, windows_driver = tmp_path / "stop_driver", tmp_path / "stop_driver.exe"
    subprocess.run(["cc", "-std=c99", "-O2", "-Wall", "-Wextra", "-Werror", "-isystem", str(FMI_HEADERS),
                    str(DRIVER), "-o", str(native_driver), "-ldl"], check=True)
    subprocess.run([sys.executable, "-m", "ziglang", "cc", "-target", "x86_64-windows-gnu", "-std=c99", "-O2",
                    "-Wall", "-Wextra", "-Werror", "-isystem", str(FMI_HEADERS), str(DRIVER), "-o",
                    str(windows_driver)], check=True, cwd=tmp_path)
    linux = _run_stop([str(native_driver)], unzipped, binary(unzipped, "linux64"))
    env = dict(os.environ, WINEPREFIX=str(tmp_path / "wine"), WINEDEBUG="-all", DISPLAY="")
    try:
        windows = _run_stop([wine(), str(windows_driver)], unzipped, binary(unzipped, "win64"), env)
    finally:   # the prefix's wineserver and the services it started end with it
        server = next((s for s in (shutil.which("wineserver"), str(Path(wine()).with_name("wineserver64")),
                                   str(Path(wine()).with_name("wineserver"))) if s and Path(s).is_file()), None)
        if server:
            subprocess.run([server, "-k"], env=env, timeout=60)
    assert linux.shape == windows.shape and linux[-1, 1] <= STOP_SPEED     # the whole stop, both
    assert linux[-1, 2] > 2000.0                                             # m: a stop from 250 km/h
    difference = np.max(np.abs(windows - linux) / np.maximum(np.abs(linux), np.finfo(float).tiny))
    print(f"win64 (Wine) vs linux64 over the stop of {linux[-1, 0]:.2f} s, {linux[-1, 2]:.3f} m: "
          f"largest relative difference {difference:.3g}")
    assert np.all(np.abs(windows - linux) <= 1e-12 * np.abs(linux))
