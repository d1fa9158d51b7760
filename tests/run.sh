#!/usr/bin/env bash
# The whole test suite, as CI runs it (README): every test of the release build, then a second
# build as a farm node has it, without the GL backend (VOXLUX_GL=OFF), under AddressSanitizer and
# UndefinedBehaviorSanitizer and with the CPU kernel's index checks (VOXLUX_BOUNDS_CHECK), running
# the `unit` tests (llvmpipe GL under ASan would be too slow,
# and that build has no GL; the shared-data and slow tests run in the release build).
set -euo pipefail
cd "$(dirname "$0")/.."
ctest --test-dir build --output-on-failure -j2
# -O1: a quicker build than -O3, and still fast enough for the unit tests under the sanitizers.
cmake -S . -B build-sanitize -G Ninja -DCMAKE_BUILD_TYPE=None -DCMAKE_CXX_FLAGS=-O1 -DVOXLUX_GL=OFF \
      -DVOXLUX_SANITIZE=address,undefined -DVOXLUX_BOUNDS_CHECK=ON
cmake --build build-sanitize --target voxlux_tests
ctest --test-dir build-sanitize -L unit --output-on-failure -j2
