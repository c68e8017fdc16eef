#!/usr/bin/env bash
# The test suite under AddressSanitizer + UndefinedBehaviorSanitizer: builds everything with clang into build-asan/
# (scripts/asan_build.sh, shared with scripts/fuzz.sh) and runs ctest there, with any ctest options given (e.g. -R or -E to pick tests).
# Leaks inside fontconfig (Cairo's font cache, not fibrodem's) are
# suppressed (tests/lsan.supp); anything else fails the test.
#   scripts/sanitize.sh [CTEST_OPTIONS...]
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/asan_build.sh
cd build-asan
export ASAN_OPTIONS="detect_leaks=1"
export LSAN_OPTIONS="suppressions=$(pwd)/../tests/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
ctest --output-on-failure -j "$(nproc 2>/dev/null || echo 2)" "$@"
