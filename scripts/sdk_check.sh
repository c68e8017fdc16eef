#!/usr/bin/env bash
# The plugin SDK as a plugin author meets it: install fibrodem into a
# temporary prefix, write a skeleton of each kind with `fibrodem new-model`,
# build each out of tree against the install (CMake: find_package(fibrodem);
# the ionic one also with pkg-config and a bare compiler line), check that a
# plugin's headers come from the SDK and the C++ library only, and run each
# skeleton's test manifest with `fibrodem run` (ctest in the skeleton); and
# the same for a CellML model through `fibrodem import-cellml`. The skeletons
# are built with no build type (Release, the SDK's default), Debug and
# RelWithDebInfo.
#   scripts/sdk_check.sh [BUILD_DIR]   (default build; built already)
# About 10 s on 2 cores (70 s with the machine loaded by other jobs).
set -euo pipefail
cd "$(dirname "$0")/.."
build=$(realpath "${1:-build}")
work=$(mktemp -d "${TMPDIR:-/tmp}/fibrodem_sdk.XXXXXX")
trap 'rm -rf "$work"' EXIT
prefix=$work/prefix

cmake --install "$build" --prefix "$prefix" >/dev/null
fibrodem=$prefix/bin/fibrodem
for f in lib/cmake/fibrodem/fibrodemConfig.cmake lib/cmake/fibrodem/fibrodemConfigVersion.cmake \
         lib/cmake/fibrodem/FibrodemPlugin.cmake lib/pkgconfig/fibrodem.pc \
         include/fibrodem/model/cell_model.hpp include/fibrodem/mechanics/contact_law_plugin.hpp \
         include/fibrodem/xsimd/xsimd.hpp lib/fibrodem/plugins/libfibrodem_colman.so \
         lib/fibrodem/plugins/libfibrodem_contact_law_linear_bond.so; do
  [ -f "$prefix/$f" ] || { echo "sdk_check: the install lacks $f" >&2; exit 1; }
done

# The installed package must not look for any of the core's dependencies.
if grep -nE '^[[:space:]]*(find_dependency|find_package|find_path|find_library)[[:space:]]*\(' \
     "$prefix/lib/cmake/fibrodem/fibrodemConfig.cmake" "$prefix/lib/cmake/fibrodem/FibrodemPlugin.cmake"; then
  echo "sdk_check: the CMake package searches for dependencies (above)" >&2; exit 1
fi

# One build type each: none (the SDK then chooses Release), Debug (-O0, where
# GCC 12 and xsimd 8 once failed on AVX-512) and RelWithDebInfo.
declare -A build_type=([ionic]="" [myofilament]=Debug [contact-law]=RelWithDebInfo)
for kind in ionic myofilament contact-law; do
  name=sdk_${kind//-/_}
  printed=$("$fibrodem" new-model "$name" --kind "$kind" --dir "$work/$name")
  grep -q -- "cmake -S .* -DCMAKE_BUILD_TYPE=Release" <<<"$printed" ||
    { echo "sdk_check: new-model prints no cmake line with -DCMAKE_BUILD_TYPE=Release:" >&2; echo "$printed" >&2; exit 1; }
  # Only CMake and the install: no other prefix on the search path.
  cmake -S "$work/$name" -B "$work/$name/build" ${build_type[$kind]:+-DCMAKE_BUILD_TYPE=${build_type[$kind]}} \
        -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF >/dev/null
  chosen=$(sed -n 's/^CMAKE_BUILD_TYPE:[A-Z]*=//p' "$work/$name/build/CMakeCache.txt")
  [ "$chosen" = "${build_type[$kind]:-Release}" ] ||
    { echo "sdk_check: $name configured as '$chosen', expected '${build_type[$kind]:-Release}'" >&2; exit 1; }
  cmake --build "$work/$name/build" >/dev/null
  # Every header the plugin includes is the SDK's or the compiler's.
  flags=$(PKG_CONFIG_PATH=$prefix/lib/pkgconfig pkg-config --cflags fibrodem)
  # shellcheck disable=SC2086
  foreign=$(c++ $flags -M "$work/$name/$name.cpp" | tr ' \\' '\n\n' | grep '^/' |
            grep -v -e "^$prefix/" -e '^/usr/include/c++/' -e '^/usr/lib/gcc/' \
                    -e '^/usr/include/x86_64-linux-gnu/' -e '^/usr/include/aarch64-linux-gnu/' \
                    -e '^/usr/include/[a-z_0-9-]*\.h$' -e '^/usr/include/\(linux\|asm-generic\|sys\|bits\)/' \
                    -e "^$work/$name/" || true)
  if [ -n "$foreign" ]; then
    echo "sdk_check: $name includes headers from outside the SDK:" >&2; echo "$foreign" >&2; exit 1
  fi
  ctest --test-dir "$work/$name/build" --output-on-failure >/dev/null ||
    { ctest --test-dir "$work/$name/build" --output-on-failure; exit 1; }
  grep -q '"status": "completed"' "$work/$name/build/test_run/summary.json" ||
    { echo "sdk_check: $name's test run did not complete" >&2; exit 1; }
  echo "sdk_check: $kind skeleton $name built out of tree ($chosen) and ran"
done

# A CellML model imported with `fibrodem import-cellml` builds out of tree
# with the CMakeLists.txt it writes, and runs (Hodgkin-Huxley 1952, written
# for the importer's tests). Its name has a capital, as a CellML model's own
# name often does: the importer and fibrodem_add_cell_model share one rule.
printed=$("$fibrodem" import-cellml tests/cellml/hh_1952_1_0.cellml --name sdk_HH --out "$work/sdk_HH")
grep -q -- "cmake -S .* -DCMAKE_BUILD_TYPE=Release" <<<"$printed" ||
  { echo "sdk_check: import-cellml prints no cmake line with -DCMAKE_BUILD_TYPE=Release:" >&2; echo "$printed" >&2; exit 1; }
cmake -S "$work/sdk_HH" -B "$work/sdk_HH/build" -DCMAKE_BUILD_TYPE=Release \
      -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF >/dev/null
cmake --build "$work/sdk_HH/build" >/dev/null
so=$(find "$work/sdk_HH/build" -name 'libfibrodem_sdk_HH.so' | head -1)
[ -n "$so" ] || { echo "sdk_check: the imported sdk_HH built no libfibrodem_sdk_HH.so" >&2; exit 1; }
cat > "$work/sdk_HH.json" <<JSON
{"fibrodem": 1, "name": "sdk_HH", "duration_ms": 20,
 "tissue": {"builder": "single_cell", "type": "myocyte"},
 "cells": {"myocyte": {"model": "sdk_HH"}},
 "stimulus": [{"target": "myocyte", "start_ms": 2, "duration_ms": 1, "amplitude_pA": 2000}],
 "solver": {"method": "rush_larsen", "dt_ms": 0.01}}
JSON
FIBRODEM_PLUGIN_PATH=$(dirname "$so") "$fibrodem" run "$work/sdk_HH.json" --out "$work/sdk_HH_run" --quiet \
  --no-report >/dev/null
grep -q '"status": "completed"' "$work/sdk_HH_run/summary.json" ||
  { echo "sdk_check: the imported sdk_HH's run did not complete" >&2; exit 1; }
echo "sdk_check: CellML import sdk_HH built out of tree and ran"

# Other build systems: pkg-config and a bare compiler line.
mkdir -p "$work/pc"
# shellcheck disable=SC2046
c++ $(PKG_CONFIG_PATH=$prefix/lib/pkgconfig pkg-config --cflags fibrodem) -O2 -fPIC -shared \
    -fvisibility=hidden "$work/sdk_ionic/sdk_ionic.cpp" -o "$work/pc/libfibrodem_sdk_ionic.so"
# (The listing is taken whole first: `plugins | grep -q` under pipefail fails
# whenever grep matches and exits before fibrodem has written the rest.)
listed=$(FIBRODEM_PLUGIN_PATH=$work/pc "$fibrodem" plugins)
grep -q "^sdk_ionic 0.1.0 (ionic)" <<<"$listed" ||
  { echo "sdk_check: the pkg-config build of sdk_ionic is not listed by fibrodem plugins" >&2; exit 1; }
echo "sdk_check: pkg-config build listed by fibrodem plugins"
echo "sdk_check: passed"
