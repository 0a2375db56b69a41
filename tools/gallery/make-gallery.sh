#!/usr/bin/env bash
# Regenerates the pictures of tools/gallery/ that the docs show, from a Release build in build/ and
# the measured data in ../shared/data/real (read there, never copied here).
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
# Renders: the Cornell box with a generated BRDF (sphere), a compressed synthetic BTF (tall box) and
# the real RGL material vch_golden_yellow (short box); the same box with the BTF's images, and the
# error map between them; progressive photon mapping against the path tracer; the bunny in the SGD
# fit of MERL's gold-metallic-paint.
"$bin/btf-datagen" --preset plastic-red --seed 1 -o "$work/plastic-red.binary" >/dev/null
"$bin/btf-datagen" btf --pattern fabric --size 16 --seed 1 --format png16 -o "$work/fabric-btf" >/dev/null
"$bin/btf" compress "$work/fabric-btf" "$work/fabric.btfz" --epsilon 0.02 >/dev/null
"$bin/btf-datagen" scene cornell -o "$work/ref" --brdf "$work/plastic-red.binary" --btf "$work/fabric-btf" --resolution 384 >/dev/null
"$bin/btf-datagen" scene cornell -o "$work/vq" --brdf "$work/plastic-red.binary" --btf "$work/fabric.btfz" --resolution 384 >/dev/null
"$bin/btf" render "$work/ref/scene.json" -o "$work/cornell-reference.exr" --spp 256 >/dev/null
"$bin/btf" render "$work/vq/scene.json" -o "$work/cornell-compressed.exr" --spp 256 >/dev/null
"$bin/btf" render "$work/ref/scene.json" -o "$work/cornell-ppm.exr" --integrator ppm --photons 200000 --passes 32 --spp 8 >/dev/null
"$bin/btf" compare "$work/cornell-compressed.exr" "$work/cornell-reference.exr" -o "$here/cornell-compressed-error.png" --scale 0.2 \
  > "$here/cornell-compressed-error.txt"
"$bin/btf" compare "$work/cornell-ppm.exr" "$work/cornell-reference.exr" -o "$here/cornell-ppm-error.png" --scale 0.5 \
  > "$here/cornell-ppm-error.txt"
cp "$work/cornell-reference.png" "$here/cornell-reference.png"
cp "$work/cornell-compressed.png" "$here/cornell-compressed.png"
cp "$work/cornell-ppm.png" "$here/cornell-ppm.png"
"$bin/btf" render "$here/../scenes/bunny.json" -o "$work/bunny.exr" --spp 64 > "$here/bunny.txt"
cp "$work/bunny.png" "$here/bunny.png"
"$bin/btf" render "$here/../scenes/dragon.json" -o "$work/dragon.exr" --spp 64 >/dev/null
cp "$work/dragon.png" "$here/dragon.png"
# The samplers at equal time on the Cornell box with RGL materials.
"$bin/btf" bench render -o "$work/bench-render" >/dev/null
cp "$work/bench-render/samplers.png" "$here/render-samplers.png"
