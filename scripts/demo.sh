#!/usr/bin/env bash
# The newcomer's first command: install what is missing, build, run the seed paper's study
# (Putignano, Dapp & Mueser 2016) at a size that takes a few minutes, print the fits and plot
# every figure from the tables:
#   scripts/demo.sh            256^2 grid, lambda_r = 32 lambda_s (a few minutes on 2 cores)
#   scripts/demo.sh --full     the paper's 2048^2 grid, lambda_r = 64 lambda_s (hours)
#   scripts/demo.sh [gfmd_paper options, e.g. --n 512 --bandwidth 32]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$root/scripts/setup.sh" gnuplot-nox python3-numpy python3-matplotlib
cmake -S "$root" -B "$root/build" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$root/build" -j "$(nproc)" --target gfmd_paper
out="$root/build/paper"
mkdir -p "$out"
"$root/build/apps/paper/gfmd_paper" --out "$out" "$@" | tee "$out/study.log"
gnuplot -e "dir='$out'" "$root/apps/paper/plot_paper.gp"
# Beyond the paper (Fig. 8): the pull-off of the adhesive sheets under displacement control, on a
# small grid (64^2: about a minute with the study's sweeps at that size)
pull="$out/pulloff"
mkdir -p "$pull"
"$root/build/apps/paper/gfmd_paper" --n 64 --bandwidth 8 --pulloff --out "$pull" > "$pull/study.log"
sed -n '/^Fig. 8/,/^$/p' "$pull/study.log"
gnuplot -e "dir='$pull'" "$root/apps/paper/plot_paper.gp"
# Pictures of the contact itself (the Python package on the library just built)
GFMD_LIBRARY="$root/build/libgfmd.so" MPLBACKEND=Agg PYTHONDONTWRITEBYTECODE=1 /usr/bin/python3 \
  "$root/examples/python/contact_maps.py" --out "$out"
# How the contact is made: patches of the half-space and the thin sheet at the same A/A0, their
# pressure distributions against Persson's, and a load-unload cycle at a hardness
GFMD_LIBRARY="$root/build/libgfmd.so" MPLBACKEND=Agg PYTHONDONTWRITEBYTECODE=1 /usr/bin/python3 \
  "$root/examples/python/contact_patches.py" --out "$out"
# A measured scan: an instrument's file read, filled, detrended, its spectrum and its contact
GFMD_LIBRARY="$root/build/libgfmd.so" MPLBACKEND=Agg PYTHONDONTWRITEBYTECODE=1 /usr/bin/python3 \
  "$root/examples/python/measured_scan.py" --out "$out"
echo
echo "tables: $out/*.csv"
echo "plots:  $(cd "$out" && ls fig*.png contact_maps.png contact_patches.png measured_scan.png | sed "s|^|$out/|" | tr '\n' ' ') $pull/fig8.png"
