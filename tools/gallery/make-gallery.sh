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
# BTF compression: VQ against per-view PCA, and how far the synthetic BTFs compress at all.
"$bin/btf" bench compression --patterns fabric,stones --size 32 --epsilons 0.01,0.02,0.05,0.1,0.2,0.4,0.6 \
  --levels 3 --no-brdfs -o "$work/compression" >/dev/null
cp "$work/compression/compression_ratio_vs_error.png" "$here/btf-rate-distortion.png"
"$bin/btf" bench compressibility --patterns fabric,stones,paint,leather --size 32 -o "$work/compressibility" >/dev/null
cp "$work/compressibility/compressibility_nearest.png" "$here/btf-nearest-texel.png"
