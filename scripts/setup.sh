#!/usr/bin/env bash
# Installs every system package dexcloth needs (Debian 12, as root). Idempotent; fast when done.
set -euo pipefail

packages=(
  build-essential cmake ninja-build git pkg-config
  libeigen3-dev nlohmann-json3-dev libcli11-dev libopenblas-dev libmetis-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  libdart-dev libdart-utils-dev libdart-utils-urdf-dev libdart-collision-bullet-dev
  libdart-external-ikfast-dev
  chromium ffmpeg
)

# Node.js (with npm) runs the viewer; the image may already ship one (e.g. NodeSource's nodejs,
# which bundles npm and conflicts with Debian's npm package), so only install it when absent.
command -v node >/dev/null 2>&1 || packages+=(nodejs)
command -v npm >/dev/null 2>&1 || packages+=(npm)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

if [ ${#missing[@]} -gt 0 ]; then
  sudo_cmd=""
  [ "$(id -u)" -ne 0 ] && sudo_cmd="sudo"
  $sudo_cmd apt-get update
  DEBIAN_FRONTEND=noninteractive $sudo_cmd apt-get install -y --no-install-recommends "${missing[@]}"
fi

# Viewer dependencies (three.js, playwright-core) from the npm registry, pinned by the lock file.
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
if [ -f "$here/viewer/package-lock.json" ] && [ ! -d "$here/viewer/node_modules" ]; then
  (cd "$here/viewer" && npm ci --no-audit --no-fund)
fi
