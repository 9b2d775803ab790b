"""railbrake: design and test electro-pneumatic train brakes with wheel-slide protection.

Physical laws live in the C core (``core/``); this package reaches them through
:mod:`railbrake._core`. SI units everywhere inside; human units only at the edges
(:mod:`railbrake.units`).
"""

from railbrake.errors import InputError

__version__ = "0.1.0"
__all__ = ["InputError", "__version__"]
