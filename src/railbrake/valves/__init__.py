"""Valve design models built on the pneumatic network (dynamics in the C core).

- EP pressure-control valve (EPV): solenoid-driven flapper over a nozzle (pilot stage) and a relay
  piston with inlet and exhaust seats (second moving body) setting the control pressure.
- Relay valve with a membrane (A_eff = dV/dx of a V(x) table) feeding the brake cylinders through
  the WSP hold valve, with the WSP vent valve; both with a response delay.
- Proportional solenoid of the EPV: magnetic circuit -> force table, current response, coil
  temperature (``railbrake.valves.solenoid``).

Defaults: ``railbrake/data/valves/*.yaml`` (an illustrative high-speed-train design, documented in
docs/pneumatics.md); any key can be overridden from a YAML file or a dict.
"""

from railbrake.valves.epv import (
    EpvCharacteristic,
    epv_characteristic,
    epv_network,
    epv_step,
    load_epv,
    oscillates,
    read_force_table,
    step_metrics,
)
from railbrake.valves.relay import load_relay, relay_step

__all__ = ["EpvCharacteristic", "epv_characteristic", "epv_network", "epv_step", "load_epv",
           "load_relay", "oscillates", "read_force_table", "relay_step", "step_metrics"]
