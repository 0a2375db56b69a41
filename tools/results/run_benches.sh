#!/bin/bash
# Runs the quick versions of the `btf bench` experiments into one folder, then writes
# docs/results.md from it (tools/results/make_results_page.py).
#
#   bash tools/results/run_benches.sh [OUT_DIR]        (default OUT_DIR: build/results)
#
# BTF_BIN sets the folder of btf and btf-datagen (default build/bin); BTF_SHARED_DATA_DIR the
# third-party data (default ../shared/data/real; the RGL and fits benches are skipped without it).
# Everything runs at `nice -n 19`. The commands are recorded in OUT_DIR/commands.txt, and the
# commit and machine in OUT_DIR/meta.json, so the page says what produced it. BTF_BENCHES (comma-
# separated: sampling, compression, bonn, compressibility, render, decode, rgl-writer, sampling-warp, fits,
# fits-tables, python, dask) runs only those and updates their sections of the page, keeping the
# others (make_results_page.py --update).
# BTF_BONN_SIDES (default 16,32) sets the texel sides of `btf bench bonn` (the full size: 50,100,200,400).
set -euo pipefail

repo=$(cd "$(dirname "$0")/../.." && pwd)
bin=${BTF_BIN:-$repo/build/bin}
data=${BTF_SHARED_DATA_DIR:-$repo/../shared/data/real}
out=${1:-$repo/build/results}
for tool in btf btf-datagen; do
  [[ -x $bin/$tool ]] || { echo "run_benches: $bin/$tool not found (build first, or set BTF_BIN)" >&2; exit 1; }
done

# The folder is replaced only when a previous run made it (or it is empty).
if [[ -d $out && -n $(ls -A "$out") && ! -f $out/meta.json ]]; then
  echo "run_benches: $out exists and was not made by this script; choose another folder" >&2
  exit 1
fi
rm -rf "$out"
mkdir -p "$out"
cd "$out"
: >commands.txt

# Runs a command at the lowest priority and records it (with build/bin/ for the binaries' folder),
# an empty or spaced argument in quotes, so that it runs as recorded.
run() {
  local recorded="" arg
  for arg in "$@"; do
    [[ -n $arg && ! $arg =~ [[:space:]] ]] || arg="'$arg'"
    recorded+="${recorded:+ }$arg"
  done
  echo "$recorded" | sed -e "s|$bin/|build/bin/|g" -e "s|$out/||g" -e "s|$repo/||g" >>commands.txt
  nice -n 19 "$@"
}

# True when BTF_BENCHES is unset or names the bench.
wanted() { [[ -z ${BTF_BENCHES:-} || ",${BTF_BENCHES}," == *",$1,"* ]]; }

commit=$(git -C "$repo" rev-parse HEAD)
dirty=false
[[ -z $(git -C "$repo" status --porcelain --untracked-files=no) ]] || dirty=true
cat >meta.json <<META
{"date": "$(date -u '+%Y-%m-%d %H:%M UTC')", "commit": "$commit", "dirty": $dirty,
 "system": "$(uname -sr)"}
META

if wanted sampling; then run "$bin/btf" bench sampling --quick -o "$out/sampling"; fi
if wanted compression; then
  run "$bin/btf" bench compression --quick -o "$out/compression"
  run "$bin/btf" bench compression --scaling --scaling-sizes 8,16,32 --patterns '' --no-brdfs -o "$out/compression-scaling"
fi
if wanted bonn; then
  run "$bin/btf" bench bonn --sides "${BTF_BONN_SIDES:-16,32}" --epsilons 0.05,0.02 --vq-max-side 16 -o "$out/bonn"
fi
if wanted compressibility; then run "$bin/btf" bench compressibility --patterns fabric,stones --size 16 -o "$out/compressibility"; fi
if wanted render; then run "$bin/btf" bench render --quick -o "$out/render"; fi

# Decoding needs a .btfz: a small synthetic BTF, compressed.
if wanted decode; then
  mkdir -p "$out/decode"
  run "$bin/btf-datagen" btf --pattern fabric --size 16 --format exr -o "$out/decode/fabric"
  run "$bin/btf" compress "$out/decode/fabric" "$out/decode/fabric.btfz" --epsilon 0.05
  echo "build/bin/btf bench decode decode/fabric.btfz --samples 65536 --repeats 2 --json > decode/decode.json" >>commands.txt
  nice -n 19 "$bin/btf" bench decode "$out/decode/fabric.btfz" --samples 65536 --repeats 2 --json >"$out/decode/decode.json"
  rm -rf "$out/decode/fabric"
fi

# The RGL writer on its list of materials (GGX, Lambert, Phong, the presets, the shared RGL files).
if wanted rgl-writer; then run "$bin/btf" bench rgl-writer -o "$out/rgl-writer"; fi

# DP-CDF against the Dupuy-Jakob warp at equal memory, both built from the same MERL-layout table:
# the presets, the shared RGL files and eight published MERL fits, each tabulated first. The library's
# default tables (not --quick), since the comparison is at the bytes each sampler needs.
if ! wanted sampling-warp; then
  :
elif [[ -d $data/rgl_bsdf && -d $data/fits ]]; then
  materials=white-diffuse,matte-clay,satin-paint,plastic-red,glossy-blue-plastic,brushed-metal,rough-gold,chrome
  for f in "$data"/rgl_bsdf/*.bsdf; do materials+=",$f"; done
  for m in gold-metallic-paint blue-acrylic chrome alum-bronze blue-fabric black-oxidized-steel dark-red-paint brass; do
    materials+=",merl-fit:sgd:$m"
  done
  run "$bin/btf" bench sampling --as-tables --samplers dp-cdf,dj-warp --materials "$materials" -o "$out/sampling-warp"
else
  echo "# btf bench sampling --as-tables (dj-warp) skipped: no $data/rgl_bsdf or $data/fits" >>commands.txt
fi

if ! wanted fits; then
  :
elif [[ -d $data/fits ]]; then
  run "$bin/btf" bench fits --materials alum-bronze --references sgd --models ggx --objectives log,linear \
    --starts 2 --fits-dir "$data/fits" -o "$out/fits"
else
  echo "# btf bench fits skipped: no $data/fits" >>commands.txt
fi

# The default fit and the other models on measured-style tables: the shared NBRDF materials tabulated
# on MERL's grid (../shared/tools/nbrdf-to-merl, which needs python3-h5py) and the shared RGL files,
# beside the published fits of the same materials.
nbrdf=$data/merl_nbrdf/merl_nbrdf_20.zip
tabulate=$repo/../shared/tools/nbrdf-to-merl
if ! wanted fits-tables; then
  :
elif [[ -f $nbrdf && -x $tabulate && -d $data/rgl_bsdf ]] && /usr/bin/python3 -c "import h5py" 2>/dev/null; then
  echo "../shared/tools/nbrdf-to-merl --zip $nbrdf --all --out-dir merl-tables" >>commands.txt
  "$tabulate" --zip "$nbrdf" --all --out-dir "$out/merl-tables" >/dev/null
  # --threads 1: the time goal of the default fit is one core per table.
  run "$bin/btf" bench fits --tables "$out/merl-tables,$data/rgl_bsdf" --models default,abc,sgd,ggx,ggx2 --threads 1 \
    --fits-dir "$data/fits" -o "$out/fits-tables"
  rm -rf "$out/merl-tables"
else
  echo "# btf bench fits --tables skipped: no $nbrdf, $tabulate or python3-h5py" >>commands.txt
fi

# The Python binding against the C++ calls, and btf.dask on a LocalCluster of 1 and 2 workers
# against one machine (Debian's python3 with this build's package, numpy, dask and distributed).
# The dask runs at one core per task (the scaling of workers alone), then at the default (a lone
# worker uses every core); both write their rows into one CSV. 16 x 16 texels keep the two runs short
# (the time grows with the texel count).
python_env=(env PYTHONPATH="$repo/build/python" BTF_DATAGEN="$bin/btf-datagen" /usr/bin/python3)
if ! wanted python; then
  :
elif PYTHONPATH="$repo/build/python" /usr/bin/python3 -c "import btf, numpy" 2>/dev/null; then
  mkdir -p "$out/python"
  run "${python_env[@]}" "$repo/tools/bench/python_overhead.py" --build "$repo/build" \
    --csv "$out/python/python_overhead.csv"
else
  echo "# tools/bench/python_overhead.py skipped: no btf or numpy for /usr/bin/python3 with PYTHONPATH=build/python" >>commands.txt
fi
if ! wanted dask; then
  :
elif PYTHONPATH="$repo/build/python" /usr/bin/python3 -c "import btf, btf.dask, dask, distributed" 2>/dev/null; then
  mkdir -p "$out/dask"
  run "${python_env[@]}" "$repo/tools/bench/dask_scaling.py" --materials 8 --size 16 --threads 1 \
    --csv "$out/dask/dask_scaling.csv"
  run "${python_env[@]}" "$repo/tools/bench/dask_scaling.py" --materials 8 --size 16 \
    --csv "$out/dask/dask_scaling.csv" --append
else
  echo "# tools/bench/dask_scaling.py skipped: no btf.dask, dask or distributed for /usr/bin/python3 with PYTHONPATH=build/python" >>commands.txt
fi

# A run of some benches updates their sections of the page; a full run writes it anew.
/usr/bin/python3 "$repo/tools/results/make_results_page.py" "$out" -o "$repo/docs/results.md" ${BTF_BENCHES:+--update}
