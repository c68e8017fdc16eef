#!/usr/bin/env bash
# The seed paper's results, reproduced: runs every sweep of examples/paper/ (5
# tissue seeds per point) into out/paper/, the electrophysiology sweeps of
# Figs. 4 and 6 again with the myocyte variant brocklehurst2022_tissue into
# out/paper/brocklehurst2022_tissue/, then writes docs/paper/README.md and its
# plots (scripts/paper_report.py). Completed runs are kept between calls (a
# sweep resumes), so an interrupted reproduction continues where it stopped.
#   scripts/paper.sh                   (a local pool over the cores)
#   FIBRODEM_MPI=N scripts/paper.sh    (each sweep under mpirun -n N)
#   scripts/paper.sh --quick [OUT [DOCS]]
#       the Fig. 4 and 6 sweeps at reduced size (one tissue seed, a 0.29 mm wide
#       strip, 400 ms) into OUT (default out/paper_quick) and DOCS (default
#       OUT/docs): the whole pipeline in well under a minute (the tests run it).
# FIBRODEM_BIN: the fibrodem executable (default build/fibrodem).
set -euo pipefail
cd "$(dirname "$0")/.."
quick=0
if [ "${1:-}" = "--quick" ]; then quick=1; shift; fi
if [ $quick = 1 ]; then
  out=${1:-out/paper_quick}; docs=${2:-$out/docs}
else
  out=${1:-out/paper}; docs=${2:-docs/paper}
fi
bin=${FIBRODEM_BIN:-build/fibrodem}
[ -x "$bin" ] || scripts/setup.sh
export FIBRODEM_BIN=$bin
preset=brocklehurst2022_tissue
launcher=()
[ -n "${FIBRODEM_MPI:-}" ] && launcher=(mpirun -n "$FIBRODEM_MPI")
mkdir -p "$out"

run_sweep() {  # sweep file, output folder, log, extra --set arguments...
  local file=$1 dir=$2 log=$3
  shift 3
  local start
  start=$(date +%s)
  "${launcher[@]}" "$bin" sweep "$file" --out "$dir" "$@" > "$log" 2>&1 ||
    echo "   (some runs did not complete: $dir/sweep.md)"
  echo "   $(( $(date +%s) - start )) s"
}

for sweep in examples/paper/*.json; do
  name=$(basename "$sweep" .json)
  ep=0
  case $name in fig4_*|fig6_*) ep=1 ;; esac
  [ $quick = 1 ] && [ $ep = 0 ] && continue
  file=$sweep
  sets=()
  if [ $quick = 1 ]; then
    # The same sweep on one tissue seed; its manifest by absolute path.
    file=$out/quick_$name.json
    python3 - "$sweep" "$file" <<'PY'
import json, os, sys
sweep = json.load(open(sys.argv[1]))
sweep["manifest"] = os.path.abspath(os.path.join(os.path.dirname(sys.argv[1]), sweep["manifest"]))
sweep["seeds"] = 1
json.dump(sweep, open(sys.argv[2], "w"), indent=2)
PY
    sets=(--set tissue.width_mm=0.29 --set duration_ms=400)
  fi
  echo "== $name"
  run_sweep "$file" "$out/$name" "$out/$name.log" "${sets[@]}"
  if [ $ep = 1 ]; then
    echo "== $name, cells.myocyte.variant $preset"
    mkdir -p "$out/$preset"
    run_sweep "$file" "$out/$preset/$name" "$out/$preset/$name.log" "${sets[@]}" \
      --set "cells.myocyte.variant=$preset"
  fi
done
note=""
[ $quick = 1 ] && note="(Reduced size: one tissue seed, a 0.29 mm wide strip, 400 ms; scripts/paper.sh --quick.)"
python3 scripts/paper_report.py "$out" "$docs" --title-note "$note"
