#!/usr/bin/env bash
# Regenerates the pictures the README shows, from a Release build in build/ and the measured data
# in ../shared/data/real (read there, never copied here).
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
bin="$here/../../build/bin"
rgl="$here/../../../shared/data/real/rgl_bsdf"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$bin/btf-datagen" --preset plastic-red --seed 1 -o "$work/plastic-red.binary" >/dev/null
"$bin/btf" plot "$work/plastic-red.binary" -o "$here/plastic-red.png"
# Each RGL material through its own parameterization, and its MERL-layout conversion.
for name in cc_ibiza_sunset_rgb paper_white_rgb vch_golden_yellow_rgb; do
  "$bin/btf" plot "$rgl/$name.bsdf" -o "$here/$name.png"
  "$bin/btf" convert "$rgl/$name.bsdf" "$work/$name.binary" >/dev/null
  "$bin/btf" plot "$work/$name.binary" -o "$here/${name}_merl.png"
done
