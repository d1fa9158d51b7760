#!/usr/bin/env bash
# The whole test suite, as CI runs it (README): every test of the release build, then a second
# build as a farm node has it, without the GL backend (VOXLUX_GL=OFF), compiled by clang under
# AddressSanitizer and UndefinedBehaviorSanitizer with the CPU kernel's index checks
# (VOXLUX_BOUNDS_CHECK) and the libFuzzer targets (VOXLUX_FUZZ): its `unit` and `shared-data`
# tests run there (not `gl`: that build has no GL, and llvmpipe under ASan would be too slow; not
# `slow`: over 20 minutes under ASan, over CI's budget), then each fuzz target for 60 s (tests/fuzz/run.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
ctest --test-dir build --output-on-failure -j2
# -O1: a quicker build than -O3, and still fast enough for the tests under the sanitizers.
CXX=clang++ cmake -S . -B build-sanitize -G Ninja -DCMAKE_BUILD_TYPE=None -DCMAKE_CXX_FLAGS=-O1 -DVOXLUX_GL=OFF \
      -DVOXLUX_SANITIZE=address,undefined -DVOXLUX_BOUNDS_CHECK=ON -DVOXLUX_FUZZ=ON
cmake --build build-sanitize --target voxlux_tests voxlux_fuzzers
ctest --test-dir build-sanitize -LE 'gl|slow' --output-on-failure -j2
tests/fuzz/run.sh build-sanitize 60
