#!/usr/bin/env bash
# Sets up and builds the project if needed, then runs the default test suite (labels unit and
# validation; the long validation runs, label long, are left out). Exits non-zero on any failure.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
bash "$root/scripts/setup.sh"
cd "$root/build"
ctest -L "unit|validation" --output-on-failure -j2 --timeout 900
