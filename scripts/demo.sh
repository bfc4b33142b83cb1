#!/usr/bin/env bash
# The main job: install dependencies, build, run the demo scene on its defaults.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$here/scripts/setup.sh"
bash "$here/scripts/build.sh"
"$here/build/dexcloth" run "$here/scenes/pinch_move.json" --out "$here/out/pinch_move"
