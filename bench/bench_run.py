"""What a run costs against its plant (issue 25: a whole run at most 1.3x its plant alone on the same
scenario, for 1, 8 and 16 cars): `railbrake bench` on the 16-, 8- and 1-car emergency stop from
300 km/h in heavy rain (BCU, WSP, KPIs, no recording), all in this process.

Figures: CPU microseconds per simulated millisecond of the whole run (simulation.run from the
resolved configuration), of the same run inside C alone, and of the plant alone stepped through the
inputs the BCU gave it (rb_run_bench); their ratio; the real-time factor (wall clock). Each is the
fastest of the runs made over SECONDS (the machine may be shared). `--seconds S` sets SECONDS.
"""

import argparse

from railbrake import simulation
from railbrake.simulation import timing

SCENARIO = "emergency-300-heavy-rain"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=timing.SECONDS)
    seconds = parser.parse_args().seconds
    print(f"{SCENARIO}: whole run against its plant alone, CPU us per simulated ms, fastest over {seconds:g} s")
    for cars in (16, 8, 1):
        f = simulation.bench(SCENARIO, cars, seconds=seconds)
        load = "?" if f["load_average"] is None else f"{f['load_average']:.1f}"
        print(f"  {cars:2d} cars, {f['kernel']} kernel, {f['simulated_s']:6.1f} s simulated: whole run "
              f"{f['run_cpu_us_per_ms']:6.3f} (median {f['run_cpu_us_per_ms_median']:6.3f}), inside C "
              f"{f['core_run_cpu_us_per_ms']:6.3f}, plant alone {f['plant_cpu_us_per_ms']:6.3f}; ratio "
              f"{f['ratio']:.2f} ({f['core_ratio']:.2f} inside C); {f['realtime_factor']:5.0f}x real time; "
              f"{f['runs']} runs; resolve {f['resolve_cpu_s']:.3f} s CPU; load {load}", flush=True)


if __name__ == "__main__":
    main()
