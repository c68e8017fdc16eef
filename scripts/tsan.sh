#!/usr/bin/env bash
# The threaded paths under ThreadSanitizer: builds
# fibrodem with clang -fsanitize=thread into build-tsan/ and runs the tests
# that share work between threads: the OpenMP loops over blocks of cells and
# DEM contacts (each run on 1, 2 and 3 threads), the sweep's worker threads,
# the background writer of pictures, and the signal handlers. OpenMP is
# LLVM's (libomp), whose synchronisation TSan learns through the Archer tool
# (libarcher, from Debian's libomp-14-dev); GCC's libgomp would show its own
# barriers as races. Any report fails the test (TSan's exit status 66).
#   scripts/tsan.sh [CTEST_OPTIONS...]   (default: the threaded tests)
set -euo pipefail
cd "$(dirname "$0")/.."
FIBRODEM_EXTRA_PACKAGES="clang libclang-rt-14-dev libomp-14-dev" scripts/setup.sh --deps-only
ARCHER=/usr/lib/llvm-14/lib/libarcher.so
[ -f "$ARCHER" ] || { echo "tsan.sh: $ARCHER not found (package libomp-14-dev)" >&2; exit 1; }
SAN="-fsanitize=thread -fno-omit-frame-pointer"
# The default: the tests labelled "threads" (tests/test_labels.cmake.in), and
# only their files built (the stage took 400-449 s instead of 641-704 s); with
# ctest options, every file.
files=""
if [ $# -eq 0 ]; then
  # (No file found: every file is built.)
  files=$(grep -lE 'test_suite\("[^"]*threads' tests/*/test_*.cpp | xargs -r -n1 basename | sed 's/\.cpp$//' |
          paste -sd';' || true)
  set -- -L '^threads$'
fi
# Not the Python module: python3 does not load the sanitizer runtimes. -O1
# and line tables only (file and line in the reports' stacks), as asan_build.sh.
# AVX2 (x86-64-v3), not the host's CPU, so the stage checks the same code on
# every CI host.
cmake -S . -B build-tsan -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo -DFIBRODEM_PYTHON=OFF \
  -DFIBRODEM_ARCH=x86-64-v3 \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -gline-tables-only -DNDEBUG" -DFIBRODEM_TEST_FILES="$files" \
  -DCMAKE_CXX_FLAGS="$SAN" -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=thread" \
  -DCMAKE_SHARED_LINKER_FLAGS="-fsanitize=thread" -DCMAKE_MODULE_LINKER_FLAGS="-fsanitize=thread" > build-tsan.log
cmake --build build-tsan -j "$(nproc 2>/dev/null || echo 2)" >> build-tsan.log
cd build-tsan
export OMP_TOOL_LIBRARIES="$ARCHER"
# (Accesses inside the uninstrumented OpenMP runtime are its own business: the
# recipe of LLVM's Archer documentation.)
export TSAN_OPTIONS="ignore_noninstrumented_modules=1:halt_on_error=1:second_deadlock_stack=1"
export ARCHER_OPTIONS="verbose=1"
ctest --output-on-failure -j "$(nproc 2>/dev/null || echo 2)" "$@"
