#!/usr/bin/env bash
# The README's test command: installs what is missing, builds into build/, runs every test with CTest,
# then runs each reader's fuzzer for a bounded time when clang is present. Exits non-zero on any failure.
#   CSHAPES_FUZZ_SECONDS=N   seconds per fuzzer (default 20; 0 skips fuzzing)
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$root"

scripts/install-deps.sh
scripts/build.sh
ctest --test-dir build --output-on-failure -j"$(nproc)" --timeout 900

if [[ -x tests/fuzz/run.sh ]]; then
  tests/fuzz/run.sh
fi
