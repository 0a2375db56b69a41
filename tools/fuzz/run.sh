#!/usr/bin/env bash
# Builds the libFuzzer targets of every reader (tests/fuzz, clang with ASan + UBSan) and runs each
# for SECONDS (default 30; one target per core at a time), then prints executions, coverage and
# crashes per target.
#   tools/fuzz/run.sh [SECONDS] [TARGET...]    e.g. tools/fuzz/run.sh 1800 fuzz_btfz
#   tools/fuzz/run.sh --make-corpus            rewrite the seeds in tests/fuzz/corpus/ (not the regression-* inputs)
# Seeds are read from tests/fuzz/corpus/<target>/ (committed, never written); what the fuzzer adds
# goes to build-fuzz/corpus/<target>/ and findings to build-fuzz/findings/<target>/. A finding
# becomes a regression input in tests/fuzz/corpus/ and a named test of the ordinary suite.
# BTF_FUZZ_SEED=N fixes libFuzzer's seed (CI uses 1, so that a run is repeatable); by default each
# run draws its own. BTF_FUZZ_RUNS=N also stops a target after N executions (the long campaign:
# 10 million executions or SECONDS, whichever comes first). Exit status: 0 when no target found anything, 1 otherwise.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
cd "$root"
build=build-fuzz
jobs=$(nproc 2>/dev/null || echo 2)

# clang and its libFuzzer runtime (Debian 12: clang 14), and llvm-14 for llvm-symbolizer: without
# it a finding's stack names no function, and the LeakSanitizer suppressions (which match function
# names) match nothing. The library's own dependencies come from tools/setup/run.sh.
packages=(clang libclang-rt-14-dev llvm-14)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "== installing ${missing[*]}"
  sudo=(); [ "$(id -u)" -ne 0 ] && sudo=(sudo)
  export DEBIAN_FRONTEND=noninteractive
  "${sudo[@]}" apt-get update -qq
  "${sudo[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

# The flags OSS-Fuzz builds with: -O1 and line tables only, so stack traces name lines and the
# build (every library source, instrumented) stays short.
echo "== building the fuzz targets in $build (clang, -fsanitize=fuzzer,address,undefined)"
CC=clang CXX=clang++ cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=None -DBTF_BUILD_FUZZERS=ON \
  -DCMAKE_CXX_FLAGS="-O1 -gline-tables-only" >/dev/null
cmake --build "$build" -j"$jobs"

if [ "${1:-}" = "--make-corpus" ]; then
  # The seeds are rewritten; the regression inputs (regression-*) are findings, kept as they are.
  find tests/fuzz/corpus -type f ! -name 'regression-*' -delete 2>/dev/null || true
  ASAN_OPTIONS=detect_leaks=0 "$build/fuzz/make_corpus" tests/fuzz/corpus
  find tests/fuzz/corpus -type f | sort
  exit 0
fi

seconds=${1:-30}
shift || true
targets=("$@")
if [ ${#targets[@]} -eq 0 ]; then
  for f in tests/fuzz/fuzz_*.cpp; do
    t=$(basename "$f" .cpp)
    [ "$t" = fuzz_support ] || targets+=("$t")
  done
fi

# Every input must finish in well under a second (-timeout is the hard bound, under the
# sanitizers) and within 2 GB; no image beyond libbtf's default size limit (0.8 GB) needs more.
export PATH=/usr/lib/llvm-14/bin:$PATH  # llvm-symbolizer, found by the sanitizers on PATH
export ASAN_OPTIONS=detect_leaks=1:allocator_may_return_null=0
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
export LSAN_OPTIONS=suppressions=$root/tests/fuzz/lsan.supp:print_suppressions=0
status=0
summary=()
# Findings of earlier runs stay in $build/findings for a look; only this run's are counted.
stamp=$(mktemp); trap 'rm -f "$stamp"' EXIT

# One target: fuzzes it, then writes its summary line (and, when it failed, the lines that say
# why) to $build/logs/<target>.report, and returns 1 when it failed or found anything.
fuzz_target() {
  local t=$1
  local work=$build/corpus/$t findings=$build/findings/$t log=$build/logs/$t.log report=$build/logs/$t.report
  mkdir -p "$work" "$findings" "$build/logs"
  local options=(); [ -f "tests/fuzz/dict/$t.dict" ] && options=(-dict="tests/fuzz/dict/$t.dict")
  [ -n "${BTF_FUZZ_SEED:-}" ] && options+=(-seed="$BTF_FUZZ_SEED")
  [ -n "${BTF_FUZZ_RUNS:-}" ] && options+=(-runs="$BTF_FUZZ_RUNS")
  echo "== $t: ${seconds} s"
  local rc=0
  "$build/fuzz/$t" "$work" "tests/fuzz/corpus/$t" "${options[@]}" -max_total_time="$seconds" -timeout=2 \
    -rss_limit_mb=2048 -max_len=16384 -print_final_stats=1 -artifact_prefix="$findings/" >"$log" 2>&1 || rc=$?
  # A target that dies before its first input prints none of these: each read tolerates that
  # (pipefail) so that the summary still names the target and its log.
  local execs rate cov found
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1 || true)
  rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log" | tail -1 || true)
  cov=$({ grep -oE 'cov: [0-9]+ ft: [0-9]+' "$log" || true; } | tail -1)
  found=$(find "$findings" -type f -newer "$stamp" | wc -l)
  printf '%-16s %10s execs %7s/s  %-22s %s finding(s)\n' "$t" "${execs:-?}" "${rate:-?}" "${cov:-cov: ?}" "$found" >"$report"
  if [ "$rc" -ne 0 ] || [ "$found" -ne 0 ]; then
    {
      echo "   FAILED (exit $rc): see $log and $findings/"
      # The lines that say why, or the log's end when none of them is there (a target that could
      # not start at all).
      if grep -qE "ERROR|SUMMARY|fuzz finding|terminate called|what\(\)" "$log"; then
        grep -E "ERROR|SUMMARY|fuzz finding|terminate called|what\(\)" "$log" | head -5
      else
        tail -15 "$log"
      fi
    } >>"$report"
    return 1
  fi
}

# Targets run side by side, one per core (BTF_FUZZ_JOBS=N to change): each still gets SECONDS of
# one core, and a short run of every target (CI's) takes half the time on two cores. Each target
# writes its inputs to a folder of its own process (fuzz_support.cpp), so they do not collide.
parallel=${BTF_FUZZ_JOBS:-$jobs}
running=0
for t in "${targets[@]}"; do rm -f "$build/logs/$t.report"; done
for t in "${targets[@]}"; do
  if [ "$running" -ge "$parallel" ]; then wait -n || true; running=$((running - 1)); fi
  fuzz_target "$t" &
  running=$((running + 1))
done
wait || true
status=0
echo "== fuzzing summary (${seconds} s per target)"
for t in "${targets[@]}"; do
  report=$build/logs/$t.report
  if [ -s "$report" ]; then cat "$report"; else printf '%-16s no report (the script failed before it)\n' "$t"; status=1; fi
  [ "$(wc -l <"$report" 2>/dev/null || echo 0)" -gt 1 ] && status=1
done
exit $status
