#!/usr/bin/env python3
"""Build the FMI 2 compliance checker (modelica-tools/FMUComplianceChecker, `fmuCheck.linux64`) from
its sources, with the FMI Library (modelon-community/fmi-library, tag 2.0.3) it builds itself, as a
tool for tests/unit/fmu/test_fmu_tools.py (RAILBRAKE_FMU_CHECKER) and tools/fmu_tool_results.py.

    python tools/build_fmu_checker.py                   # downloads both (needs the internet)
    python tools/build_fmu_checker.py --source PATH --fmil PATH
                                                        # each a source tree, a .tar.gz/.zip or a git
                                                        # directory (with the commit / the tag 2.0.3)
    export RAILBRAKE_FMU_CHECKER=$PWD/build/tools/fmu-checker/install/fmuCheck.linux64

The checker is at its last commit (its development has stopped; its last tag, 2.0.4b1, still
fetches the FMI Library from a Subversion server that is gone). Its CMake project clones the FMI
Library from GitHub (ExternalProject, GIT_TAG 2.0.3); with --fmil that clone is pointed at the given
sources through git's `url.<local>.insteadOf` (GIT_CONFIG_* in the environment: nothing global
changes), a tree or an archive being made into a one-commit git repository tagged 2.0.3 first. The
FMI Library builds its own bundled expat, zlib and minizip, so no library is downloaded; Debian's
cmake and a C compiler are all it takes (installed with apt-get when missing and we are root).
Nothing of either project is kept in this repository.
"""

from __future__ import annotations

import argparse
import os
import subprocess
from pathlib import Path

from tool_sources import ensure_debian_packages, unpack

CHECKER_COMMIT = "c704b983b979f57681a5322889360b7688248088"      # 2023-10-16, the last one
CHECKER_URL = f"https://github.com/modelica-tools/FMUComplianceChecker/archive/{CHECKER_COMMIT}.tar.gz"
FMIL_TAG = "2.0.3"
FMIL_GIT = "https://github.com/modelon-community/fmi-library.git"    # as the checker's CMakeLists.txt names it
FMIL_URL = f"https://github.com/modelon-community/fmi-library/archive/refs/tags/{FMIL_TAG}.tar.gz"
DEBIAN_PACKAGES = {"cmake": "/usr/bin/cmake", "gcc": "/usr/bin/gcc", "make": "/usr/bin/make", "git": "/usr/bin/git"}
ROOT = Path(__file__).resolve().parents[1]
TOOL = "build_fmu_checker"


def fmil_repository(source: str, into: Path) -> Path:
    """A git directory holding the tag FMIL_TAG: `source` itself, or one made from a tree or archive."""
    path = Path(source)
    tagged = subprocess.run(["git", f"--git-dir={path}", "rev-parse", "--verify", "-q", f"{FMIL_TAG}^{{commit}}"],
                            capture_output=True).returncode == 0 if path.is_dir() else False
    if tagged:
        return path
    tree = unpack(TOOL, source, FMIL_URL, FMIL_TAG, into, "CMakeLists.txt")
    git = ["git", "-C", str(tree), "-c", "user.name=build", "-c", "user.email=build@invalid"]
    for step in (["init", "-q"], ["add", "-A"], ["commit", "-q", "-m", f"FMI Library {FMIL_TAG}"], ["tag", FMIL_TAG]):
        subprocess.run(git + step, check=True)
    return tree / ".git"


def build(checker: Path, fmil_git: Path | None, build_dir: Path, jobs: int) -> Path:
    env = dict(os.environ)
    if fmil_git is not None:     # the checker's ExternalProject clones FMIL_GIT: take the local one instead
        env.update(GIT_CONFIG_COUNT="1", GIT_CONFIG_KEY_0=f"url.{fmil_git.resolve()}.insteadOf",
                   GIT_CONFIG_VALUE_0=FMIL_GIT)
    install = build_dir / "install"
    subprocess.run(["cmake", "-S", str(checker), "-B", str(build_dir / "build"), "-DCMAKE_BUILD_TYPE=Release",
                    f"-DFMUCHK_INSTALL_PREFIX={install}", "-DCMAKE_C_FLAGS=-w"], check=True, env=env)
    subprocess.run(["cmake", "--build", str(build_dir / "build"), "-j", str(jobs), "--target", "install"],
                   check=True, env=env)
    (executable,) = install.glob("**/fmuCheck.*")
    return executable


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--source", help="the checker's source tree, .tar.gz/.zip, or git dir with commit "
                        f"{CHECKER_COMMIT[:10]} (default: download {CHECKER_URL})")
    parser.add_argument("--fmil", help=f"the FMI Library: tree, archive or git dir with the tag {FMIL_TAG} "
                        f"(default: the checker's build clones {FMIL_GIT})")
    parser.add_argument("--out", type=Path, default=ROOT / "build" / "tools" / "fmu-checker",
                        help="build folder (default: %(default)s)")
    parser.add_argument("--jobs", type=int, default=2)
    args = parser.parse_args(argv)
    ensure_debian_packages(TOOL, DEBIAN_PACKAGES)
    checker = unpack(TOOL, args.source, CHECKER_URL, CHECKER_COMMIT, args.out / "src" / "FMUComplianceChecker",
                     "CMakeLists.txt")
    fmil = fmil_repository(args.fmil, args.out / "src" / "fmi-library") if args.fmil else None
    executable = build(checker, fmil, args.out, args.jobs)
    print(f"{TOOL}: built {executable}\nexport RAILBRAKE_FMU_CHECKER={executable}")


if __name__ == "__main__":
    main()
