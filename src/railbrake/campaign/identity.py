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
    """The core's own build hash (rb_build_hash: a digest of its sources, set at configure time),
    else, for a core that lacks it, the SHA-256 of the loaded shared library's bytes."""
    from railbrake import _core
    function = getattr(_core, "rb_build_hash", None)
    if function is not None:
        return function().decode()
    with open(_core.lib._name, "rb") as library:
        return hashlib.sha256(library.read()).hexdigest()


def run_key(canonical: str, derived: str = "") -> str:
    """derived: the settings of KPIs a study derives in the worker (the build-up fractions of an
    assessment), so that changing them reruns the runs; empty for a plain study."""
    text = "\n".join((canonical, railbrake_version(), core_build_hash()) + ((derived,) if derived else ()))
    return hashlib.sha256(text.encode()).hexdigest()
