#!/usr/bin/env bash
# README command 2 (and CI): install what is missing, build everything with warnings as errors, run every
# unit test, a short benchmark run, then the suite again under ASan+UBSan and the concurrency tests under
# ThreadSanitizer. Long stress runs and full benchmarks are behind the `stress` and `bench` labels.
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
jobs="$(nproc)"
bash "$root/tools/scripts/install-deps.sh"

build_and_test() {  # build_dir, ctest label regex, extra cmake args...
  local dir="$1" labels="$2"
  shift 2
  cmake -S "$root" -B "$dir" -DSTRATA_WERROR=ON "$@" > /dev/null
  cmake --build "$dir" -j "$jobs"
  ctest --test-dir "$dir" -L "$labels" --output-on-failure -j "$jobs"
}

echo "== release build: unit tests and benchmark smoke run"
build_and_test "$root/build" '^(unit|bench-smoke)$' -DCMAKE_BUILD_TYPE=Release
echo "== ASan + UBSan build: unit tests"
build_and_test "$root/build-asan" '^unit$' -DCMAKE_BUILD_TYPE=Debug -DSTRATA_ASAN=ON -DSTRATA_WITH_BULLET=OFF
echo "== ThreadSanitizer build: concurrency tests"
# oneTBB's shared library is not instrumented, so this build uses the std::thread job system instead.
TSAN_OPTIONS="halt_on_error=1" build_and_test "$root/build-tsan" '^tsan$' -DCMAKE_BUILD_TYPE=Debug -DSTRATA_TSAN=ON \
  -DSTRATA_WITH_TBB=OFF -DSTRATA_WITH_BULLET=OFF
