#!/usr/bin/env bash
# README command 2 (and CI): install what is missing, build everything with warnings as errors, run every
# unit test and a short benchmark run, bake a level on a single-node Slurm, install the build and a physics-only build and use each from
# tests/package through find_package(Strata), then the suite again under ASan+UBSan, the concurrency tests
# under ThreadSanitizer and a short fixed run of each libFuzzer target. Long stress runs, full benchmarks and
# long fuzzing are behind the `stress`, `bench` and `fuzz` labels.
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
jobs="$(nproc)"
bash "$root/tools/scripts/install-deps.sh" test

build_and_test() {  # build dir, build targets ("all" for everything), ctest label regex, cmake args...
  local dir="$1" targets="$2" labels="$3"
  shift 3
  # Tests on explicitly: README command 1 configures build/ without them, and a cached OFF would leave this
  # stage with nothing to run.
  cmake -S "$root" -B "$dir" -DSTRATA_WERROR=ON -DSTRATA_BUILD_TESTS=ON "$@" > /dev/null
  # shellcheck disable=SC2086 # the targets are a word list
  cmake --build "$dir" --target $targets -j "$jobs"
  ctest --test-dir "$dir" -L "$labels" --output-on-failure --no-tests=error -j "$jobs"
}

test_targets="strata_tests strata_allocation_tests"
echo "== release build: unit tests, benchmark smoke runs, the installed package used by a consumer project," \
  "a farm bake on a single-node Slurm"
build_and_test "$root/build" all '^(unit|bench-smoke|package|slurm)$' -DCMAKE_BUILD_TYPE=Release
echo "== physics-only build (no navmesh, assets, tools or Bullet): installed and used by the consumer project"
cmake -S "$root" -B "$root/build-physics-only" -DSTRATA_WERROR=ON -DCMAKE_BUILD_TYPE=Release \
  -DSTRATA_BUILD_NAVMESH=OFF -DSTRATA_BUILD_ASSETS=OFF -DSTRATA_WITH_BULLET=OFF > /dev/null
cmake --build "$root/build-physics-only" -j "$jobs"
cmake -DSTRATA_BUILD_DIR="$root/build-physics-only" -DCONSUMER_SOURCE_DIR="$root/tests/package" \
  -DWORK_DIR="$root/build-physics-only/package" -DCOMPONENTS=physics -P "$root/tests/package/RunConsumer.cmake"
echo "== ASan + UBSan build: unit tests"
build_and_test "$root/build-asan" "$test_targets" '^unit$' -DCMAKE_BUILD_TYPE=Debug -DSTRATA_ASAN=ON \
  -DSTRATA_WITH_BULLET=OFF
echo "== ThreadSanitizer build: concurrency tests"
# oneTBB's shared library is not instrumented, so this build uses the std::thread job system instead.
TSAN_OPTIONS="halt_on_error=1" build_and_test "$root/build-tsan" "$test_targets" '^tsan$' -DCMAKE_BUILD_TYPE=Debug \
  -DSTRATA_TSAN=ON -DSTRATA_WITH_TBB=OFF -DSTRATA_WITH_BULLET=OFF
echo "== libFuzzer build (clang, ASan + UBSan): a short fixed run of each fuzzer"
cmake -S "$root" -B "$root/build-fuzz" -DCMAKE_CXX_COMPILER=clang++ -DSTRATA_FUZZ=ON -DSTRATA_WERROR=ON \
  -DSTRATA_BUILD_TOOLS=OFF -DSTRATA_BUILD_TESTS=OFF -DSTRATA_WITH_TBB=OFF -DSTRATA_WITH_BULLET=OFF > /dev/null
cmake --build "$root/build-fuzz" -j "$jobs"
ctest --test-dir "$root/build-fuzz" -L '^fuzz-smoke$' --output-on-failure --no-tests=error -j "$jobs"
