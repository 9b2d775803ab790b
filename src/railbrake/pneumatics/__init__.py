"""Pneumatics: orifice flow and networks of reservoirs, volumes, orifices, pipes, valves, cylinders.

The laws live in the C core (``core/src/pneumatics_*.c``, ``network_*.c``); a network is compiled
here into flat C structs and simulated whole inside C by the stiff Rosenbrock integrator
(``core/src/ode_rosenbrock.c``). Source of the laws: ``shared/reference/README.md`` section 4
(ideal gas, ISO 6358 orifice).
"""

from railbrake.pneumatics.network import Network, NetworkResult
from railbrake.pneumatics.orifice import (
    AIR_GAMMA,
    AIR_R,
    AMBIENT_PRESSURE,
    orifice_mass_flow,
    sonic_conductance,
)

__all__ = ["AIR_GAMMA", "AIR_R", "AMBIENT_PRESSURE", "Network", "NetworkResult", "orifice_mass_flow",
           "sonic_conductance"]
