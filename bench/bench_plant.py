"""Plant timing (issue 12: at least 500x real time for 16 cars with the best kernel, 350x portable, p99 at
most 1.5x the mean): the plant alone at one 1 ms step (timing loop in C, rb_plant_bench) over 1, 4, 8 and
16 cars with each wheelset kernel, and the wall-clock time of the default scenario (BCU + plant +
recording + KPIs).

The machine may be shared: the mean step time is the timing thread's CPU time (rb_plant_bench), and each
case is the fastest of the runs railbrake bench --plant makes over SECONDS of wall-clock time (simulation.bench_plant:
the others were slowed down by the rest of the machine, not by the plant), printed with the median and
slowest run and the machine's load average. `--seconds S` sets SECONDS.
"""

import argparse
import time

from railbrake import simulation
from railbrake.simulation import timing

CARS = (1, 4, 8, 16)
KERNELS = ("auto", "portable")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=timing.SECONDS)
    seconds = parser.parse_args().seconds
    print(f"plant alone, the fastest of the runs of 20000 steps in {seconds:g} s per case")
    for kernel in KERNELS:
        for cars in CARS:
            f = simulation.bench_plant(cars=cars, kernel=kernel, seconds=seconds)
            load = "?" if f["load_average"] is None else f"{f['load_average']:.1f}"
            print(f"  {cars:2d} cars, {f['kernel']:8s} kernel, {f['substeps']} sub-step: "
                  f"{f['realtime_factor']:6.0f}x real time, step {f['step_us_cpu_mean']:6.2f} us mean CPU "
                  f"({f['step_us_wall_mean']:6.2f} wall), {f['step_us_p99']:6.2f} us p99 "
                  f"({f['step_us_p99'] / f['step_us_wall_mean']:.2f}x mean), {f['step_us_max']:8.1f} us max; "
                  f"{f['runs']} runs, {f['realtime_factor_median']:6.0f}x median, "
                  f"{f['realtime_factor_slowest']:6.0f}x slowest; load {load}", flush=True)
    t0 = time.perf_counter()
    r = simulation.run("emergency-300-heavy-rain")
    wall = time.perf_counter() - t0
    print(f"emergency-300-heavy-rain, 16 cars: {r.kpis['stopping_time_s']:.1f} s simulated in {wall:.2f} s "
          f"({r.kpis['stopping_time_s'] / wall:.0f}x real time with WSP, recording and KPIs)")


if __name__ == "__main__":
    main()
