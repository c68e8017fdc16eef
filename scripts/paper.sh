#!/usr/bin/env bash
# The seed paper's results, reproduced (issue "Sweeps that scale past one
# machine", part 5): runs every sweep of examples/paper/ (5 tissue seeds per
# point) into out/paper/, then writes docs/paper/README.md (scripts/paper_report.py).
# Completed runs are kept between calls (a sweep resumes), so an interrupted
# reproduction continues where it stopped.
#   scripts/paper.sh               (a local pool over the cores)
#   FIBRODEM_MPI=N scripts/paper.sh  (each sweep under mpirun -n N)
set -euo pipefail
cd "$(dirname "$0")/.."
[ -x build/fibrodem ] || scripts/setup.sh
launcher=()
[ -n "${FIBRODEM_MPI:-}" ] && launcher=(mpirun -n "$FIBRODEM_MPI")
for sweep in examples/paper/*.json; do
  name=$(basename "$sweep" .json)
  echo "== $name"
  start=$(date +%s)
  "${launcher[@]}" build/fibrodem sweep "$sweep" --out "out/paper/$name" > "out/paper_$name.log" 2>&1 ||
    echo "   (some runs did not complete: out/paper/$name/sweep.md)"
  echo "   $(( $(date +%s) - start )) s"
done
python3 scripts/paper_report.py out/paper docs/paper
