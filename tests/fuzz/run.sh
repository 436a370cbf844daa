#!/usr/bin/env bash
# Builds a libFuzzer target per mesh reader (OFF, PLY, OBJ, STL, TOSCA vert/tri, XYZ) with clang++ and
# AddressSanitizer + UndefinedBehaviorSanitizer into build-fuzz/ (apart from the main build), seeds each with
# small valid files generated here, and runs each for a bounded time, as many at once as there are cores.
# Exits non-zero on any crash, leak, sanitizer report or over-large allocation; prints executions per reader.
#   CSHAPES_FUZZ_SECONDS=N  seconds per reader (default 12, at most 30; 0 skips fuzzing)
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
seconds=${CSHAPES_FUZZ_SECONDS:-12}
if [[ "$seconds" == 0 ]]; then
  echo "fuzz: skipped (CSHAPES_FUZZ_SECONDS=0)"
  exit 0
fi
(( seconds > 30 )) && seconds=30
cxx=${CSHAPES_FUZZ_CXX:-$(command -v clang++ || command -v clang++-14 || true)}
if [[ -z "$cxx" ]]; then
  echo "fuzz: clang++ not found; skipping the fuzzers (apt-get install clang to run them)"
  exit 0
fi

out="$root/build-fuzz"
mkdir -p "$out/obj" "$out/seeds" "$out/corpus" "$out/artifacts"
# The readers' headers as they are included, "cshapes/<room>/<file>.h" (CMakeLists.txt maps them likewise).
mkdir -p "$out/include/cshapes"
for room in support mesh; do ln -sfn "$root/$room" "$out/include/cshapes/$room"; done
eigen=$(pkg-config --cflags eigen3 2>/dev/null || echo -I/usr/include/eigen3)
flags=(-std=c++17 -g -O1 -fno-omit-frame-pointer -fsanitize=address,undefined -fno-sanitize-recover=all
       -I"$out/include" $eigen)
sources=(mesh/io.cpp mesh/io_text.cpp mesh/io_stl.cpp mesh/io_ply.cpp mesh/io_ply_write.cpp mesh/mesh.cpp mesh/mesh_defects.cpp support/atomic_file.cpp)

# Compilations and fuzzers run as many at a time as there are cores (each is one process on one core).
max_jobs=$(nproc)
running=()
drain() {  # waits for every started job; under set -e a failed one ends the script with its status
  local pid
  for pid in "${running[@]}"; do wait "$pid"; done
  running=()
}
spawn() {
  "$@" &
  running+=($!)
  (( ${#running[@]} < max_jobs )) || drain
}

# Rebuild when a source or header is newer than the last build.
newest=$(ls -t "$root"/support/*.h "$root"/mesh/*.h "$root"/tests/fuzz/fuzz_reader.cpp "${sources[@]/#/$root/}" | head -1)
objects=()
for src in "${sources[@]}"; do
  obj="$out/obj/$(basename "${src%.cpp}").o"
  objects+=("$obj")
  if [[ ! -f "$obj" || "$root/$src" -nt "$obj" || "$newest" -nt "$obj" ]]; then
    spawn "$cxx" "${flags[@]}" -fsanitize=fuzzer-no-link -c "$root/$src" -o "$obj"
  fi
done
drain

readers=(off ply obj stl vert xyz)
for fmt in "${readers[@]}"; do
  bin="$out/fuzz_$fmt"
  if [[ ! -x "$bin" || "$newest" -nt "$bin" || "$out/obj/io.o" -nt "$bin" ]]; then
    spawn "$cxx" "${flags[@]}" -fsanitize=fuzzer -DCSHAPES_FUZZ_FORMAT="\"$fmt\"" \
      "$root/tests/fuzz/fuzz_reader.cpp" "${objects[@]}" -o "$bin"
  fi
done
drain

# Seeds: small valid files of every variant the readers handle.
rm -rf "$out/seeds"
seed() { mkdir -p "$out/seeds/$1"; printf "$3" > "$out/seeds/$1/$2"; }
seed off tetra.off 'OFF\n4 4 6\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n'
seed off quad_coff.off 'COFF\n# comment\n4 1 0\n0 0 0 255 0 0 255\n1 0 0 0 255 0 255\n1 1 0 0 0 255 255\n0 1 0 1 1 1 1\n4 0 1 2 3 0.5 0.5 0.5\n'
seed off tri_noff.off 'NOFF 3 1 0\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n3 0 1 2\n'
ply_header='ply\nformat %s 1.0\ncomment seed\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\nproperty uchar red\nproperty uchar green\nproperty uchar blue\nproperty double quality\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n'
seed ply ascii.ply "$(printf "$ply_header" ascii)"'\n0 0 0 255 0 0 0.5\n1 0 0 0 255 0 1\n1 1 0 0 0 255 1.5\n0 1 0 9 9 9 2\n3 0 1 2\n4 0 2 3 1\n'
# Binary seeds, packed by python3 (skipped without it): little endian with colours, a double and a quad;
# big endian with a ushort-counted uint index list.
mkdir -p "$out/seeds/ply" "$out/seeds/stl"
if command -v python3 >/dev/null; then
  python3 - "$out/seeds/ply" "$(printf "$ply_header" binary_little_endian)" <<'PY'
import struct, sys
folder, header = sys.argv[1], sys.argv[2]
corners = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)]
body = b"".join(struct.pack("<3f3Bd", *p, 10, 20, 30, 0.5 * i) for i, p in enumerate(corners))
body += struct.pack("<B3i", 3, 0, 1, 2) + struct.pack("<B4i", 4, 0, 2, 3, 1)
open(folder + "/binary_le.ply", "wb").write(header.encode() + b"\n" + body)
be = (b"ply\nformat binary_big_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      b"property float z\nelement face 1\nproperty list ushort uint vertex_index\nend_header\n")
be += b"".join(struct.pack(">3f", *p) for p in corners[:3]) + struct.pack(">H3I", 3, 0, 1, 2)
open(folder + "/binary_be.ply", "wb").write(be)
stl = b"solid binary header".ljust(80, b" ") + struct.pack("<I", 2)
for tri in ((0, 1, 2), (0, 2, 3)):
    stl += struct.pack("<3f", 0, 0, 1) + b"".join(struct.pack("<3f", *corners[k]) for k in tri) + b"\0\0"
open(folder + "/../stl/binary.stl", "wb").write(stl)
PY
fi
seed ply cloud.ply 'ply\nformat ascii 1.0\nelement vertex 2\nproperty double x\nproperty double y\nproperty double z\nend_header\n0 0 0\n1 2 3\n'
seed obj quad.obj 'v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\ng g\nf 1/1/1 2/1/1 3/1/1 4/1/1\nv 0 0 1\nf -1//1 -5//1 -4//1\nf 5/1 2/1 4/1\n'
seed stl ascii.stl 'solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nfacet normal 0 0 1\nouter loop\nvertex 1 0 0\nvertex 1 1 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid s\n'
seed vert pair.vert '0 0 0\n1 0 0\n0 1 0\n0 0 1\n\x001 3 2\n1 2 4\n1 4 3\n2 3 4\n'
seed xyz points.xyz '# points\n0 0 0\n1 2 3 0 0 1\n-1e-3 4 5.5\n'

# One reader's fuzzer; its exit status goes to fuzz_FMT.rc (the report below reads it).
fuzz_one() {
  local fmt=$1 rc=0
  mkdir -p "$out/corpus/$fmt"
  "$out/fuzz_$fmt" "$out/corpus/$fmt" "$out/seeds/$fmt" -max_total_time="$seconds" -rss_limit_mb=2048 \
    -max_len=8192 -timeout=10 -print_final_stats=1 -artifact_prefix="$out/artifacts/$fmt-" \
    >"$out/fuzz_$fmt.log" 2>&1 || rc=$?
  echo "$rc" >"$out/fuzz_$fmt.rc"
}
rm -f "$out"/fuzz_*.rc
for fmt in "${readers[@]}"; do spawn fuzz_one "$fmt"; done
drain

status=0
for fmt in "${readers[@]}"; do
  log="$out/fuzz_$fmt.log"
  rc=$(cat "$out/fuzz_$fmt.rc" 2>/dev/null || echo "no status")
  execs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || echo "?")
  [[ -z "$execs" ]] && execs="?"
  fmt_upper=$(echo "$fmt" | tr a-z A-Z)
  [[ "$fmt" == vert ]] && fmt_upper="VERT/TRI"
  if [[ "$rc" == 0 ]]; then
    echo "fuzz $fmt_upper: $execs execs, 0 crashes"
  else
    echo "fuzz $fmt_upper: $execs execs, FAILED (exit $rc); log $log, artifacts $out/artifacts/$fmt-*"
    grep -m5 -E 'ERROR|SUMMARY|runtime error|Test unit written' "$log" || tail -20 "$log"
    status=1
  fi
done
exit $status
