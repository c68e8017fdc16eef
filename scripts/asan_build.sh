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
SAN="$SAN -fno-omit-frame-pointer -g -O1"
LINK="-fsanitize=address,undefined"
cmake -S . -B build-asan -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo -DFIBRODEM_PYTHON=OFF \
  -DFIBRODEM_FUZZ=ON -DCMAKE_CXX_FLAGS="$SAN" -DCMAKE_EXE_LINKER_FLAGS="$LINK" \
  -DCMAKE_SHARED_LINKER_FLAGS="$LINK" -DCMAKE_MODULE_LINKER_FLAGS="$LINK" > build-asan.log
targets=()
for t in "$@"; do targets+=(--target "$t"); done
cmake --build build-asan "${targets[@]}" -j "$(nproc 2>/dev/null || echo 2)" >> build-asan.log
