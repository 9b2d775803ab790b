"""The detailed train model's cost: wall time, solver steps and right-hand-side calls for the
comparison cases, against the real-time plant's run of the same scenario (1 ms).

    python bench/bench_detailed.py [--quick]     # --quick: 1 car only
"""

import sys
import time

from railbrake.simulation import run
from railbrake.simulation.detailed import run_detailed

CASES = [("emergency-250-dry", 1), ("emergency-300-heavy-rain", 1), ("emergency-250-dry", 8),
         ("emergency-300-heavy-rain", 8)]


def main() -> None:
    quick = "--quick" in sys.argv
    print(f"{'scenario':26s} {'cars':>4s} {'sim s':>7s} {'detailed s':>10s} {'x real':>7s} "
          f"{'steps':>8s} {'rejected':>8s} {'rhs calls':>10s} {'RT 1 ms s':>9s}")
    for scenario, cars in CASES:
        if quick and cars > 1:
            continue
        det = run_detailed(scenario, cars=cars)
        start = time.perf_counter()
        run(scenario, cars=cars)
        rt_wall = time.perf_counter() - start
        k = det.kpis
        print(f"{scenario:26s} {cars:4d} {k['stopping_time_s']:7.1f} {k['wall_s']:10.2f} "
              f"{k['stopping_time_s'] / k['wall_s']:7.1f} {k['ode_steps']:8d} {k['ode_rejected']:8d} "
              f"{k['rhs_calls']:10d} {rt_wall:9.2f}", flush=True)


if __name__ == "__main__":
    main()
