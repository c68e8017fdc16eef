#!/usr/bin/env bash
# The test suite under AddressSanitizer + UndefinedBehaviorSanitizer (issue
# "Nothing lost"): builds everything with clang into build-asan/ and runs
# ctest there, with any ctest options given (e.g. -R or -E to pick tests).
# Leaks inside fontconfig (Cairo's font cache, not fibrodem's) are
# suppressed (tests/lsan.supp); anything else fails the test.
#   scripts/sanitize.sh [CTEST_OPTIONS...]
set -euo pipefail
cd "$(dirname "$0")/.."
FIBRODEM_EXTRA_PACKAGES="clang libclang-rt-14-dev libomp-14-dev" scripts/setup.sh --deps-only
# (float-cast-overflow is off: xsimd's portable exp, which clang's build
# takes, converts the +-inf of exp(-inf) to an integer lane that it then masks
# away; GCC's build, on the hardware conversion, ran clean with it on.)
SAN="-fsanitize=address,undefined -fno-sanitize=float-cast-overflow -fno-sanitize-recover=undefined"
SAN="$SAN -fno-omit-frame-pointer -g -O1"
LINK="-fsanitize=address,undefined"
# Not the Python module: python3 does not load the sanitizer runtimes.
cmake -S . -B build-asan -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo -DFIBRODEM_PYTHON=OFF \
  -DCMAKE_CXX_FLAGS="$SAN" -DCMAKE_EXE_LINKER_FLAGS="$LINK" -DCMAKE_SHARED_LINKER_FLAGS="$LINK" \
  -DCMAKE_MODULE_LINKER_FLAGS="$LINK" > build-asan.log
cmake --build build-asan -j "$(nproc 2>/dev/null || echo 2)" >> build-asan.log
cd build-asan
export ASAN_OPTIONS="detect_leaks=1"
export LSAN_OPTIONS="suppressions=$(pwd)/../tests/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
ctest --output-on-failure -j "$(nproc 2>/dev/null || echo 2)" "$@"
