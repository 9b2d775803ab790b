"""Plant timing (issue 5: at least 200x real time for 16 cars on one core): real-time factor of the plant alone at 1 ms (timing loop in C),
and the wall-clock time of the default scenario (BCU + plant + recording + KPIs)."""

import time

from railbrake import simulation


def main() -> None:
    for cars in (1, 8, 16):
        f = simulation.bench(cars=cars, steps=50000)
        print(f"plant {cars:2d} cars: {f['realtime_factor']:7.0f}x real time, "
              f"step {f['step_us_mean']:.2f} us mean, {f['step_us_p99']:.2f} us p99")
    t0 = time.perf_counter()
    r = simulation.run("emergency-300-heavy-rain")
    wall = time.perf_counter() - t0
    print(f"emergency-300-heavy-rain, 16 cars: {r.kpis['stopping_time_s']:.1f} s simulated in {wall:.2f} s "
          f"({r.kpis['stopping_time_s'] / wall:.0f}x real time with WSP, recording and KPIs)")


if __name__ == "__main__":
    main()
