#!/usr/bin/env bash
# Builds the libFuzzer targets with clang (ASan + UBSan) and fuzzes the C API for two thirds of a
# bounded time and the topography readers (every format) for the last third.
# Any crash, hang, leak or sanitizer report fails; the input that caused it is left in
# build-fuzz/findings/ -- copy it to fuzz/regressions/ so that ctest replays it forever.
#   scripts/fuzz.sh [seconds]   (default 60)
#   scripts/fuzz.sh --build     (the fuzzer's build only: scripts/test.sh builds it ahead)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
seconds="${1:-60}"
"$root/scripts/setup.sh" clang libclang-rt-14-dev libomp-14-dev
# (RelWithDebInfo at -O1 with line tables only: the reports' files and lines, less of the
# compile's time than -O2; the inputs run short, the instrumentation dominates either way)
cmake -S "$root" -B "$root/build-fuzz" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  "-DCMAKE_C_FLAGS_RELWITHDEBINFO=-O1 -gline-tables-only -DNDEBUG" "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -gline-tables-only -DNDEBUG" \
  -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ -DGFMD_FUZZ=ON \
  -DGFMD_BUILD_TESTS=OFF -DGFMD_BUILD_EXAMPLES=OFF -DGFMD_BUILD_BENCHMARK=OFF -DGFMD_BUILD_FORTRAN=OFF >/dev/null
cmake --build "$root/build-fuzz" -j "$(nproc)" --target fuzz_api fuzz_topography
if [ "$seconds" = "--build" ]; then exit 0; fi
# fuzz TARGET SECONDS CORPUS REGRESSIONS: new inputs go to a scratch corpus of the target's own;
# the checked-in corpus and regressions seed it.  The readers' allocations are bounded by the
# input's length: 256 MB of resident memory is far beyond any input's.
fuzz() {
  local work="$root/build-fuzz/corpus_$1" findings="$root/build-fuzz/findings"
  mkdir -p "$work" "$findings"
  (cd "$findings" && OMP_NUM_THREADS=1 ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 \
    "$root/build-fuzz/fuzz/$1" -max_total_time="$2" -timeout=20 -rss_limit_mb="$5" \
    -print_final_stats=1 "$work" "$3" "$4")
}
fuzz fuzz_api $((seconds * 2 / 3)) "$root/fuzz/corpus" "$root/fuzz/regressions" 2048
fuzz fuzz_topography $((seconds - seconds * 2 / 3)) "$root/fuzz/corpus_topography" "$root/fuzz/regressions_topography" 256
echo "fuzz: ${seconds} s without a finding"
