#!/usr/bin/env bash
# The main job on the built-in default scene, a river spill: sets up, simulates the scene and writes
# its run folder (spill metrics and their plot, pictures, trajectory, metadata, per-frame
# statistics) to runs/<scene name>/.
#   bash scripts/run_default.sh [extra spill-sim run options]
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
scene=configs/scenes/river_case1.json
out=runs/river_case1
./build/sph/spill-sim run --scene "$scene" --out "$out" --force --png "$@"
echo "spill metrics: $out/spill.json (plot: $out/spill.svg)   pictures: $out/png/   trajectory: $out/trajectory.h5"
