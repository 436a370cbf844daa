#!/usr/bin/env bash
# The C++ package: installs the library part of a build (`cmake --install BUILD --component dev`) into a
# temporary prefix, configures and builds tests/consumer/ against it with find_package(cshapes), and runs it;
# then the same for examples/own_method/ (a method registered by a program of its own, in experiment retrieval).
# Usage: tests/check_consumer.sh BUILD_DIR. Registered with CTest as Package.AConsumerBuildsAgainstTheInstalledTree.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=$(cd "$1" && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cmake --install "$build" --prefix "$work/prefix" --component dev >/dev/null
test -f "$work/prefix/include/cshapes/pipeline/canonical_forms.h"
test -f "$work/prefix/lib/cmake/cshapes/cshapesConfig.cmake"
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
cmake -S "$root/tests/consumer" -B "$work/build" -DCMAKE_PREFIX_PATH="$work/prefix" -DCMAKE_BUILD_TYPE=Release \
  "${launcher[@]}" >/dev/null
cmake --build "$work/build" >/dev/null
"$work/build/consumer"
echo "package: tests/consumer built against $work/prefix and ran"
# The C++ door of docs/outside-methods.md: a method registered by a program of its own, in an experiment.
cmake -S "$root/examples/own_method" -B "$work/own" -DCMAKE_PREFIX_PATH="$work/prefix" -DCMAKE_BUILD_TYPE=Release \
  "${launcher[@]}" >/dev/null
cmake --build "$work/own" >/dev/null
"$work/own/own_method" "$work/own-run" | tee "$work/own.txt"
grep -q "^principal-axes: mAP " "$work/own.txt"
grep -q "^lbo: mAP " "$work/own.txt"
echo "package: examples/own_method built against $work/prefix and ran its method in experiment retrieval"
