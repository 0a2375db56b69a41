#!/usr/bin/env bash
# One entry point for a fresh Debian 12 machine: installs the Debian packages libbtf needs (when any
# is missing), builds in Release, then runs one job:
#   demo   the main job: generate, compress, sample, render, compare and chart, on built-in and real
#          data (out/)
#   test   the whole test suite through ctest
#   asan   the test suite again in a separate AddressSanitizer + UBSan build (build-asan/)
# Idempotent: with everything installed and built it only re-runs the job.
set -euo pipefail

job=${1:-demo}
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
cd "$root"
jobs=$(nproc 2>/dev/null || echo 2)

# Each package and why; nothing else is installed (`--no-install-recommends`). A fresh Debian 12
# root (../shared/tools/fresh-debian, run by .ci/run) proves the list complete.
packages=(
  build-essential cmake ninja-build  # the C++20 compiler and the build
  libglm-dev              # vectors and matrices of the public headers
  libopenexr-dev          # linear EXR images (BTF folders, renders)
  libopenimageio-dev      # PNG/JPEG images, resizing and text for previews and plots
  openimageio-tools       # Debian's OpenImageIO CMake package names its tools (iconvert, oiiotool...)
                          # as imported targets and fails without them; they also let users inspect EXRs
  libflann-dev            # kd-tree search of the VQ codebooks
  libeigen3-dev           # per-view PCA baseline (SVD)
  libceres-dev            # least-squares fits of analytic models (btf fit)
  libqhull-dev            # spherical Delaunay triangulations of measured BTF directions
  libembree-dev libtbb-dev  # the renderer's BVH; TBB for parallel loops throughout
  libtinyobjloader-dev    # OBJ meshes (with .mtl) for scenes
  libnanoflann-dev        # a peer kd-tree measured against the photon map's own (btf bench render)
  libboost-dev            # Boost.Math: chi-square quantiles of the sampler tests
  libzstd-dev zlib1g-dev  # .btfz sections: zstd payloads, CRC-32
  nlohmann-json3-dev      # btf.json, .btfz headers, scenes, --json output
  libcli11-dev            # the command line
  libgtest-dev libgmock-dev libbenchmark-dev  # tests and benchmarks
  gnuplot-nox             # charts (PNG and SVG) of btf bench and btf sample
  fonts-dejavu-core       # the font of plot labels and charts
  pybind11-dev python3-dev  # the Python package btf (python/): pybind11 and Debian python3's headers
  python3-numpy           # btf's arrays (directions, reflectance, BTF views, renders)
  python3-pytest          # the Python package's tests (tests/python, ctest -L python)
  python3-matplotlib      # plots of docs/python.md's session (docs/examples/python_session.py)
  python3-dask python3-distributed  # btf.dask: a dataset compressed on a Dask cluster (python3 -m btf.dask)
)

install_packages() {
  local missing=()
  for p in "${packages[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  [ ${#missing[@]} -eq 0 ] && return 0
  echo "== installing ${#missing[@]} Debian packages: ${missing[*]}"
  local sudo=()
  [ "$(id -u)" -ne 0 ] && sudo=(sudo)
  export DEBIAN_FRONTEND=noninteractive
  "${sudo[@]}" apt-get update -qq
  "${sudo[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
  echo "== installed in $SECONDS s"
}

build() {  # build DIR [extra cmake args...]
  local dir=$1 start=$SECONDS; shift
  echo "== building in $dir"
  cmake -S . -B "$dir" -G Ninja "$@" >/dev/null
  cmake --build "$dir" -j"$jobs" ${BUILD_TARGET:+--target $BUILD_TARGET}
  echo "== built $dir in $((SECONDS - start)) s"
}

# `import btf` in Debian's python3 (docs/python.md#installing): a .pth file in its user site naming
# the build's python/ folder. Not pip: Debian 12's pip refuses the system site (PEP 668), and a wheel
# would need a build backend Debian 12 does not package; a rebuild is seen without reinstalling.
python_path() {  # python_path BUILD_DIR
  [ -d "$1/python/btf" ] || return 0
  local site
  site=$(/usr/bin/python3 -m site --user-site)
  mkdir -p "$site"
  echo "$root/$1/python" > "$site/libbtf.pth"
  echo "== /usr/bin/python3 imports btf from $root/$1/python ($site/libbtf.pth)"
}

demo() {
  local bin=build/bin out=out real=../shared/data/real
  mkdir -p "$out"
  echo "== generating a measured-style BRDF (preset plastic-red, MERL layout)"
  "$bin/btf-datagen" --preset plastic-red --seed 1 -o "$out/plastic-red.binary"
  echo "== its facts"
  "$bin/btf" info "$out/plastic-red.binary"
  "$bin/btf" plot "$out/plastic-red.binary" -o "$out/plastic-red.png"
  echo "== importance sampling it with a Douglas-Peucker CDF, checked by chi-square"
  "$bin/btf" sample "$out/plastic-red.binary" --theta-o 40 --sampler dp-cdf -n 200000 -o "$out/plastic-red-samples.png"
  echo "== the smallest models of it: a GGX fitted with Ceres (parameters, rel_rmse, albedo beside the data's)"
  echo "   and the table as an octree within 10% per cell (bytes and rel_rmse against the full table)"
  "$bin/btf" fit "$out/plastic-red.binary" --model ggx -o "$out/plastic-red-ggx.json"
  "$bin/btf" plot "$out/plastic-red-ggx.json" -o "$out/plastic-red-ggx.png"
  "$bin/btf" convert "$out/plastic-red.binary" "$out/plastic-red.octree" --tolerance 0.1
  echo "== a synthetic measured BTF (virtual gonioreflectometer, 16 x 16 texels, 81 x 81 images)"
  "$bin/btf-datagen" btf --pattern fabric --size 16 --seed 1 --format png16 -o "$out/fabric-btf"
  "$bin/btf" info "$out/fabric-btf"
  echo "== compressed by multi-level vector quantization, checked against the images, and decompressed"
  "$bin/btf" compress "$out/fabric-btf" "$out/fabric.btfz" --epsilon 0.02
  "$bin/btf" info "$out/fabric.btfz"
  "$bin/btf" decompress "$out/fabric.btfz" "$out/fabric-decoded" --format png16
  echo "== the datasets people download: the same BTF in the UTIA layout (a folder per view, EXR in CIE XYZ) and"
  echo "   as a Bonn .btf file (DFMF: log-Y, U/Y, V/Y factorised by a truncated SVD), each read and compressed"
  "$bin/btf-datagen" btf --pattern fabric --size 16 --seed 1 --layout utia --format exr -o "$out/fabric-utia"
  "$bin/btf" info "$out/fabric-utia"
  "$bin/btf" compress "$out/fabric-utia" "$out/fabric-utia.btfz" --epsilon 0.02
  "$bin/btf-datagen" btf --pattern fabric --size 16 --seed 1 --layout dfmf --components 256 -o "$out/fabric.btf"
  "$bin/btf" info "$out/fabric.btf"
  "$bin/btf" compare "$out/fabric.btf" "$out/fabric-btf"
  "$bin/btf" compress "$out/fabric.btf" "$out/fabric-dfmf.btfz" --epsilon 0.02
  echo "   and the Bonn dome's own 151 x 151 directions: read without decoding, compressed on its ten light rings"
  "$bin/btf-datagen" btf --pattern stones --size 16 --seed 1 --directions dome --layout dfmf -o "$out/stones-dome.btf"
  "$bin/btf" info "$out/stones-dome.btf"
  "$bin/btf" compress "$out/stones-dome.btf" "$out/stones-dome.btfz" --epsilon 0.02
  echo "== VQ against per-view PCA at equal storage (rate-distortion chart), and how far the data can be compressed at all"
  "$bin/btf" bench compression --patterns fabric --size 16 --epsilons 0.02,0.1,0.4 --levels 3 --no-brdfs -o "$out/bench-compression"
  "$bin/btf" bench compressibility --patterns fabric --size 16 -o "$out/compressibility"
  echo "== the calibrated stand-in for measured BTFs: a printed paper through the measured camera (noise, jitter,"
  echo "   8-bit sRGB), compressed and judged against its own noise floor"
  "$bin/btf-datagen" btf --pattern print --camera --size 16 --seed 1 -o "$out/print-btf"
  "$bin/btf" compress "$out/print-btf" "$out/print.btfz" --epsilon 0.2 --chroma-epsilon 0.05
  if [ -d "$real" ]; then
    echo "== a real measured material (RGL database): facts, MERL-layout conversion, previews"
    "$bin/btf" info "$real/rgl_bsdf/vch_golden_yellow_rgb.bsdf"
    "$bin/btf" convert "$real/rgl_bsdf/vch_golden_yellow_rgb.bsdf" "$out/vch_golden_yellow.binary"
    "$bin/btf" plot "$real/rgl_bsdf/vch_golden_yellow_rgb.bsdf" -o "$out/vch_golden_yellow_rgl.png"
    "$bin/btf" plot "$out/vch_golden_yellow.binary" -o "$out/vch_golden_yellow_merl.png"
    echo "== a real measured BTF slice (Bonn UBO2003 WALLPAPER, one view, 8-bit sRGB JPEG): facts, then compressed"
    echo "   and judged by rel_rmse, SSIM and its own noise floor"
    "$bin/btf" info "$real/btf/ubo2003_wallpaper_view000"
    "$bin/btf" compress "$real/btf/ubo2003_wallpaper_view000" "$out/wallpaper-view000.btfz" --epsilon 0.2 --levels 2 \
      --chroma-epsilon 0.2 --level1-cut
    echo "== a material database: the RGL materials and MERL fits as one-texel BTFs, sharing codebooks, against"
    echo "   each compressed alone; then two files compressed apart, joined losslessly by btf merge"
    "$bin/btf" compress "$real"/rgl_bsdf/*.bsdf merl-fit:sgd:alum-bronze merl-fit:sgd:blue-acrylic \
      merl-fit:sgd:red-plastic merl-fit:sgd:white-paint merl-fit:abc:chrome "$out/brdf-database.btfz" \
      --epsilon 0.05 --compare-alone
    "$bin/btf" info "$out/brdf-database.btfz"
    "$bin/btf" compress "$real/rgl_bsdf/paper_white_rgb.bsdf" "$out/paper-white.btfz" --epsilon 0.05 --no-verify
    "$bin/btf" compress merl-fit:sgd:alum-bronze "$out/alum-bronze.btfz" --epsilon 0.05 --no-verify
    "$bin/btf" merge "$out/paper-white.btfz" "$out/alum-bronze.btfz" -o "$out/merged.btfz"
    echo "== a MERL material from its published ABC fit, compared with its other fits"
    "$bin/btf-datagen" --merl-fit gold-metallic-paint --model abc --seed 1 -o "$out/gold-metallic-paint.binary"
    "$bin/btf" info "$out/gold-metallic-paint.binary"
    echo "== rendering: the Cornell box with the generated BRDF (sphere), the synthetic BTF (tall box) and the real"
    echo "   RGL material vch_golden_yellow (short box), first with the BTF's images, then with its .btfz"
    "$bin/btf-datagen" scene cornell -o "$out/cornell-reference" --brdf "$out/plastic-red.binary" --btf "$out/fabric-btf"
    "$bin/btf-datagen" scene cornell -o "$out/cornell-compressed" --brdf "$out/plastic-red.binary" --btf "$out/fabric.btfz"
    "$bin/btf" render "$out/cornell-reference/scene.json" -o "$out/cornell-reference.exr" --spp 64
    "$bin/btf" render "$out/cornell-compressed/scene.json" -o "$out/cornell-compressed.exr" --spp 64
    echo "   and the tall box in the dome BTF's .btfz, interpolated on triangulations of its 151 directions"
    "$bin/btf-datagen" scene cornell -o "$out/cornell-dome" --brdf "$out/plastic-red.binary" --btf "$out/stones-dome.btfz"
    "$bin/btf" render "$out/cornell-dome/scene.json" -o "$out/cornell-dome.exr" --spp 16
    echo "== the compressed BTF against its images, same scene and seeds (error map: cornell-compressed-error.png)"
    "$bin/btf" compare "$out/cornell-compressed.exr" "$out/cornell-reference.exr" -o "$out/cornell-compressed-error.png" --scale 0.2
    echo "== a second estimator: progressive photon mapping of the reference scene, against the path tracer"
    "$bin/btf" render "$out/cornell-reference/scene.json" -o "$out/cornell-ppm.exr" --integrator ppm --photons 100000 --passes 16 --spp 4
    "$bin/btf" compare "$out/cornell-ppm.exr" "$out/cornell-reference.exr" -o "$out/cornell-ppm-error.png" --scale 0.5
    echo "== the renderer's costs and the samplers at equal time (small sizes; btf bench render for the full run)"
    "$bin/btf" bench render -o "$out/bench-render" --resolution 64 --spp 1,4,16 --reference-spp 256 --photons 200000 --queries 50000
    echo "== model no more than a scene needs: the real RGL material on a sphere filling the frame under a point light,"
    echo "   and on a small, far sphere under a uniform sky; btf fit-scene picks per scene the smallest representation"
    echo "   within a rendered relmse of 0.01 (tables, chart and renders beside each lean.json)"
    "$bin/btf-datagen" scene closeup -o "$out/fit-closeup" --resolution 96 --spp 16
    "$bin/btf-datagen" scene distant -o "$out/fit-distant" --resolution 96 --spp 16
    "$bin/btf" fit-scene "$out/fit-closeup/scene.json" --budget 0.01 -o "$out/fit-closeup/lean.json"
    "$bin/btf" fit-scene "$out/fit-distant/scene.json" --budget 0.01 -o "$out/fit-distant/lean.json"
    echo "== from Python (Debian's python3, import btf): docs/python.md's session, plots and renders into $out/python/;"
    echo "   then two of the materials above compressed into one database on a local Dask cluster of two workers"
    /usr/bin/python3 docs/examples/python_session.py "$out/python"
    /usr/bin/python3 -m btf.dask "$out/fabric-btf" "$out/stones-dome.btf" -o "$out/dask-database.btfz" --local-workers 2 \
      --epsilon 0.05
  else
    echo "(no $real beside the checkout: skipping the real-data part)"
  fi
  echo "== outputs"
  ls -l "$out"
  echo "== done: the renders are $out/cornell-*.png (linear EXRs beside them), the error maps $out/*-error.png,"
  echo "   the charts $out/*.png and $out/*/*.png, the lean scenes $out/fit-*/lean.json"
}

install_packages
case "$job" in
  demo) # The demo builds the two programs and the Python package alone: the test programs and benchmarks are not.
        BUILD_TARGET="btf_cli btf_datagen btf_python" build build -DCMAKE_BUILD_TYPE=Release; python_path build; demo ;;
  test) build build -DCMAKE_BUILD_TYPE=Release; python_path build
        ctest --test-dir build --output-on-failure -j"$jobs" ;;
  asan) # Only the library's tests (and the library guide's examples) run under the sanitizers: building the command-line programs a
        # second time would double CI's compile time, and their tests run in the Release pass.
        # Line tables only (-g1): the sanitizers' reports still name file and line, while the
        # compile is shorter and the objects smaller than with full debug information.
        BUILD_TARGET="btf_unit_tests docs_examples" build build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo \
          "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O2 -g1 -DNDEBUG" -DBTF_SANITIZE=ON -DBTF_BUILD_BENCHMARKS=OFF
        # The statistical and slow tiers (tests/support/tier.h: high sample counts, large fits,
        # thousands of image writes) repeat arithmetic that the unit tier reaches at small sizes
        # and run in the Release suite; under the sanitizers (several times slower) they would
        # take most of CI's time.
        ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
          ctest --test-dir build-asan --output-on-failure -j"$jobs" -L '^unit$' ;;
  *) echo "usage: $0 [demo|test|asan]" >&2; exit 2 ;;
esac
