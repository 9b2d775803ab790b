#!/usr/bin/env python3
"""Measure what the third-party FMI tools say of railbrake's FMU and write it to
docs/measured/fmu_tools.json, which docs/fmu.md reads (those tools cannot run when the docs are
built: they are built from sources that cannot be fetched offline).

    python tools/build_fmusim.py ... && python tools/build_fmu_checker.py ...
    .venv/bin/python tools/fmu_tool_results.py --fmusim build/tools/fmusim/fmusim \\
        --checker build/tools/fmu-checker/install/fmuCheck.linux64

For 1, 8 and 16 cars of emergency-250-dry (the whole stop, recorded every 0.01 s): `railbrake run`,
the FMI 2.0 and 3.0 exports run by fmusim (co-simulation, 10 ms communication step) and compared
channel by channel with `railbrake compare --json` (largest difference relative to each channel's
largest value), and the FMI 2.0 export through the compliance checker (its summary counts). The
file keeps the date, the command, the tools' versions and railbrake's commit.
"""

from __future__ import annotations

import argparse
import json
import re
import subprocess
import sys
import tempfile
from datetime import datetime, timezone
from importlib.resources import files
from pathlib import Path

import numpy as np
import yaml

from build_fmu_checker import CHECKER_COMMIT, FMIL_TAG
from railbrake.fmu import export_fmu

ROOT = Path(__file__).resolve().parents[1]
SCENARIO, CARS, INTERVAL = "emergency-250-dry", (1, 8, 16), 0.01
OUTPUT = ROOT / "docs" / "measured" / "fmu_tools.json"


def railbrake(*args) -> str:
    done = subprocess.run([sys.executable, "-m", "railbrake", *map(str, args)], capture_output=True, text=True)
    if done.returncode != 0:
        sys.exit(f"fmu_tool_results: railbrake {' '.join(map(str, args))} failed:\n{done.stdout}{done.stderr}")
    return done.stdout


def native_run(folder: Path, cars: int) -> tuple[Path, dict]:
    """The scenario recorded every INTERVAL, run natively: (its YAML, the KPIs)."""
    spec = yaml.safe_load((files("railbrake") / "data" / "scenarios" / f"{SCENARIO}.yaml").read_text())
    spec.setdefault("outputs", {})["record_interval"] = f"{INTERVAL} s"
    scenario = folder / f"{SCENARIO}.yaml"
    scenario.write_text(yaml.safe_dump(spec))
    kpis = json.loads(railbrake("run", scenario, "--cars", cars, "--out", folder / "native", "--format", "parquet",
                                "--json"))
    return scenario, kpis


def fmusim_agreement(fmusim: str, fmu: Path, folder: Path, stop: float) -> dict:
    csv = fmu.with_suffix(".csv")
    done = subprocess.run([fmusim, "--interface-type", "cs", "--stop-time", f"{stop:.2f}", "--output-interval",
                           str(INTERVAL), "--output-file", str(csv), str(fmu)], capture_output=True, text=True)
    if done.returncode != 0:
        sys.exit(f"fmu_tool_results: fmusim failed on {fmu.name}:\n{done.stdout}{done.stderr}")
    relative = json.loads(railbrake("compare", folder / "native", csv, "--json"))["channels_relative"][0]
    channel = max(relative, key=lambda name: relative[name])
    samples = sum(1 for _ in csv.open()) - 1
    return {"channels": len(relative), "samples": samples, "largest_relative": relative[channel],
            "largest_channel": channel}


def checker_summary(checker: str, fmu: Path, stop: float, folder: Path) -> dict:
    done = subprocess.run([checker, "-h", str(INTERVAL), "-s", f"{stop:.2f}", "-o", str(folder / "checker.csv"),
                           str(fmu)], capture_output=True, text=True)
    report = done.stdout + done.stderr
    summary = re.findall(r"Checker reported:\s+(\d+) Warning\(s\)\s+(\d+) Error\(s\)", report)
    fmu_reported = re.findall(r"FMU reported:\s+(\d+) warning\(s\) and error\(s\)", report)
    if done.returncode != 0 or not summary:
        sys.exit(f"fmu_tool_results: the checker failed on {fmu.name}:\n{report[-3000:]}")
    return {"exit_code": done.returncode, "checker_warnings": sum(int(w) for w, _ in summary),
            "checker_errors": sum(int(e) for _, e in summary), "fmu_warnings_and_errors": sum(map(int, fmu_reported)),
            "runs_checked": len(summary)}


def version_of(command: list[str]) -> str:
    done = subprocess.run(command, capture_output=True, text=True)
    return (done.stdout + done.stderr).strip().splitlines()[0]


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--fmusim", required=True, help="fmusim executable (tools/build_fmusim.py)")
    parser.add_argument("--checker", required=True, help="fmuCheck executable (tools/build_fmu_checker.py)")
    parser.add_argument("--out", type=Path, default=OUTPUT, help="results file (default: %(default)s)")
    args = parser.parse_args(argv)
    commit = subprocess.run(["git", "-C", str(ROOT), "rev-parse", "--short", "HEAD"], capture_output=True,
                            text=True).stdout.strip()
    results = {"made": datetime.now(timezone.utc).strftime("%Y-%m-%d %H:%M UTC"), "railbrake_commit": commit,
               "command": " ".join(["python tools/fmu_tool_results.py", *(argv if argv is not None else sys.argv[1:])]),
               "scenario": SCENARIO, "output_interval_s": INTERVAL,
               "fmusim": version_of([args.fmusim, "--version"]),
               "checker": f"FMUComplianceChecker {CHECKER_COMMIT[:10]} with the FMI Library {FMIL_TAG}",
               "cases": []}
    for cars in CARS:
        with tempfile.TemporaryDirectory() as tmp:
            folder = Path(tmp)
            scenario, kpis = native_run(folder, cars)
            stop = float(np.floor(kpis["stopping_time_s"] / INTERVAL) * INTERVAL)
            case = {"cars": cars, "stop_time_s": stop}
            for version in ("2", "3"):
                fmu = export_fmu(str(scenario), folder / f"plant{version}.fmu", version, cars=cars)
                case[f"fmusim_fmi{version}"] = fmusim_agreement(args.fmusim, fmu, folder, stop)
                if version == "2":
                    case["checker_fmi2"] = checker_summary(args.checker, fmu, stop, folder)
            results["cases"].append(case)
            print(json.dumps(case), flush=True)
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(results, indent=1) + "\n")
    print(f"fmu_tool_results: wrote {args.out}")


if __name__ == "__main__":
    main()
