#!/usr/bin/env bash
# Installs what fibrodem needs from Debian 12 packages (only what is missing)
# and builds it in ./build (Release). Safe to run again.
#   scripts/setup.sh [--deps-only | --runtime]
#   (--deps-only: install, do not build; --runtime: build only what running a
#   scene needs, the command, plugins and modules, not the tests or the
#   Python module; FIBRODEM_EXTRA_PACKAGES="...": more packages, e.g.
#   scripts/fuzz.sh's clang)
set -euo pipefail
cd "$(dirname "$0")/.."

# libvalijson-dev: checks manifests against schema/*.schema.json.
# libscotch-dev: splits a tissue's cell graph over the ranks of an mpirun.
# python3-*, pybind11-dev: the Python module (python/); matplotlib: its plots and examples/python;
# pip, setuptools, wheel, venv: `pip install --no-build-isolation .` (docs/guide/python.md).
packages=(build-essential cmake pkg-config libeigen3-dev libsundials-dev libboost-dev
          nlohmann-json3-dev libspdlog-dev doctest-dev libcli11-dev libbenchmark-dev nettle-dev
          libcairo2-dev libpng-dev zlib1g-dev libxsimd-dev libpugixml-dev libvalijson-dev libopenmpi-dev openmpi-bin
          libscotch-dev
          python3-dev pybind11-dev python3-numpy python3-pytest python3-matplotlib
          python3-pip python3-setuptools python3-wheel python3-venv
          ${FIBRODEM_EXTRA_PACKAGES:-})
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "fibrodem setup: installing ${missing[*]}"
  sudo=""
  [ "$(id -u)" -ne 0 ] && sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

[ "${1:-}" = "--deps-only" ] && exit 0
jobs=$(nproc 2>/dev/null || echo 2)
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
target=()
[ "${1:-}" = "--runtime" ] && target=(--target fibrodem_runtime)
cmake --build build -j "$jobs" "${target[@]}"
