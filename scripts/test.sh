#!/usr/bin/env bash
# The newcomer's second command (and CI's): install what is missing, build and run the whole test
# suite, then again under AddressSanitizer + UndefinedBehaviorSanitizer, the threads test under
# ThreadSanitizer, every unit test under valgrind memcheck, and the fuzzer for 60 s.
#   scripts/test.sh [--quick]   (--quick: the plain build only)
# The MPI library (GFMD_BUILD_MPI) is built and tested in the release build and under ASan + UBSan
# (with leak checks, Open MPI's own allocations suppressed: cmake/GfmdMpi.cmake); the
# ThreadSanitizer and valgrind runs cover the serial library.
# The sanitizer, ThreadSanitizer and fuzzer builds run in the background, at the lowest priority,
# from the release build's start: a build or a ctest leaves a core idle for tens of seconds (its
# links, its serial tests, its last long ones), which they take; the foreground keeps the cores
# whenever it wants them (no test times itself).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
jobs="$(nproc)"
extra=(procps valgrind python3-numpy python3-pytest python3-matplotlib python3-scipy python3-venv python3-pip python3-setuptools python3-wheel python3-mpi4py libopenmpi-dev openmpi-bin libfftw3-mpi-dev)
# the fuzzer's compiler too, in the same apt run (one package index update on a fresh machine)
[ "${1:-}" = "--quick" ] || extra+=(clang libclang-rt-14-dev libomp-14-dev)
"$root/scripts/setup.sh" "${extra[@]}"
passed=0
failed=0
# run_ctest DIR: ctest in DIR; its exit status decides (every test in it passed, or not)
run_ctest() {
  echo "ctest $1 [built at $(elapsed)]"
  if ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
       ctest --test-dir "$1" --output-on-failure -j "$jobs"; then
    echo "ctest $1: all passed"; passed=$((passed + 1))
  else
    echo "ctest $1: FAILED"; failed=$((failed + 1))
  fi
}
summary() { echo "test.sh: $passed passed, $failed failed ($(elapsed))"; [ "$failed" -eq 0 ]; }
# elapsed: the wall time since the script began (each phase's line prints it, to see where it goes)
elapsed() { printf '%d min %02d s' $((SECONDS / 60)) $((SECONDS % 60)); }
# kill_tree PID: PID and every process below it (a background build, the fuzzer and its subshell)
kill_tree() {
  local child
  for child in $(pgrep -P "$1" 2>/dev/null); do kill_tree "$child"; done
  kill "$1" 2>/dev/null || true
}
# A phase that stops the script (set -e) must not leave a background build or the fuzzer behind it.
background=()
declare -A build_pid
trap 'for pid in "${background[@]}"; do kill_tree "$pid"; done' EXIT
# in_background NAME NICENESS COMMAND...: runs the command in the background at that niceness,
# its output in build/NAME.log and its exit status in build/NAME.status (the builds and the
# fuzzer); build_wait NAME waits for a build and prints its log if it failed (the script stops
# then, as it does when a foreground build fails).
in_background() {
  local name="$1" niceness="$2"; shift 2
  rm -f "$root/build/$name.status"
  mkdir -p "$root/build"
  (
    renice -n "$niceness" -p "$BASHPID" >/dev/null # its children (compilers, cmake) inherit it
    status=0
    "$@" >"$root/build/$name.log" 2>&1 || status=$?
    echo "$status" >"$root/build/$name.status"
  ) &
  background+=($!)
  build_pid[$name]=$!
}
build_wait() {
  # until its status is written, or its subshell is gone without writing one (killed)
  while [ ! -f "$root/build/$1.status" ] && kill -0 "${build_pid[$1]}" 2>/dev/null; do sleep 1; done
  if [ "$(cat "$root/build/$1.status" 2>/dev/null)" != 0 ]; then
    cat "$root/build/$1.log"; echo "build $1: FAILED"; exit 1
  fi
  echo "build $1: done [at $(elapsed)]"
}

# (the build functions chain their commands with &&: set -e does not act in a function called
# from the left of ||, as in_background calls them)
# The sanitizer builds with -g1, not Debug's -g: the reports keep their functions, files and lines
# (line tables), without the variables' and types' debug information, which took a sixth of the
# build's CPU time (the ASan + UBSan build on 2 cores: 84 s wall, 159 s user + sys with -g; 70 s,
# 131 s with -g1)
debug_flags=(-DCMAKE_C_FLAGS_DEBUG=-g1 -DCMAKE_CXX_FLAGS_DEBUG=-g1 -DCMAKE_Fortran_FLAGS_DEBUG=-g1)
sanitize_build() {
  cmake -S "$root" -B "$root/build-sanitize" -DCMAKE_BUILD_TYPE=Debug "${debug_flags[@]}" -DGFMD_SANITIZE=ON -DGFMD_BUILD_MPI=ON &&
    cmake --build "$root/build-sanitize" -j "$jobs"
}
tsan_build() {
  cmake -S "$root" -B "$root/build-tsan" -DCMAKE_BUILD_TYPE=Debug "${debug_flags[@]}" -DGFMD_TSAN=ON -DGFMD_BUILD_FORTRAN=OFF \
    -DGFMD_BUILD_EXAMPLES=OFF -DGFMD_BUILD_BENCHMARK=OFF &&
    cmake --build "$root/build-tsan" -j "$jobs" --target test_threads &&
    "$root/scripts/fuzz.sh" --build
}
# The sanitizer builds, one after the other, in the background at the lowest priority from the
# start: they take what the release build and the ctests leave idle (a link, a serial test).
# Each writes its own log and status, which build_wait reads.
background_builds() {
  local status
  for name in sanitize tsan_fuzz; do
    status=0
    if [ "$name" = sanitize ]; then sanitize_build; else tsan_build; fi >"$root/build/$name.log" 2>&1 || status=$?
    echo "$status" >"$root/build/$name.status"
    [ "$status" = 0 ] || { [ "$name" = sanitize ] && echo 1 >"$root/build/tsan_fuzz.status"; break; }
  done
}
echo "== release build: the test suite (with libgfmd_mpi and its tests under mpiexec) [at $(elapsed)]"
cmake -S "$root" -B "$root/build" -DCMAKE_BUILD_TYPE=Release -DGFMD_BUILD_MPI=ON >/dev/null
if [ "${1:-}" != "--quick" ]; then
  rm -f "$root/build/sanitize.status" "$root/build/tsan_fuzz.status"
  echo "== the sanitizer and fuzzer builds begin in the background [at $(elapsed)]"
  in_background builds 19 background_builds
  build_pid[sanitize]=${build_pid[builds]}
  build_pid[tsan_fuzz]=${build_pid[builds]}
fi
cmake --build "$root/build" -j "$jobs"
if [ "${1:-}" = "--quick" ]; then run_ctest "$root/build"; summary; exit $?; fi
run_ctest "$root/build"

echo "== AddressSanitizer + UndefinedBehaviorSanitizer build: the test suite [at $(elapsed)]"
build_wait sanitize
run_ctest "$root/build-sanitize"
build_wait tsan_fuzz

# The fuzzer runs on one core for 60 s: beside the ThreadSanitizer run and the first valgrind
# runs, its output in a log that is printed when it ends. Its exit status goes to a file: the
# valgrind runs below are waited for with `wait -n`, which may reap the fuzzer too.
echo "== fuzzing the C API for 60 s (libFuzzer, ASan + UBSan), in the background [at $(elapsed)]"
in_background fuzz 0 "$root/scripts/fuzz.sh" 60

echo "== ThreadSanitizer: distinct handles in concurrent threads [at $(elapsed)]"
if TSAN_OPTIONS=halt_on_error=1 OMP_NUM_THREADS=1 "$root/build-tsan/tests/test_threads"; then
  echo "tsan test_threads: clean"; passed=$((passed + 1))
else
  echo "tsan test_threads: FAILED"; failed=$((failed + 1))
fi

echo "== valgrind memcheck: every unit test of the release build [at $(elapsed)]"
logs="$root/build/valgrind"
mkdir -p "$logs"
# The unit tests that must run under valgrind (a missing one is a failure, not a skip), and any
# other test_* the build made; the longest first (minutes each under valgrind), so that the two
# at a time end together.
required=(test_newton test_cg_reference test_displacement test_api test_adhesion test_units test_threads
  test_continuation test_plasticity test_multilevel test_checkpoint fortran/test_fortran_bindings test_patches
  test_hertz test_selfaffine test_theory test_sinusoid test_layout test_failed_calls test_green test_topography
  test_free_boundary)
binaries=()
for name in "${required[@]}"; do binaries+=("$root/build/tests/$name"); done
for t in "$root"/build/tests/test_*; do
  case " ${required[*]} " in *" $(basename "$t") "*) ;; *) binaries+=("$t") ;; esac
done
binaries+=("$root/build/fuzz/fuzz_replay")
# valgrind_one BINARY: memcheck on one test binary, its output in $logs/NAME.log, its exit
# status in $logs/NAME.status and its wall seconds in $logs/NAME.seconds (printed with the
# result). The runs go $jobs at a time, the fuzzer counted while it runs: valgrind uses one core
# each.
valgrind_one() {
  local t="$1" name args=()
  name="$(basename "$t")"
  [ "$name" = fuzz_replay ] && args=("$root/fuzz/corpus" "$root/fuzz/regressions")
  local status=0 start=$SECONDS
  (cd "$root/build/tests" && OMP_NUM_THREADS=1 valgrind -q --error-exitcode=99 --leak-check=full \
      --errors-for-leak-kinds=definite,indirect --show-leak-kinds=definite,indirect \
      "$t" "${args[@]}" >"$logs/$name.log" 2>&1) || status=$?
  echo $((SECONDS - start)) >"$logs/$name.seconds"
  echo "$status" >"$logs/$name.status"
}
for t in "${binaries[@]}"; do
  rm -f "$logs/$(basename "$t").status"
  [ -x "$t" ] || continue
  while [ "$(jobs -rp | wc -l)" -ge "$jobs" ]; do wait -n || true; done
  valgrind_one "$t" &
done
wait # the valgrind runs and the fuzzer
trap - EXIT
for t in "${binaries[@]}"; do
  name="$(basename "$t")"
  if [ ! -x "$t" ]; then
    echo "valgrind $name: MISSING ($t was not built)"; failed=$((failed + 1))
  elif [ "$(cat "$logs/$name.status" 2>/dev/null)" = 0 ]; then
    echo "valgrind $name: clean ($(cat "$logs/$name.seconds") s)"; passed=$((passed + 1))
  else
    echo "valgrind $name: FAILED"; tail -n 40 "$logs/$name.log"; failed=$((failed + 1))
  fi
done
echo "== the fuzzer's end [at $(elapsed)]"
if [ "$(cat "$root/build/fuzz.status" 2>/dev/null)" = 0 ]; then
  tail -n 8 "$root/build/fuzz.log"; passed=$((passed + 1))
else
  cat "$root/build/fuzz.log"; echo "fuzz: FAILED"; failed=$((failed + 1))
fi
summary
