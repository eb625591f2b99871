#!/usr/bin/env bash
# Installs, on Debian or Ubuntu, the packages gfmd needs that are missing (needs root or sudo).
#   scripts/setup.sh [extra-package ...]
set -euo pipefail
pkgs=(cmake make g++ gcc gfortran pkg-config libfftw3-dev liblapacke-dev libcmocka-dev libzip-dev libxml2-dev "$@")
missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi
echo "setup: installing ${missing[*]}"
sudo=""
if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
$sudo apt-get update -qq
DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
