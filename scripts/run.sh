#!/usr/bin/env bash
# Sets up and builds the project if needed, then runs the default scene (the most complete scene
# there is) and prints where its results are. Extra arguments go to the scene, e.g.
#   bash scripts/run.sh --preset fine
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
bash "$root/scripts/setup.sh"
cd "$root"
exec "$root/build/apps/cardiosph" heart --output "$root/output/heart" "$@"
