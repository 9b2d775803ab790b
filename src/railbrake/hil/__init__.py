"""Hardware-in-the-loop: the plant paced at 1 kHz against an external BCU over UDP, and the
reference BCU server (core/src/hil_runner.c, hil_bcu.c; guide docs/hil.md, frames docs/hil-interface.md).

Python only sets up parameters and calls the C loops in chunks (0.5 s of steps for the plant, 0.5 s
of wall time for the BCU) so a caller can show progress and stop with Ctrl-C; nothing in Python
runs inside the 1 ms loop.
"""

from railbrake.hil.runs import (BCU_CHUNK, BcuCounters, CHUNK_STEPS, CHUNK_TIME, DEFAULT_BCU_PRIORITY,
                                DEFAULT_HOLD_TIME, DEFAULT_LATE_TIME, DEFAULT_PRIORITY, DT, GIL_SWITCH_INTERVAL,
                                HilResult, RealTime, channels, config_digest, describe_config, hil_config, loss_dict,
                                parse_udp_url, request_real_time, run, run_kpis, serve_bcu)

__all__ = ["BCU_CHUNK", "BcuCounters", "CHUNK_STEPS", "CHUNK_TIME", "DEFAULT_BCU_PRIORITY", "DEFAULT_HOLD_TIME",
           "DEFAULT_LATE_TIME", "DEFAULT_PRIORITY", "DT", "GIL_SWITCH_INTERVAL", "HilResult", "RealTime", "channels",
           "config_digest", "describe_config", "hil_config", "loss_dict", "parse_udp_url", "request_real_time", "run",
           "run_kpis", "serve_bcu"]
