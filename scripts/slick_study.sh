#!/usr/bin/env bash
# The still-water slick study behind docs/results/slick_resolution.md: the floating release
# (Fay's set-up) at 4, 2 and 1.33 cm particles, and the dropped block at the river scenes'
# viscosities and at the still-water scenes' tenth of them, at 4 and 2 cm. Each run's spill.json
# (slick shape per frame and Fay's fit) is copied to docs/results/slick/<run>.json.
#   bash scripts/slick_study.sh [--quick]   (about 27 minutes on 2 cores; --quick leaves out the
#   1.33 cm run, 20 of them)
set -euo pipefail
cd "$(dirname "$0")/.."
sim=./build/sim/spill-sim
out=docs/results/slick
runs=$(mktemp -d)
trap 'rm -rf "$runs"' EXIT
mkdir -p "$out"
run() {  # name scene [spill-sim options]
  local name=$1 scene=$2
  shift 2
  echo "== $name" >&2
  "$sim" run --scene "configs/scenes/$scene.json" --out "$runs/$name" --threads 2 "$@"
  cp "$runs/$name/spill.json" "$out/$name.json"
}
run floating_4cm slick_still_water_floating
run floating_2cm slick_still_water_floating --set /particle_radius=0.01
if [[ "${1:-}" != "--quick" ]]; then
  run floating_1.33cm slick_still_water_floating --set /particle_radius=0.0066666667
fi
river_viscosities=(--set /materials/water/viscosity=0.001 --set /materials/oil/viscosity=0.004)
run dropped_4cm slick_still_water --set /end_time=2
run dropped_2cm slick_still_water --set /end_time=2 --set /particle_radius=0.01
run dropped_4cm_river_viscosity slick_still_water --set /end_time=2 "${river_viscosities[@]}"
run dropped_2cm_river_viscosity slick_still_water --set /end_time=2 --set /particle_radius=0.01 \
  "${river_viscosities[@]}"
echo "spill.json of each run: $out/" >&2
