#!/usr/bin/env bash
# The test job (also what CI runs, via .ci/run): installs the build and test dependencies, then
#   1. builds everything with warnings as errors in build-ci/ (Release) and runs the whole suite,
#      then installs it into a scratch prefix and builds and runs examples/cpp/ against it, and runs
#      the Python package's pytest suite (python/tests) and imports it installed;
#   2. builds the GoogleTest suite (mwst_tests, and the CLI it runs) again with AddressSanitizer +
#      UndefinedBehaviorSanitizer (-DMWST_SANITIZE=ON, -O1) in build-asan/ with clang and runs it (the
#      CGAL differential tests are left out there: their compile time does not fit the CI budget;
#      clang builds this tree in about 360 s and runs it in about 300 s on two cores, GCC took about
#      490 s and 375 s);
#   3. builds the libFuzzer harnesses of fuzz/ with clang in build-fuzz/ and runs each for a bounded
#      time with a fixed seed on a scratch copy of data/ (data/ itself is never written), two at a
#      time (one per core). A crash leaves its input in build-fuzz/artifacts/ and fails the job.
#   usage: scripts/run-tests.sh           (as root on a fresh Debian 12, or with sudo)
#   env:   JOBS (parallel build and test jobs, default 2)
#          FUZZ_SECONDS (per harness, default 30; 0 skips step 3)
#          SKIP_ASAN=1 skips step 2
#          SHARED_EXAMPLES=1 also builds libmwst.so and runs examples/cpp/ against it (step 1)
set -euo pipefail
cd "$(dirname "$0")/.."
jobs="${JOBS:-2}"
fuzz_seconds="${FUZZ_SECONDS:-30}"

bash scripts/install-deps.sh cmake ninja-build g++ pkg-config \
  libcli11-dev nlohmann-json3-dev libcairo2-dev libgtest-dev libbenchmark-dev libgmp-dev libcgal-dev \
  clang libclang-rt-14-dev \
  python3-dev python3-pybind11 pybind11-dev python3-numpy python3-scipy python3-pytest python3-matplotlib

step() { echo "== run-tests: $1 ($(date -u +%H:%M:%S))" >&2; }
started=$SECONDS

# 1. Release build, warnings as errors, every suite.
step "release build and tests"
cmake -S . -B build-ci -G Ninja -DCMAKE_BUILD_TYPE=Release -DMWST_WERROR=ON -DMWST_BUILD_PYTHON=ON
cmake --build build-ci -j "$jobs"
ctest --test-dir build-ci --output-on-failure -j "$jobs"
echo "== run-tests: release: $((SECONDS - started)) s" >&2

# 1b. The installed package: mwst installed into a scratch prefix, and the three programs of
#     examples/cpp/ built against that prefix alone (find_package(mwst 0.4 CONFIG)) and run.
t=$SECONDS
step "installed package and examples/cpp"
consumers=$(mktemp -d)
cmake --install build-ci --prefix "$consumers/prefix" >/dev/null
bash examples/cpp/run.sh "$consumers/prefix" "$consumers/work"
# The same against a shared libmwst.so (opt-in: a second build of the library and the CLI, several
# CPU minutes more without ccache).
if [ "${SHARED_EXAMPLES:-0}" = 1 ]; then
  cmake -S . -B build-shared -G Ninja -DCMAKE_BUILD_TYPE=Release -DMWST_WERROR=ON -DBUILD_SHARED_LIBS=ON \
    -DMWST_BUILD_TESTS=OFF -DMWST_BUILD_CGAL_TESTS=OFF
  cmake --build build-shared -j "$jobs" --target mwst_cli
  cmake --install build-shared --prefix "$consumers/shared" >/dev/null
  bash examples/cpp/run.sh "$consumers/shared" "$consumers/work-shared"
fi
rm -rf "$consumers"
echo "== run-tests: installed package: $((SECONDS - t)) s" >&2

# 1c. The Python package (python/, built into build-ci/python by step 1): its pytest suite, which
#     compares it with build-ci/mwst; then `cmake --install --component python` into a scratch
#     prefix, and the installed copy imported and run from there.
t=$SECONDS
step "python package"
PYTHONDONTWRITEBYTECODE=1 PYTHONPATH="$PWD/build-ci/python" MWST_CLI="$PWD/build-ci/mwst" \
  /usr/bin/python3 -m pytest -q -p no:cacheprovider python/tests
pyprefix=$(mktemp -d)
cmake --install build-ci --component python --prefix "$pyprefix" >/dev/null
installed=$(dirname "$(find "$pyprefix" -path '*/mwst/__init__.py')")
(cd "$pyprefix" && PYTHONDONTWRITEBYTECODE=1 PYTHONPATH="$(dirname "$installed")" /usr/bin/python3 -c '
import sys, mwst, mwst.triangle
assert mwst.__file__.startswith(sys.argv[1]), mwst.__file__
mesh = mwst.triangulate([[0, 0], [1, 0], [1, 1], [0, 1]], [[0, 1], [1, 2], [2, 3], [3, 0]], method="dr", max_area=0.01)
assert mwst.check(mesh, [[0, 0], [1, 0], [1, 1], [0, 1]], [[0, 1], [1, 2], [2, 3], [3, 0]]).ok
print("installed mwst", mwst.__version__, "in", sys.argv[1], "works:", mesh)
' "$installed")
rm -rf "$pyprefix"
echo "== run-tests: python package: $((SECONDS - t)) s" >&2

# 2. The GoogleTest suite under ASan + UBSan. -O1 keeps the instrumented build and run fast enough;
#    no NDEBUG, so assertions are on as well.
if [ "${SKIP_ASAN:-0}" != 1 ]; then
  t=$SECONDS
  step "sanitizer build and tests"
  # (No -Werror here: step 1 enforces GCC's warnings; this step is about what the sanitizers find.)
  CC=clang CXX=clang++ cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1" -DMWST_SANITIZE=ON -DMWST_WERROR=OFF \
    -DMWST_BUILD_CGAL_TESTS=OFF
  cmake --build build-asan -j "$jobs"
  LSAN_OPTIONS="suppressions=$PWD/scripts/lsan-suppressions.txt:print_suppressions=0" \
  ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:strict_string_checks=1" \
  UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1" \
    ctest --test-dir build-asan --output-on-failure -j "$jobs"
  echo "== run-tests: sanitizers: $((SECONDS - t)) s" >&2
fi

# 3. libFuzzer harnesses (clang), each for $fuzz_seconds on a scratch corpus seeded from data/.
if [ "$fuzz_seconds" -gt 0 ]; then
  t=$SECONDS
  step "fuzz build"
  # -O1 (no NDEBUG: assertions on), as OSS-Fuzz builds fuzzers: measured against -O3, 233 instead of
  # 321 CPU s of compile, and about 15 % fewer executions of fuzz_triangulate in the same time.
  CC=clang CXX=clang++ cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1" -DMWST_BUILD_FUZZ=ON -DMWST_BUILD_TESTS=OFF -DMWST_BUILD_CGAL_TESTS=OFF
  cmake --build build-fuzz -j "$jobs" --target fuzz_node fuzz_poly fuzz_ele fuzz_triangulate
  scratch=$(mktemp -d)
  trap 'rm -rf "$scratch"' EXIT
  mkdir -p build-fuzz/artifacts
  # One harness for $fuzz_seconds on its scratch corpus; its log in the scratch directory.
  fuzz_one() {
    local harness=$1 corpus="$scratch/$1"
    mkdir -p "$corpus"
    case "$harness" in
      fuzz_node) cp data/*.node "$corpus/" ;;
      fuzz_poly) cp data/*.poly "$corpus/" ;;
      fuzz_ele) cp tests/regression/*.ele tests/regression/*.area "$corpus/" ;;
      *) cp data/*.node data/*.poly "$corpus/" ;;
    esac
    # -seed fixes libFuzzer's choices; -timeout flags any single input slower than 60 s;
    # -rss_limit_mb any that needs more than 2 GB.
    "build-fuzz/fuzz/$harness" -seed=1 -max_total_time="$fuzz_seconds" -timeout=60 -rss_limit_mb=2048 \
      -print_final_stats=1 -artifact_prefix="build-fuzz/artifacts/$harness-" "$corpus" \
      >"$scratch/$harness.log" 2>&1
  }
  # Reports a harness's run; fails the job if it failed.
  fuzz_report() {
    local harness=$1 status=$2
    if [ "$status" -ne 0 ]; then
      tail -n 60 "$scratch/$harness.log" >&2
      echo "run-tests: $harness failed (exit $status); the input is in build-fuzz/artifacts/" >&2
      exit 1
    fi
    echo "== run-tests: $harness:" >&2
    grep -E '^(Done|stat::number_of_executed_units|stat::peak_rss_mb)|INITED|cov:.*DONE' "$scratch/$harness.log" | tail -n 4 >&2
  }
  # Two at a time (the machine has two cores): the readers together, then the whole pipeline.
  step "fuzz_node and fuzz_poly for $fuzz_seconds s each, side by side"
  status_node=0
  status_poly=0
  fuzz_one fuzz_node & pid_node=$!
  fuzz_one fuzz_poly || status_poly=$?
  wait "$pid_node" || status_node=$?
  fuzz_report fuzz_node "$status_node"
  fuzz_report fuzz_poly "$status_poly"
  step "fuzz_triangulate and fuzz_ele for $fuzz_seconds s each, side by side"
  status=0
  status_ele=0
  fuzz_one fuzz_ele & pid_ele=$!
  fuzz_one fuzz_triangulate || status=$?
  wait "$pid_ele" || status_ele=$?
  fuzz_report fuzz_triangulate "$status"
  fuzz_report fuzz_ele "$status_ele"
  echo "== run-tests: fuzz: $((SECONDS - t)) s" >&2
fi
echo "== run-tests: all passed in $((SECONDS - started)) s" >&2
