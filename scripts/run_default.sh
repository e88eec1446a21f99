#!/usr/bin/env bash
# The main job on the built-in default scene, a river spill: sets up, simulates the scene and writes
# its run folder (report.html, spill metrics and their plot, pictures and their video, trajectory,
# metadata, per-frame statistics) to runs/<scene name>/.
#   bash scripts/run_default.sh [extra spill-sim run options, e.g. --vtk for ParaView files]
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
scene=configs/scenes/river_case1.json
out=runs/river_case1
./build/sim/spill-sim run --scene "$scene" --out "$out" --force --png "$@"
echo "report: $out/report.html   spill metrics: $out/spill.json (plot: $out/spill.svg)   pictures: $out/png/ (video: $out/river.mp4)   trajectory: $out/trajectory.h5"
