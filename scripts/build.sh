#!/usr/bin/env bash
# Configures and builds cshapes into build/ (Release). Usage: scripts/build.sh [extra cmake args]
# With Ninja (Debian's ninja-build, which scripts/install-deps.sh installs), a room's files compile while the
# rooms below it are still being built, where Make waits for them: a cold build keeps both cores busy.
# A build/ configured before keeps its generator; -G in the arguments chooses another.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
args=()
# ccache, when present, makes rebuilds of other checkouts and branches cheap.
command -v ccache >/dev/null && args+=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
generator_given=false
for a in "$@"; do [[ "$a" == -G* ]] && generator_given=true; done
if [[ ! -f "$root/build/CMakeCache.txt" ]] && ! $generator_given && command -v ninja >/dev/null; then
  args+=(-G Ninja)
fi
cmake -S "$root" -B "$root/build" -DCMAKE_BUILD_TYPE=Release "${args[@]}" "$@" >/dev/null
cmake --build "$root/build" -j"$(nproc)"
