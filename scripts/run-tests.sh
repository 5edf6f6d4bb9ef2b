#!/usr/bin/env bash
# The test job (also what CI runs, via .ci/run): installs the build and test dependencies, builds
# everything with warnings as errors in build-ci/, and runs the whole test suite.
#   usage: scripts/run-tests.sh           (as root on a fresh Debian 12, or with sudo)
#   env:   JOBS (parallel build and test jobs, default 2)
set -euo pipefail
cd "$(dirname "$0")/.."

bash scripts/install-deps.sh cmake ninja-build g++ pkg-config \
  libcli11-dev nlohmann-json3-dev libcairo2-dev libgtest-dev libbenchmark-dev libgmp-dev libcgal-dev

cmake -S . -B build-ci -G Ninja -DCMAKE_BUILD_TYPE=Release -DMWST_WERROR=ON
cmake --build build-ci -j "${JOBS:-2}"
ctest --test-dir build-ci --output-on-failure -j "${JOBS:-2}"
