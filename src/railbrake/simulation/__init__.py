"""Whole-train brake simulation with wheel-slide protection (model in the loop).

Python sets the parameters up (ctypes structs: railbrake.simulation.parameters) and calls the C core,
which runs the BCU and the plant at a fixed 1 ms step into a preallocated array (core/src/plant*.c,
bcu*.c, run.c); railbrake.simulation.runs makes the runs, in chunks of simulated time so a caller
can show progress, into a railbrake.results.Result. Model: docs/simulation.md.
"""

from railbrake import sizing  # noqa: F401 (simulation.sizing.SupplyWarning: the warning structs() gives)
from railbrake.results.scripting import Result
from railbrake.simulation.changes import Change
from railbrake.simulation.response import (RESPONSE_WINDOW, emergency_scenario, response_times,
                                           simulated_response)
from railbrake.simulation.runs import CHUNK, QUIET_CHUNK, WspCallback, run, run_batch, run_structs  # noqa: F401
from railbrake.simulation.parameters import (DT, KERNEL_ENV, MAX_SUBSTEP, WSP_CONTROLLERS, ZERO_CELSIUS,
                                             axle_name, bcu_params, channels, demanded_steps, kernel_code,
                                             kpi_dict, outside_validity_kpi, plant_params, scenario_train, structs,
                                             substeps_for, wall_time, wsp_params)
from railbrake.simulation.stopping import stopping_distance
from railbrake.simulation.timing import bench, bench_plant

__all__ = ["CHUNK", "Change", "DT", "KERNEL_ENV", "MAX_SUBSTEP", "QUIET_CHUNK", "RESPONSE_WINDOW", "Result",
           "WSP_CONTROLLERS", "ZERO_CELSIUS", "axle_name", "bcu_params", "bench", "bench_plant",
           "channels", "demanded_steps", "emergency_scenario", "kernel_code", "kpi_dict", "outside_validity_kpi", "plant_params",
           "response_times", "run", "run_batch", "run_structs", "scenario_train", "simulated_response", "stopping_distance", "structs",
           "substeps_for", "wall_time", "wsp_params"]
