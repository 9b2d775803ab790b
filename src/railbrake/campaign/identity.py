"""A run's identity: SHA-256 of its canonical resolved configuration, railbrake's version and the
C core's build hash. Two runs with the same key give the same KPIs, so a rerun may skip it."""

from __future__ import annotations

import functools
import hashlib
from importlib import metadata


@functools.lru_cache(maxsize=1)
def railbrake_version() -> str:
    try:
        return metadata.version("railbrake")
    except metadata.PackageNotFoundError:
        return "unknown"


@functools.lru_cache(maxsize=1)
def core_build_hash() -> str:
    """The core's own build hash when it exports one (rb_build_hash), else the SHA-256 of the
    loaded shared library's bytes (any rebuild with other code changes it)."""
    from railbrake import _core
    function = getattr(_core, "build_hash", None)
    if function is not None:
        return str(function())
    with open(_core.lib._name, "rb") as library:
        return hashlib.sha256(library.read()).hexdigest()


def run_key(canonical: str, derived: str = "") -> str:
    """derived: the settings of KPIs a study derives in the worker (the build-up fractions of an
    assessment), so that changing them reruns the runs; empty for a plain study."""
    text = "\n".join((canonical, railbrake_version(), core_build_hash()) + ((derived,) if derived else ()))
    return hashlib.sha256(text.encode()).hexdigest()
