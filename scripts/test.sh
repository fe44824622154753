#!/usr/bin/env bash
# Builds GazeDirector (installing what is missing) and runs its test suite on
# the real data in ../shared.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
ctest --preset release
