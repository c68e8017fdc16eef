#!/usr/bin/env bash
# The clang AddressSanitizer + UndefinedBehaviorSanitizer build in build-asan/,
# shared by scripts/fuzz.sh and scripts/sanitize.sh: one configuration (with
# libFuzzer's coverage instrumentation and the fuzz targets), so that the
# second script reuses the first's objects instead of compiling the core again.
#   scripts/asan_build.sh [TARGET...]    (no target: everything)
# Not the Python module: python3 does not load the sanitizer runtimes.
# (float-cast-overflow is off: xsimd's portable exp, which clang's build
# takes, converts the +-inf of exp(-inf) to an integer lane that it then masks
# away; GCC's build, on the hardware conversion, ran clean with it on.)
set -euo pipefail
cd "$(dirname "$0")/.."
FIBRODEM_EXTRA_PACKAGES="clang libclang-rt-14-dev libomp-14-dev" scripts/setup.sh --deps-only
SAN="-fsanitize=fuzzer-no-link,address,undefined -fno-sanitize=float-cast-overflow -fno-sanitize-recover=undefined"
SAN="$SAN -fno-omit-frame-pointer"
LINK="-fsanitize=address,undefined"
# -O1 and line tables only (file and line in the reports' stacks, no
# variables), not RelWithDebInfo's -O2 -g, which came after -O1 and won: the
# fuzz and sanitize stages took 5-10 % less time in CI on 2 cores.
cmake -S . -B build-asan -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo -DFIBRODEM_PYTHON=OFF \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -gline-tables-only -DNDEBUG" \
  -DFIBRODEM_FUZZ=ON -DCMAKE_CXX_FLAGS="$SAN" -DCMAKE_EXE_LINKER_FLAGS="$LINK" \
  -DCMAKE_SHARED_LINKER_FLAGS="$LINK" -DCMAKE_MODULE_LINKER_FLAGS="$LINK" > build-asan.log
targets=()
for t in "$@"; do targets+=(--target "$t"); done
cmake --build build-asan "${targets[@]}" -j "$(nproc 2>/dev/null || echo 2)" >> build-asan.log
