#!/usr/bin/env bash
# The README's main job: installs what is missing, builds, and reruns the paper's experiment.
#
#   experiments/run_paper.sh [--data DIR|MANIFEST] [--out DIR] [any option of `cshapes experiment paper`]
#
# --data   shapes to use: a folder of meshes (class = file name without trailing digits, e.g. cat3.off -> cat)
#          or a manifest.csv. Default: a synthetic articulated dataset that cshapes generates itself
#          (deterministic), so the job runs on a fresh machine with no data. For the paper's TOSCA shapes:
#          --data ../shared/data/tosca5k. Imperfect meshes (non-manifold, several components, ...) are repaired
#          per method and reported per shape (report.md); --strict refuses them instead. Files that are not
#          meshes are ignored; a mesh that cannot be used, or whose canonical form fails by any method, is
#          left out with its reason (stderr, report.md, metrics.json) and the run goes on with the others:
#          the figures are still drawn, and the script then exits with 3 (a partial result), as
#          `cshapes experiment paper` does. --strict stops at the first such shape instead (exit code 1).
# --out    where everything is written (default: results/). Intermediate results are cached there: rerunning
#          after an interruption resumes where it stopped. The folder is this script's: it holds the build
#          log, the generated data and the PDFs beside the experiment's outputs, so the experiment is run with
#          --force (those files stay as they are; a rerun replaces the experiment's own files and removes the
#          ones it no longer writes). Point --out at a folder of its own.
# --pdf    also write every figure as PDF, beside the PNGs (`--figure-format pdf|svg`, passed on to the
#          experiment, draws them in that format instead)
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)

data=""
out="$root/results"
extra=()
pdf=()
while [[ $# -gt 0 ]]; do
  case "$1" in
    --data) data="$2"; shift 2 ;;
    --data=*) data="${1#*=}"; shift ;;
    --out) out="$2"; shift 2 ;;
    --out=*) out="${1#*=}"; shift ;;
    --pdf) pdf=(--pdf); shift ;;
    -h|--help) sed -n '2,15p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) extra+=("$1"); shift ;;
  esac
done

start=$(date +%s)
"$root/scripts/install-deps.sh"
echo "== building (log: $out/build.log)" >&2
mkdir -p "$out"
if ! "$root/scripts/build.sh" >"$out/build.log" 2>&1; then
  tail -30 "$out/build.log" >&2
  echo "run_paper: the build failed; see $out/build.log" >&2
  exit 1
fi
cshapes="$root/build/cshapes"

if [[ -z "$data" ]]; then
  data="$out/data/synthetic"
  if [[ ! -f "$data/manifest.csv" ]]; then
    echo "== no --data given: generating the synthetic dataset into $data" >&2
    "$cshapes" generate dataset --out "$data" --classes 4 --poses 5 --noisy 1 --seed 1
  fi
  data="$data/manifest.csv"
  echo "   (for the paper's TOSCA shapes: experiments/run_paper.sh --data ../shared/data/tosca5k)" >&2
fi

# Exit code 3: the experiment finished but left shapes out (named in report.md); the figures are still drawn
# and the code is passed on. Any other failure stops here.
status=0
"$cshapes" experiment paper --data "$data" --out "$out" --force "${extra[@]}" || status=$?
if [[ $status -ne 0 && $status -ne 3 ]]; then
  exit "$status"
fi

# `cshapes experiment paper` draws the PNGs itself (report.md says when it could not, and how to);
# PDFs are drawn here on request.
if [[ ${#pdf[@]} -gt 0 ]]; then
  echo "== figures as PDF" >&2
  "$root/scripts/python.sh" "$root/build/share/cshapes/plots/paper_figures.py" "$out" --format=pdf
fi
echo "== done in $(( $(date +%s) - start )) s: see $out/report.md" >&2
if [[ $status -eq 3 ]]; then
  echo "run_paper: a partial result: shapes were left out (report.md names them); exit code 3" >&2
fi
exit "$status"
