#!/usr/bin/env bash
# The newcomer's second command (and CI's): install what is missing, build and run the whole test
# suite, then again under AddressSanitizer + UndefinedBehaviorSanitizer and under valgrind memcheck.
#   scripts/test.sh [--quick]   (--quick: the plain build only)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
jobs="$(nproc)"
"$root/scripts/setup.sh" valgrind

echo "== release build: the test suite"
cmake -S "$root" -B "$root/build" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$root/build" -j "$jobs"
ctest --test-dir "$root/build" --output-on-failure -j "$jobs"
if [ "${1:-}" = "--quick" ]; then exit 0; fi

echo "== AddressSanitizer + UndefinedBehaviorSanitizer build: the test suite"
cmake -S "$root" -B "$root/build-sanitize" -DCMAKE_BUILD_TYPE=Debug -DGFMD_SANITIZE=ON >/dev/null
cmake --build "$root/build-sanitize" -j "$jobs"
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  ctest --test-dir "$root/build-sanitize" --output-on-failure -j "$jobs"

echo "== valgrind memcheck: every unit test of the release build"
logs="$root/build/valgrind"
mkdir -p "$logs"
status=0
for t in "$root"/build/tests/test_*; do
  [ -x "$t" ] || continue
  name="$(basename "$t")"
  if (cd "$root/build/tests" && valgrind -q --error-exitcode=99 --leak-check=full \
        --errors-for-leak-kinds=definite,indirect --show-leak-kinds=definite,indirect \
        "$t" >"$logs/$name.log" 2>&1); then
    echo "valgrind $name: clean"
  else
    echo "valgrind $name: FAILED"; tail -n 40 "$logs/$name.log"; status=1
  fi
done
exit $status
