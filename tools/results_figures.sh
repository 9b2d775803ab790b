#!/bin/sh
# The figures of docs/simulation.md (Results) and docs/hil.md (MIL against HIL), made by the code:
#   tools/results_figures.sh [WORK_DIR]     (runs the scenarios, ~5 min on 2 cores; HIL runs paced)
set -e
work=${1:-out/figures}
img=$(dirname "$0")/../docs/img
mkdir -p "$work" "$img"
railbrake run --out "$work/demo" --json > /dev/null
railbrake run emergency-300-leaves-patch --out "$work/leaves" --json > /dev/null
railbrake run fault-vent-valve-stuck --out "$work/fault" --json > /dev/null
cp "$work/demo/wsp_cycle_c9a1.png" "$img/demo_wsp_cycle_c9a1.png"
for f in slip cylinders reservoirs; do cp "$work/demo/$f.png" "$img/demo_$f.png"; done
cp "$work/leaves/braking_curve.png" "$img/leaves_braking_curve.png"
cp "$work/leaves/wsp_cycle_c8a4.png" "$img/leaves_wsp_cycle_c8a4.png"
cp "$work/fault/wsp_cycle_c3a2.png" "$img/fault_wsp_cycle_c3a2.png"
cp "$work/fault/cylinders.png" "$img/fault_cylinders.png"
# MIL against HIL (reference BCU over loopback UDP), 8 cars in heavy rain
railbrake run emergency-300-heavy-rain --cars 8 --out "$work/mil8" --json > /dev/null
railbrake bcu emergency-300-heavy-rain --cars 8 --listen udp://127.0.0.1:47800 > /dev/null &
sleep 2
railbrake hil emergency-300-heavy-rain --cars 8 --bcu udp://127.0.0.1:47800 --out "$work/hil8" --json > /dev/null
wait
railbrake compare "$work/mil8" "$work/hil8" --plot "$work/compare8"
cp "$work/compare8/compare_cylinders.png" "$img/mil_hil_cylinders.png"
cp "$(ls "$work"/hil8/wsp_cycle_c*.png | head -1)" "$img/hil_wsp_cycle.png"   # the HIL run's worst axle
