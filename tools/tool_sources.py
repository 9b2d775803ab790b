"""Shared by tools/build_fmusim.py and tools/build_fmu_checker.py: Debian packages installed when
missing, and a third-party source tree unpacked from wherever it can be had (a URL, a tree, an
archive or a git directory holding the wanted tag or commit). The trees go under build/, never into
the repository."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import tarfile
import urllib.request
import zipfile
from pathlib import Path


def ensure_debian_packages(tool: str, packages: dict[str, str]) -> None:
    """apt-get install the packages whose marker file is missing (as root), else say which to install."""
    missing = [name for name, marker in packages.items() if not Path(marker).exists()]
    if not missing:
        return
    if os.geteuid() != 0 or shutil.which("apt-get") is None:
        sys.exit(f"{tool}: missing Debian packages {' '.join(missing)}: "
                 f"install them (apt-get install {' '.join(missing)}) or run this script as root")
    env = dict(os.environ, DEBIAN_FRONTEND="noninteractive")
    subprocess.run(["apt-get", "update", "-q"], check=True, env=env, stdout=subprocess.DEVNULL)
    subprocess.run(["apt-get", "install", "-y", "-q", "--no-install-recommends", *missing], check=True, env=env,
                   stdout=subprocess.DEVNULL)


def unpack(tool: str, source: str | None, url: str, ref: str, tree: Path, marker: str,
           parts: tuple[str, ...] = ()) -> Path:
    """The source tree at `ref` in the fresh folder `tree`, from `source` (a tree, a .tar.gz/.zip,
    a git directory holding `ref`: only `parts` of it when given) or, without one, from `url`.
    `marker` is a file every right tree has."""
    if tree.exists():
        shutil.rmtree(tree)
    tree.parent.mkdir(parents=True, exist_ok=True)
    if source is None:
        archive = tree.parent / url.rsplit("/", 1)[-1]
        print(f"{tool}: downloading {url}")
        urllib.request.urlretrieve(url, archive)
        source = str(archive)
    path = Path(source)
    if (path / marker).exists():
        shutil.copytree(path, tree)
    elif path.is_dir():     # a git directory (bare, or a work tree's .git)
        tree.mkdir()
        archive = subprocess.run(["git", f"--git-dir={path}", "archive", "--format=tar", ref, *parts],
                                 check=True, capture_output=True).stdout
        subprocess.run(["tar", "-x", "-C", str(tree)], input=archive, check=True)
    else:
        staging = tree.parent / f"{tree.name}.unpacked"
        shutil.rmtree(staging, ignore_errors=True)
        if zipfile.is_zipfile(path):
            zipfile.ZipFile(path).extractall(staging)
        else:
            with tarfile.open(path) as archive:
                archive.extractall(staging, filter="data")
        (top,) = [p for p in staging.iterdir() if p.is_dir()]
        top.rename(tree)
        staging.rmdir()
    if not (tree / marker).exists():
        sys.exit(f"{tool}: {source} is not the expected source tree (no {marker})")
    return tree
