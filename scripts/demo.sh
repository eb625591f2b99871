#!/usr/bin/env bash
# The newcomer's first command: install what is missing, build, run the demonstration, plot it.
#   scripts/demo.sh [demo options, e.g. --n 512]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$root/scripts/setup.sh" gnuplot-nox
cmake -S "$root" -B "$root/build" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$root/build" -j "$(nproc)" --target gfmd_demo
out="$root/build/demo"
mkdir -p "$out"
"$root/build/examples/gfmd_demo" --csv "$out/demo.csv" "$@"
gnuplot -e "csv='$out/demo.csv'; out='$out/demo.png'" "$root/examples/plot_demo.gp"
echo "plot: $out/demo.png"
