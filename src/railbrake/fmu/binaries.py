"""The FMU's binaries: one shared library per target platform, built from the FMU's own sources and
checked before they are zipped.

The targets are built with the zig toolchain from PyPI (`ziglang`, the `fmu` extra: a clang with the
C libraries of every target), so that one machine builds them all: linux64 against glibc 2.17 (old
real-time Linux images load it), win64 (MinGW-w64 with the UCRT) and aarch64-linux. Without zig
only the host's platform can be built, with the system C compiler (then the binary needs the
host's glibc). Every library is compiled with hidden symbols: only the FMI API (FMI2_Export /
FMI3_Export) is exported, so two railbrake FMUs live in one process.
"""

from __future__ import annotations

import importlib.util
import os
import re
import shutil
import subprocess
import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path

import fmpy

from railbrake.errors import InputError

FMI_HEADERS = Path(fmpy.__file__).parent / "c-code"
GLIBC_BASELINE = (2, 17)


@dataclass(frozen=True)
class Platform:
    name: str            # as `export-fmu --platforms` names it
    fmi2: str            # binaries/<folder> in an FMI 2 FMU
    fmi3: str            # ... and in an FMI 3 FMU
    zig_target: str
    extension: str
    host: bool           # the system C compiler builds it

    def folder(self, version: str) -> str:
        return self.fmi2 if version == "2" else self.fmi3


_HOST = fmpy.platform == "linux64"
PLATFORMS = {p.name: p for p in (
    Platform("linux64", "linux64", "x86_64-linux", "x86_64-linux-gnu.{0}.{1}".format(*GLIBC_BASELINE), ".so",
             _HOST),
    Platform("win64", "win64", "x86_64-windows", "x86_64-windows-gnu", ".dll", False),
    Platform("aarch64-linux", "aarch64-linux", "aarch64-linux", "aarch64-linux-gnu.{0}.{1}".format(*GLIBC_BASELINE),
             ".so", False),
)}
DEFAULT_PLATFORMS = ("linux64",)

# C99 with the core's warnings; no FP contraction (the same values as the core's own build); only the
# FMI API visible; reproducible: no debug information (it would hold the build's temporary paths),
# the build folder mapped away from any path left, no build id from the linker.
_FLAGS = ("-std=c99", "-O2", "-ffp-contract=off", "-fvisibility=hidden", "-shared", "-Wall", "-Wextra",
          "-Werror=vla", "-g0")


def parse_platforms(text: str) -> tuple[str, ...]:
    """'linux64,win64' -> ('linux64', 'win64'); an unknown or repeated name is refused."""
    names = tuple(n.strip() for n in text.split(","))
    for name in names:
        if name not in PLATFORMS:
            raise InputError(f"--platforms: {name!r} is not a platform: choose from {', '.join(PLATFORMS)}")
    if len(set(names)) != len(names):
        raise InputError(f"--platforms {text!r}: a platform is named twice")
    return names


def have_zig() -> bool:
    return importlib.util.find_spec("ziglang") is not None


def _compiler(platform: Platform) -> list[str]:
    if have_zig():
        return [sys.executable, "-m", "ziglang", "cc", "-target", platform.zig_target]
    if platform.host:
        return [os.environ.get("CC", "cc"), "-fPIC"]
    raise InputError(f"platform {platform.name}: building it needs the zig toolchain "
                     "(pip install 'railbrake[fmu]', or `make install` in the repository)")


def compile_binary(unzipped: Path, version: str, sources: list[str], identifier: str, platform_name: str,
                   extra_flags: tuple[str, ...] = ()) -> Path:
    """binaries/<platform>/<identifier>.<so|dll> from sources/, then checked (check_binary)."""
    platform = PLATFORMS[platform_name]
    target = unzipped / "binaries" / platform.folder(version) / f"{identifier}{platform.extension}"
    target.parent.mkdir(parents=True, exist_ok=True)
    compiler = _compiler(platform)
    linux = platform.extension == ".so"
    with tempfile.TemporaryDirectory() as build:   # the linker's by-products (import library, .pdb) stay there
        built = Path(build) / target.name
        command = [*compiler, *_FLAGS, f"-ffile-prefix-map={unzipped}=.", f"-ffile-prefix-map={build}=.",
                   *(["-fPIC", "-Wl,--no-undefined", "-Wl,--build-id=none", "-Wl,--strip-debug"] if linux else []),
                   f"-I{unzipped / 'sources'}", "-isystem", str(FMI_HEADERS), *extra_flags,
                   *[str(unzipped / "sources" / s) for s in sources], "-o", str(built), *(["-lm"] if linux else [])]
        done = subprocess.run(command, capture_output=True, text=True, cwd=build)
        if done.returncode != 0:
            raise InputError(f"compiling the FMU for {platform.name} with {' '.join(compiler)} failed:\n"
                             f"{done.stderr[-4000:]}")
        shutil.move(built, target)
    problems = check_binary(target, version, GLIBC_BASELINE if have_zig() else None)
    if problems:
        raise InputError(f"the {platform.name} binary {target.name} fails its check: {'; '.join(problems)}")
    return target


# ------------------------------------------------------------------ checks

def exported_symbols(binary: Path) -> list[str]:
    """The functions a shared library exports (ELF: its dynamic symbol table; PE: its export table)."""
    if binary.suffix == ".dll":
        text = _objdump("-p", binary)
        table = text.split("[Ordinal/Name Pointer] Table", 1)[1].split("\n\n")[0] if "Name Pointer] Table" in text else ""
        return re.findall(r"^\s*\[\s*\d+\]\s+(\S+)\s*$", table, re.M)
    return [line.split()[-1] for line in _objdump("-T", binary).splitlines()
            if " DF " in line and "*UND*" not in line]


def glibc_versions(binary: Path) -> list[tuple[int, ...]]:
    """The GLIBC_x.y symbol versions an ELF library needs."""
    found = set(re.findall(r"GLIBC_(\d+(?:\.\d+)+)", _objdump("-T", binary)))
    return sorted(tuple(int(x) for x in v.split(".")) for v in found)


def check_binary(binary: Path, version: str, glibc: tuple[int, int] | None = GLIBC_BASELINE) -> list[str]:
    """What is wrong with an FMU binary: exports besides the FMI API, or (ELF) a glibc newer than
    `glibc` (None: the host's, as the system C compiler builds). Empty when it is right, or when
    objdump (binutils) is not there to tell."""
    if shutil.which("objdump") is None:
        return []
    foreign = [s for s in exported_symbols(binary) if not s.startswith(f"fmi{version}")]
    problems = [f"exports {len(foreign)} symbols besides the FMI API ({', '.join(foreign[:5])})"] if foreign else []
    if binary.suffix == ".so" and glibc is not None:
        newest = max(glibc_versions(binary), default=())
        if newest > glibc:
            problems.append(f"needs GLIBC_{'.'.join(map(str, newest))}, newer than the baseline "
                            f"GLIBC_{'.'.join(map(str, glibc))}")
    return problems


def host_toolchain_note(fmu: Path) -> str | None:
    """What an FMU's linux64 binary needs when the system C compiler built it (no zig, the `fmu`
    extra): the newest GLIBC_x.y symbol version it uses (the host's glibc or newer), against the
    glibc 2.17 of a zig build. None when zig built it or there is no linux64 binary."""
    import zipfile
    if have_zig():
        return None
    with zipfile.ZipFile(fmu) as zf, tempfile.TemporaryDirectory() as tmp:
        names = [n for n in zf.namelist() if n.startswith("binaries/linux64/") and n.endswith(".so")]
        if not names:
            return None
        binary = Path(zf.extract(names[0], tmp))
        newest = max(glibc_versions(binary), default=()) if shutil.which("objdump") else ()
    needs = f"glibc {'.'.join(map(str, newest))} or newer" if newest else "this machine's glibc or newer"
    return (f"the linux64 binary was built with the system C compiler ({os.environ.get('CC', 'cc')}): it needs "
            f"{needs}; with the zig toolchain (pip install 'railbrake[fmu]') it needs glibc "
            f"{'.'.join(map(str, GLIBC_BASELINE))}")


def _objdump(option: str, binary: Path) -> str:
    done = subprocess.run(["objdump", option, str(binary)], capture_output=True, text=True)
    if done.returncode != 0:
        raise InputError(f"objdump {option} {binary}: {done.stderr.strip()}")
    return done.stdout
