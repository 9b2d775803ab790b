#!/bin/sh
# The figures of docs/hil.md (MIL against HIL), made by the code (those of docs/simulation.md are
# drawn when the docs are built: make docs):
#   tools/results_figures.sh [WORK_DIR]     (runs the scenarios; HIL runs paced)
#   RAILBRAKE="python -m railbrake" tools/results_figures.sh   (another way to call the CLI)
# Each run's worst axle is read from its kpis.json, so the figures follow the model, not a name
# written here. What each command prints is kept in WORK_DIR/*.json, *.txt (hil8.txt: the HIL run's
# KPIs, counters and timing report: late frames, overruns; rerun it if it overran badly).
set -e
work=${1:-out/figures}
rb=${RAILBRAKE:-railbrake}
img=$(dirname "$0")/../docs/img
mkdir -p "$work" "$img"
py=${PYTHON:-python3}

worst() {   # a run folder's worst axle, e.g. c3a4: its worst_axle KPI or, where that is null (no
            # lock, no slip above 2 %), the one WSP cycle figure a run without faults or --axles draws
    "$py" - "$1" <<'PY'
import json, pathlib, sys
run = pathlib.Path(sys.argv[1])
axle = json.loads((run / "kpis.json").read_text())["worst_axle"]
drawn = sorted(p.stem.removeprefix("wsp_cycle_") for p in run.glob("wsp_cycle_*.png"))
if axle is None and len(drawn) == 1:
    axle = drawn[0]
if axle not in drawn:
    sys.exit(f"{run}: worst axle {axle!r} not among the WSP cycle figures {drawn}")
print(axle)
PY
}

# the MIL worked examples (default demo, leaf patch, stuck vent valve) are drawn when the docs are
# built (docs/simulation.md, executed); this script makes the HIL figures only.
# MIL against HIL (reference BCU over loopback UDP), 8 cars in heavy rain
$rb run emergency-300-heavy-rain --cars 8 --out "$work/mil8" --json > "$work/mil8.json"
[ -f "$work/hil.key" ] || $rb hil-key "$work/hil.key"   # both sides authenticate their frames with it
$rb bcu emergency-300-heavy-rain --cars 8 --listen udp://127.0.0.1:47800 --key "$work/hil.key" \
    --json > "$work/bcu8.json" &
bcu=$!
sleep 3
$rb hil emergency-300-heavy-rain --cars 8 --bcu udp://127.0.0.1:47800 --key "$work/hil.key" --out "$work/hil8" \
    > "$work/hil8.txt"   # the console table of docs/hil.md; counters and timing also in hil8/run.json
wait $bcu
$rb compare "$work/mil8" "$work/hil8" --plot "$work/compare8" > "$work/compare8.txt"
$rb compare "$work/mil8" "$work/hil8" --json > "$work/compare8.json"
cp "$work/compare8/compare_cylinders.png" "$img/mil_hil_cylinders.png"
a=$(worst "$work/hil8")
cp "$work/hil8/wsp_cycle_$a.png" "$img/hil_wsp_cycle.png"   # the HIL run's worst axle
