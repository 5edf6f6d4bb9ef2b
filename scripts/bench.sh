#!/usr/bin/env bash
# scripts/bench.sh — builds build-bench (Release, -DMWST_BUILD_BENCH=ON) and runs the benchmarks,
# each against its peer library in the same run (bench/README.md), tee-ing the tables to
# results/bench/NAME.md.
#
#   scripts/bench.sh                     every bench/bench_*.cpp
#   scripts/bench.sh bench_delaunay      only these (names of bench/*.cpp without .cpp)
#   BENCH_ARGS="--quick" scripts/bench.sh bench_delaunay     extra arguments for every benchmark
#
# Environment: BUILD_DIR (default build-bench), OUT_DIR (default results/bench), JOBS (default 2:
# the machines have two cores).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${BUILD_DIR:-$root/build-bench}
out=${OUT_DIR:-$root/results/bench}
jobs=${JOBS:-2}

if [ $# -gt 0 ]; then
  names=("$@")
else
  names=()
  for f in "$root"/bench/bench_*.cpp; do names+=("$(basename "$f" .cpp)"); done
fi

bash "$root/scripts/install-deps.sh" cmake ninja-build g++ pkg-config \
  libcli11-dev nlohmann-json3-dev libcairo2-dev libgmp-dev libcgal-dev
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DMWST_BUILD_BENCH=ON \
  -DMWST_BUILD_TESTS=OFF >/dev/null
# The command line is timed as a whole process when it builds; the benchmarks run without it.
ninja -C "$build" -j "$jobs" mwst_cli || echo "bench.sh: mwst_cli did not build; its rows are omitted" >&2
ninja -C "$build" -j "$jobs" "${names[@]}"

mkdir -p "$out"
status=0
for name in "${names[@]}"; do
  echo "== $name"
  # shellcheck disable=SC2086
  if ! "$build/bench/$name" ${BENCH_ARGS:-} | tee "$out/$name.md"; then
    echo "bench.sh: $name failed" >&2
    status=1
  fi
done
exit $status
