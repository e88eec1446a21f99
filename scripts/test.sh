#!/usr/bin/env bash
# Sets up (packages + build) and runs the whole test suite with CTest: unit and validation tests.
#   bash scripts/test.sh                 # everything
#   bash scripts/test.sh -L unit         # extra arguments go to ctest
set -euo pipefail
cd "$(dirname "$0")/.."
SPILL_TEST_PACKAGES=1 bash scripts/setup.sh
cd build
ctest --output-on-failure -j "$(nproc 2>/dev/null || echo 2)" "$@"
