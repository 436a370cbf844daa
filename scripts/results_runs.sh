#!/usr/bin/env bash
# Runs every experiment the results page (docs/results.md) reports, into one folder, and copies the figures the
# page embeds into docs/images/results/. The page's tables are read from OUT/*/report.md and the CSV/JSON beside
# them; rerunning resumes from each run's cache/.
#
#   scripts/results_runs.sh [--data DIR] [--out DIR] [--only NAME,...]
#
# NAME: paper, noise, topkids, pose-tosca5k, pose-kids, pose-generated, retrieval. Defaults: --data
# ../shared/data (or $CSHAPES_DATA), --out results-runs.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
data="${CSHAPES_DATA:-$here/../shared/data}"
out="results-runs"
only=""
while [[ $# -gt 0 ]]; do
  case "$1" in
    --data) data="$2"; shift 2 ;;
    --out) out="$2"; shift 2 ;;
    --only) only="$2"; shift 2 ;;
    -h|--help) sed -n '2,9p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "results_runs.sh: unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
done
cshapes="${CSHAPES_CLI:-$here/build/cshapes}"
[[ -x "$cshapes" ]] || { echo "results_runs.sh: no cshapes at $cshapes (build with scripts/build.sh)" >&2; exit 2; }
for d in tosca5k topkids kids; do
  [[ -d "$data/$d" ]] || { echo "results_runs.sh: $data/$d is missing (see ../shared/data/README)" >&2; exit 2; }
done
mkdir -p "$out"
images="$here/docs/images/results"
mkdir -p "$images"

wanted() { [[ -z "$only" || ",$only," == *",$1,"* ]]; }
timed() {  # NAME COMMAND...: runs the command, its log in OUT/NAME.log, its wall time in OUT/NAME.seconds
  local name="$1"; shift
  echo "== $name: $*"
  local start=$SECONDS
  "$@" > "$out/$name.log" 2>&1 || { local rc=$?; echo "$name failed (exit $rc), see $out/$name.log" >&2; return $rc; }
  echo $((SECONDS - start)) > "$out/$name.seconds"
}
# A figure wider than 1,600 pixels is scaled down to that width for the page (Fig. 6 is drawn at 3,100, over
# 1 MiB); the run's own folder keeps the full-size picture.
copy() {
  if [[ ! -f "$1" ]]; then echo "results_runs.sh: $1 was not drawn" >&2; return 0; fi
  /usr/bin/python3 - "$1" "$images/$2" <<'PY'
import sys
from PIL import Image
src, dst = sys.argv[1], sys.argv[2]
im = Image.open(src)
if im.size[0] > 1600:
    im = im.resize((1600, round(im.size[1] * 1600 / im.size[0])), Image.LANCZOS)
im.save(dst, optimize=True)
PY
}

if wanted paper; then
  timed paper "$here/experiments/run_paper.sh" --data "$data/tosca5k" --out "$out/paper"
  for f in "$out"/paper/fig*.png; do copy "$f" "paper_$(basename "$f")"; done
fi
if wanted noise; then
  timed noise "$cshapes" experiment noise --data "$data/tosca5k" --out "$out/noise" --levels 0,1,2,3,4
  copy "$out/noise/noise.png" noise.png
fi
if wanted topkids; then
  timed topkids "$cshapes" experiment topkids --data "$data/topkids" --out "$out/topkids"
  copy "$out/topkids/topkids.png" topkids.png
fi
if wanted pose-tosca5k; then
  timed pose-tosca5k "$cshapes" experiment pose --data "$data/tosca5k" --out "$out/pose-tosca5k"
  copy "$out/pose-tosca5k/pose_residuals.png" pose_residuals_tosca5k.png
fi
if wanted pose-kids; then
  timed pose-kids "$cshapes" experiment pose --data "$data/kids" --out "$out/pose-kids" --methods coulomb,cmds
  copy "$out/pose-kids/pose_residuals.png" pose_residuals_kids.png
fi
if wanted pose-generated; then
  timed generate "$cshapes" generate dataset --out "$out/generated" --classes 4 --poses 6 --noisy 1 \
    --vertices 5000 --seed 2
  timed pose-generated "$cshapes" experiment pose --data "$out/generated" --out "$out/pose-generated"
fi
if wanted retrieval; then
  timed retrieval "$cshapes" experiment retrieval --data "$data/tosca5k" --out "$out/retrieval"
  for f in "$out"/retrieval/figures/*.png; do copy "$f" "retrieval_$(basename "$f")"; done
fi
echo "results in $out; figures copied to docs/images/results/"
