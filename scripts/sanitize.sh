#!/usr/bin/env bash
# The test suite under AddressSanitizer + UndefinedBehaviorSanitizer: builds into build-asan/
# (optimised, with debug info) and runs every test with CTest; any sanitizer report fails it.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$here/scripts/setup.sh"
cmake -S "$here" -B "$here/build-asan" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DDEXCLOTH_WITH_SANITIZERS=ON -DDEXCLOTH_WITH_BENCH=OFF
cmake --build "$here/build-asan" -j "$(nproc)"
cd "$here/build-asan"
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:strict_string_checks=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
ctest --output-on-failure -j "$(nproc)" "$@"
