#!/usr/bin/env bash
# Installs the Debian packages the project needs (only those missing), then configures and builds
# it in build/ (Release). Idempotent: a second run only rebuilds what changed.
#   bash scripts/setup.sh            # packages + build
#   SPILL_SKIP_APT=1 bash scripts/setup.sh   # build only
#   SPILL_TEST_PACKAGES=1 bash scripts/setup.sh   # also what the tests need (chromium)
#   SPILL_CMAKE_ARGS=-DSPILL_WITH_TORCH=OFF bash scripts/setup.sh   # simulator only, no LibTorch
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(
  build-essential cmake pkg-config
  libeigen3-dev libhdf5-dev nlohmann-json3-dev libgtest-dev libcli11-dev libpng-dev
  ffmpeg  # a run's pictures become its video (river.mp4)
  libgdal-dev gdal-bin  # the reach's rasters (GeoTIFF, ESRI ASCII, ...) in and out
  libnetcdf-dev netcdf-bin  # the far field's CF trajectory NetCDF (ncdump: its test)
)
# The test suite opens report.html in headless Chromium (scripts/test.sh sets this).
if [ "${SPILL_TEST_PACKAGES:-0}" = "1" ]; then
  packages+=(chromium)
  packages+=(hdf5-tools)  # h5diff: a sharded generation's splits against one process's
fi
# The learning stack; a simulator-only build (SPILL_CMAKE_ARGS=-DSPILL_WITH_TORCH=OFF) needs none
# of it, LibTorch's 2 GB included.
if [[ "${SPILL_CMAKE_ARGS:-}" != *SPILL_WITH_TORCH=OFF* ]]; then
  packages+=(
    libtorch-dev libopenblas0-pthread libgoogle-perftools-dev
    libgloo-dev  # c10d's ProcessGroupGloo header: spill-train's data-parallel training
    python3-torch  # tests/gnn/gns_reference.py: the plain-PyTorch GNS our model is tested against
  )
fi

if [ "${SPILL_SKIP_APT:-0}" != "1" ]; then
  missing=()
  for p in "${packages[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  if [ ${#missing[@]} -gt 0 ]; then
    echo "setup: installing ${missing[*]}"
    sudo_cmd=""
    [ "$(id -u)" -ne 0 ] && sudo_cmd="sudo"
    $sudo_cmd apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $sudo_cmd apt-get install -y -qq --no-install-recommends "${missing[@]}"
  fi
fi

jobs=$(nproc 2>/dev/null || echo 2)
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release ${SPILL_CMAKE_ARGS:-} > build.log 2>&1 || { cat build.log; exit 1; }
cmake --build build -j "$jobs" >> build.log 2>&1 || { tail -n 60 build.log; exit 1; }
echo "setup: built build/sim/spill-sim (log: build.log)"
