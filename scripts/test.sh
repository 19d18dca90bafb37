#!/usr/bin/env bash
# Sets up and builds the project if needed, then runs the test suite. Exits non-zero on any failure.
#   bash scripts/test.sh          the quick suite: labels unit, validation and regression
#   bash scripts/test.sh --full   everything, with the long validation runs (label long): what CI runs
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
labels="unit|validation|regression"
case "${1:-}" in
  "") ;;
  --full) labels="unit|validation|regression|long" ;;
  *) echo "usage: bash scripts/test.sh [--full]" >&2; exit 2 ;;
esac
bash "$root/scripts/setup.sh"
cd "$root/build"
ctest -L "$labels" --output-on-failure -j2 --timeout 1800
