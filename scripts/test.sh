#!/usr/bin/env bash
# Quick start 2: set up, build, and run the whole test suite.
set -euo pipefail
cd "$(dirname "$0")/.."
# Chromium (headless) opens each kind of report.html in the suite's browser tests.
FIBRODEM_EXTRA_PACKAGES="chromium ${FIBRODEM_EXTRA_PACKAGES:-}" scripts/setup.sh
cd build
ctest --output-on-failure -j "$(nproc 2>/dev/null || echo 2)"
