"""How long the refusals of issue 32 take (must hold: under 5 s each, with file, line and key): the
`railbrake` command in its own process, start-up included, on the inputs the issue found read or
dropped: a scenario's unknown `train:` keys, a FIFO and a symlink to /dev/zero as adhesion
condition, a 50 MB study file and a study's unchecked values. Each case must end in status 2; the
tests (tests/unit/guard/test_inputs_read_or_refused.py) check the messages, this only the clock.
Prints each wall time, the CPU time it took (which other jobs on the machine do not inflate) and
the load average, and the same for `railbrake --version` (the start-up alone).
Usage: bench_refusals.py [ROUNDS]."""

import os
import resource
import subprocess
import sys
import tempfile
import time
from importlib import resources
from pathlib import Path

RAILBRAKE = str(Path(sys.executable).parent / "railbrake")
SCENARIO = ("schema: railbrake.scenario/1\nname: x\ntrain: {{{train}}}\ninitial_speed: 100 km/h\n"
            "demand: [{{time: 0 s, emergency: true}}]\nadhesion: {{condition: {condition}}}\n")


def scenario(folder: Path, name: str, train: str = "preset: crh380a-8, cars: 2", condition: str = "dry-medium"):
    path = folder / f"scenario-{name}.yaml"
    path.write_text(SCENARIO.format(train=train, condition=condition))
    return ["run", str(path)]


def cases(folder: Path) -> dict[str, list[str]]:
    fifo, zero, huge = folder / "rain.yaml", folder / "zero.yaml", folder / "huge.yaml"
    os.mkfifo(fifo)
    zero.symlink_to("/dev/zero")
    with huge.open("wb") as handle:
        handle.write(b"schema: railbrake.study/1\n")
        handle.truncate(50 * 2**20)
    study = (resources.files("railbrake") / "data" / "studies" / "wsp-en15595.yaml").read_text()
    unchecked = folder / "study.yaml"
    unchecked.write_text(study.replace("air_limit_kg: 20.0", "air_limit_kg: 1.0e+300"))
    return {
        "train: presett": scenario(folder, "presett", "presett: crh380a-8"),
        "train: car": scenario(folder, "car", "preset: crh380a-8, car: 2"),
        "train: max_speed_kmh": scenario(folder, "max_speed", "preset: crh380a-8, max_speed_kmh: 100"),
        "adhesion condition: a FIFO": scenario(folder, "fifo", condition=str(fifo)),
        "adhesion condition: /dev/zero": scenario(folder, "zero", condition=str(zero)),
        "study file of 50 MB": ["campaign", "plan", str(huge)],
        "study value tuning.air_limit_kg = 1e300": ["campaign", "plan", str(unchecked)],
    }


def main(rounds: int = 3) -> None:
    with tempfile.TemporaryDirectory(prefix="bench-refusals-") as tmp:
        print(f"refusals, `railbrake` in its own process, best and worst of {rounds} "
              f"(load average {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores):")
        slowest = 0.0
        for name, args in cases(Path(tmp)).items():
            times = [timed([RAILBRAKE, *args], name) for _ in range(rounds)]
            slowest = max(slowest, max(wall for wall, _, _ in times))
            print(f"  {name}: wall {min(w for w, _, _ in times):.2f} .. {max(w for w, _, _ in times):.2f} s, "
                  f"CPU {min(c for _, c, _ in times):.2f} s   {times[-1][2][:100]}")
        wall, cpu, _ = timed([RAILBRAKE, "--version"], "--version", status=0)
        print(f"slowest {slowest:.2f} s wall (limit 5 s); `railbrake --version` alone: wall {wall:.2f} s, "
              f"CPU {cpu:.2f} s; load average now {os.getloadavg()[0]:.2f}")


def timed(command: list[str], name: str, status: int = 2) -> tuple[float, float, str]:
    """Wall and CPU seconds (the child's user + system: what load does not inflate) and the error."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    done = subprocess.run(command, capture_output=True, text=True, timeout=120)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if done.returncode != status:
        sys.exit(f"{name}: status {done.returncode}, not {status}: {done.stderr}")
    cpu = after.ru_utime - before.ru_utime + after.ru_stime - before.ru_stime
    return wall, cpu, done.stderr.strip()


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 3)
