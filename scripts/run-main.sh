#!/usr/bin/env bash
# The main job: installs what building mwst needs, builds it (Release, in build/), then runs the
# paper's experiments (Table 1, Figures 3 and 4) into results/ and prints Table 1 beside the
# paper's figures (see EXPERIMENTS.md).
#   usage: scripts/run-main.sh            (as root on a fresh Debian 12, or with sudo)
#   env:   JOBS (parallel build jobs, default 2)
set -euo pipefail
cd "$(dirname "$0")/.."

bash scripts/install-deps.sh cmake ninja-build g++ pkg-config \
  libcli11-dev nlohmann-json3-dev libcairo2-dev libgmp-dev gnuplot-nox

cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release \
  -DMWST_BUILD_TESTS=OFF -DMWST_BUILD_CGAL_TESTS=OFF
cmake --build build --target mwst_cli -j "${JOBS:-2}"

build/mwst experiment all --data data --out results
cat results/table1.md
