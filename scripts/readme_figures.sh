#!/usr/bin/env bash
# Renders the README's side-by-side figures of the paper's scenes: each scene run whole in the
# bai-liu coupling (left) and the kinematic baseline (right), one frame of each rendered by
# `dexcloth snapshot` (headless chromium) and put side by side with ffmpeg, into docs/img/.
#   bash scripts/readme_figures.sh [scene ...]     (default: the six below; needs build/)
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bin="$here/build/dexcloth"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

# scene:frame:crop-x (frames at 50 per second; a 920-pixel-wide crop of each 1280×720 frame,
# from crop-x, leaves out the viewer's info panel)
declare -A shots=(
  [curtain_hand]=125:290 [dress_sleeve]=170:200 [fold_napkin]=192:200
  [press_flatten]=180:200 [grab_pile]=155:200 [dress_sleeve_hand]=170:200)
scenes=("$@")
[ ${#scenes[@]} -eq 0 ] && scenes=(curtain_hand dress_sleeve dress_sleeve_hand fold_napkin press_flatten grab_pile)

for scene in "${scenes[@]}"; do
  [ -n "${shots[$scene]:-}" ] || { echo "readme_figures.sh: no shot for '$scene'" >&2; exit 2; }
  frame="${shots[$scene]%%:*}"
  x="${shots[$scene]##*:}"
  for coupling in bai-liu kinematic; do
    "$bin" run "$here/scenes/$scene.json" --coupling "$coupling" --out "$work/$scene-$coupling" --quiet
    "$bin" snapshot "$work/$scene-$coupling" --frames "$frame" --png "$work/$scene-$coupling/png"
  done
  left="$(ls "$work/$scene-bai-liu/png/"*.png)"
  right="$(ls "$work/$scene-kinematic/png/"*.png)"
  ffmpeg -loglevel error -y -i "$left" -i "$right" -filter_complex \
    "[0:v]crop=920:720:$x:0[l];[1:v]crop=920:720:$x:0[r];[l][r]hstack,scale=1200:-1" \
    "$here/docs/img/$scene.png"
  echo "docs/img/$scene.png"
done
