#!/usr/bin/env python3
"""Build fmusim, the FMU simulator of modelica/Reference-FMUs, at tag v0.0.39, from its sources, as a
tool for tests/unit/fmu/test_fmu_tools.py (RAILBRAKE_FMUSIM) and tools/fmu_tool_results.py.

    python tools/build_fmusim.py                        # downloads the v0.0.39 sources (needs the internet)
    python tools/build_fmusim.py --source PATH          # a source tree, a .tar.gz/.zip of one, or a git
                                                        # directory holding the tag v0.0.39
    export RAILBRAKE_FMUSIM=$PWD/build/tools/fmusim/fmusim

Upstream's build (fmusim/CMakeLists.txt with build/build_*.py) downloads and builds libxml2 2.14,
zlib 1.3.1 (whose contrib/minizip it compiles in) and SUNDIALS CVODE 7.3. This script uses Debian's
packages instead (libxml2-dev, zlib1g-dev, libminizip-dev, libsundials-dev; installed with apt-get
when missing and we are root) and compiles upstream's own source list (the `set(sources ...)` of
fmusim/CMakeLists.txt, less the minizip files, which come from libminizip) with the system C
compiler. Debian 12's SUNDIALS is 6.4: its SUNContext_Create takes a plain pointer where 7.x
takes SUN_COMM_NULL, so that name is defined as NULL on the command line (CVODE only serves
model-exchange FMUs; railbrake's are co-simulation). Nothing of Reference-FMUs is kept in this
repository; the sources are unpacked under the build folder.
"""

from __future__ import annotations

import argparse
import os
import re
import subprocess
import sys
from pathlib import Path

from tool_sources import ensure_debian_packages, unpack

TAG = "v0.0.39"
VERSION = TAG[1:]
URL = f"https://github.com/modelica/Reference-FMUs/archive/refs/tags/{TAG}.tar.gz"
FMUSIM_PARTS = ["fmusim", "include", "src", "LICENSE.txt"]   # the folders fmusim's build reads
DEBIAN_PACKAGES = {"libxml2-dev": "/usr/include/libxml2/libxml/parser.h",
                   "zlib1g-dev": "/usr/include/zlib.h",
                   "libminizip-dev": "/usr/include/minizip/unzip.h",
                   "libsundials-dev": "/usr/include/cvode/cvode.h"}
LIBRARIES = ["xml2", "minizip", "z", "sundials_cvode", "sundials_nvecserial", "sundials_sunmatrixdense",
             "sundials_sunlinsoldense", "sundials_generic", "dl", "m"]
ROOT = Path(__file__).resolve().parents[1]


def upstream_sources(tree: Path) -> list[Path]:
    """The C files of fmusim's `set(sources ...)`, less zlib's minizip (Debian's libminizip has it)."""
    cmake = (tree / "fmusim" / "CMakeLists.txt").read_text()
    listed = re.search(r"set\(sources\s+(.*?)\)", cmake, re.S)
    if listed is None:
        sys.exit("build_fmusim: fmusim/CMakeLists.txt has no set(sources ...): not the layout of v0.0.39")
    files = [name for name in listed.group(1).split() if name.endswith(".c") and "ZLIB_SRC_DIR" not in name]
    return [(tree / "fmusim" / name).resolve() for name in files]


def sundials_major() -> int:
    header = Path("/usr/include/sundials/sundials_config.h").read_text()
    return int(re.search(r"#define SUNDIALS_VERSION_MAJOR (\d+)", header).group(1))


def compile_fmusim(tree: Path, out: Path, cc: str) -> Path:
    defines = [f'-DFMUSIM_VERSION="{VERSION}"']
    if sundials_major() < 7:
        defines.append("-DSUN_COMM_NULL=NULL")
    includes = ["-I", str(tree / "fmusim"), "-I", str(tree / "include"), "-I", "/usr/include/libxml2",
                "-I", "/usr/include/minizip"]
    out.mkdir(parents=True, exist_ok=True)
    executable = out / "fmusim"
    command = [cc, "-O2", "-w", *defines, *includes, *map(str, upstream_sources(tree)), "-o", str(executable),
               *(f"-l{name}" for name in LIBRARIES)]
    subprocess.run(command, check=True)
    return executable


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--source", help="Reference-FMUs source tree, .tar.gz/.zip, or git dir with the tag "
                        f"{TAG} (default: download {URL})")
    parser.add_argument("--out", type=Path, default=ROOT / "build" / "tools" / "fmusim",
                        help="build folder; the executable is OUT/fmusim (default: %(default)s)")
    parser.add_argument("--cc", default=os.environ.get("CC", "cc"), help="C compiler (default: $CC or cc)")
    args = parser.parse_args(argv)
    ensure_debian_packages("build_fmusim", DEBIAN_PACKAGES)
    tree = unpack("build_fmusim", args.source, URL, TAG, args.out / "src" / f"Reference-FMUs-{VERSION}",
                  "fmusim/CMakeLists.txt", FMUSIM_PARTS)
    executable = compile_fmusim(tree, args.out, args.cc)
    version = subprocess.run([str(executable), "--version"], capture_output=True, text=True).stdout.strip()
    print(f"build_fmusim: built {version}\nexport RAILBRAKE_FMUSIM={executable}")


if __name__ == "__main__":
    main()
