#!/usr/bin/env bash
# The main job on the built-in default scene: sets up, simulates the scene and writes its run
# folder (trajectory, metadata, per-frame statistics, pictures) to runs/<scene name>/.
#   bash scripts/run_default.sh [extra spill-sim run options]
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
scene=configs/scenes/dam_break.json
out=runs/dam_break
./build/sph/spill-sim run --scene "$scene" --out "$out" --force --png "$@"
echo "pictures: $out/png/   metrics: $out/stats.json   trajectory: $out/trajectory.h5"
