"""Pneumatics: orifice flow and networks of reservoirs, volumes, orifices, pipes, valves, cylinders.

The laws live in the C core (``core/src/pneumatics_*.c``, ``network_*.c``); a network is compiled
here into flat C structs and simulated whole inside C by the stiff Rosenbrock integrator
(``core/src/ode_rosenbrock.c``). Sources of the laws: ideal gas (R = 287.05 J/(kg K),
gamma = 1.4 for dry air, ISO 2533:1975 table 1) and the orifice flow-rate characteristic of
ISO 6358-1:2013, sec. 3 and annex A (sonic conductance C, critical pressure ratio b, reference
density 1.185 kg/m^3 at 293.15 K).
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
