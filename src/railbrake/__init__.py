"""railbrake: design and test electro-pneumatic train brakes with wheel-slide protection.

Physical laws live in the C core (``core/``); this package reaches them through
:mod:`railbrake._core`. SI units everywhere inside; human units only at the edges
(:mod:`railbrake.units`).

For scripts: :func:`run` a scenario into a :class:`Result` (``to_dataframe()``, ``plot()``,
``save()``), :func:`load_result` a saved run, :func:`compare` runs side by side; :func:`railbrake.resolve.resolve` a configuration with overrides.
"""

from railbrake._version import __version__
from railbrake.errors import InputError

__all__ = ["InputError", "Result", "__version__", "compare", "load_result", "run"]

# Imported when first used, so `import railbrake` (and the CLI's start) does not load the C core.
_LAZY = {"run": "railbrake.simulation", "Result": "railbrake.simulation",
         "load_result": "railbrake.results.scripting", "compare": "railbrake.results.scripting"}


def __getattr__(name: str):
    if name in _LAZY:
        import importlib
        return getattr(importlib.import_module(_LAZY[name]), name)
    raise AttributeError(f"module 'railbrake' has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(_LAZY))
