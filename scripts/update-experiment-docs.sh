#!/usr/bin/env bash
# Re-runs the paper's experiments (`mwst experiment all`, see EXPERIMENTS.md) and copies the files
# EXPERIMENTS.md shows into docs/experiments/. The numbers quoted in EXPERIMENTS.md's prose are not
# updated: re-read it against docs/experiments/table1.md afterwards.
#   usage: scripts/update-experiment-docs.sh          (after building build/mwst, e.g. by scripts/run-main.sh)
#   env:   MWST (the binary, default build/mwst), OUT (results directory, default results)
set -euo pipefail
cd "$(dirname "$0")/.."

mwst="${MWST:-build/mwst}"
out="${OUT:-results}"
"$mwst" experiment all --data data --out "$out"
mkdir -p docs/experiments
for f in table1.md table1.csv figure3.csv figure3.png figure3_all.png \
         figure4_Ellipse.png figure4_Florida.png figure4_Plate.png figure4_Superior.png figure4_Kuzmin2K.png; do
  cp "$out/$f" docs/experiments/
done
echo "updated docs/experiments/ from $out/" >&2
