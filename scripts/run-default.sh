#!/usr/bin/env bash
# Quick start 1: set up, build, and run the default scene.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh --runtime  # the command, plugins and modules: not the tests
build/fibrodem run examples/default.json --out out/default --overwrite "$@"  # (replaces its own earlier output)
echo "Outputs of the default scene are in $(pwd)/out/default (summary.json, biomarkers.csv, traces.csv, run.log)"
