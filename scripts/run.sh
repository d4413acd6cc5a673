#!/usr/bin/env bash
# Sets up a fresh Debian 12 machine (as root), builds kcwarp and runs the main job: the GUI on a
# bundled example when a display is available, otherwise the headless demo (writes ./out/demo).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
if [ -n "${DISPLAY:-}" ] && [ -x build/app/kcwarp ]; then
  exec build/app/kcwarp "$@"
fi
exec build/app/kcwarp-cli demo --out out/demo "$@"
