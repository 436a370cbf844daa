#!/usr/bin/env bash
# The scaling table of docs/scale-out.md: `distmat` (exact mode, Coulomb) on N generated shapes of 1,000 vertices with
# R = 1 process (all cores as threads) and R = 2 MPI ranks (the cores split between them), each from an empty
# cache, then the two-stage mode (--two-stage-k K, recall against the exact matrix). One JSON line per run:
# wall seconds (canonical forms, pairs, I/O), the pair stage's seconds and pairs per second, and whether the
# R = 2 matrix is byte-identical to R = 1's. Take it on an idle machine.
# Usage: scripts/scaling.sh [--two-stage K] N [N ...]     (WORK=/tmp/cshapes-scaling by default)
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cli="$root/build/cshapes"
work=${WORK:-/tmp/cshapes-scaling}
k=0
[[ "${1:-}" == "--two-stage" ]] && { k=$2; shift 2; }
mkdir -p "$work"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1

run() {  # N R LABEL ARGS...: one timed distmat from an empty cache
  local n=$1 ranks=$2 label=$3; shift 3
  local out="$work/N$n.$label.csv" cache="$work/cache.N$n.$label"
  rm -rf "$cache"
  local launcher=()
  [[ $ranks -gt 1 ]] && launcher=(mpirun --oversubscribe -np "$ranks")
  local start end json
  start=$(date +%s.%N)
  json=$("${launcher[@]}" "$cli" --quiet distmat "$work/gen$n" -o "$out" --method coulomb --cache "$cache" --json "$@")
  end=$(date +%s.%N)
  /usr/bin/python3 - "$n" "$ranks" "$label" "$start" "$end" "$json" <<'PY'
import json, sys
n, ranks, label, start, end, text = sys.argv[1:]
j = json.loads(text)
wall = float(end) - float(start)
row = {"N": int(n), "R": int(ranks), "run": label, "wall_seconds": round(wall, 1),
       "pairs": j["pairs"], "pairs_computed": j["pairs_computed"], "pair_seconds": round(j["seconds"], 1),
       "pairs_per_second": round(j["pairs_computed"] / j["seconds"], 1) if j["seconds"] > 0 else None,
       "forms_computed": j["forms_computed"]}
if "two_stage" in j:
    row["two_stage"] = j["two_stage"]
print(json.dumps(row), flush=True)
PY
}

for n in "$@"; do
  if [[ ! -f "$work/gen$n/manifest.csv" ]]; then
    classes=4; (( n % 4 == 0 )) || classes=2
    per=$(( n / classes )); noisy=$(( per / 10 )); (( noisy > 0 )) || noisy=1
    "$cli" --quiet generate dataset --out "$work/gen$n" --classes "$classes" --poses $(( per - noisy )) \
      --noisy "$noisy" --vertices 1000 --seed 1 >/dev/null
  fi
  run "$n" 1 R1
  run "$n" 2 R2
  if cmp -s "$work/N$n.R1.csv" "$work/N$n.R2.csv"; then
    echo "{\"N\": $n, \"R1_R2_byte_identical\": true}"
  else
    echo "{\"N\": $n, \"R1_R2_byte_identical\": false}"
  fi
  if [[ $k -gt 0 ]]; then
    run "$n" 1 "twostage$k" --two-stage-k "$k" --reference "$work/N$n.R1.csv"
  fi
done
