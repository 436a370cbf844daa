#!/usr/bin/env bash
# Reruns every benchmark behind docs/benchmarks.md's table and writes one JSON file per row into OUT
# (default: results/benchmarks), then prints every ratio (scripts/benchmark_ratios.py). Each benchmark measures
# its reference in the same run. The rows of the dispatched kernels (Coulomb, SMACOF) are then run again under
# each instruction set this CPU supports (CSHAPES_SIMD=baseline|avx2|avx512, support/simd.h) into
# OUT/simd-TARGET/, for the side-by-side table. On a fresh Debian machine it first installs what is missing,
# the anchors included (scikit-learn and Open3D, Debian's python3-sklearn and python3-open3d), and builds.
#   scripts/benchmarks.sh [OUT] [--data DIR] [--main-job]
#     DIR: tosca5k, default ../shared/data/tosca5k
#     --main-job: also time experiments/run_paper.sh on DIR (six methods, a fresh output folder, no cache)
# Takes 15-20 minutes on 2 cores (remeshing and three waits for an idle machine included); run it on an
# otherwise idle machine. Exits 1 when an anchor could not run. `scripts/benchmark_ratios.py OUT --markdown >
# docs/benchmarks.md` writes the page.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
out="${1:-$root/results/benchmarks}"
data="$root/../shared/data/tosca5k"
main_job=0
shift || true
while [[ $# -gt 0 ]]; do
  case "$1" in
    --data) data="$2"; shift 2 ;;
    --main-job) main_job=1; shift ;;
    *) echo "benchmarks: unknown argument $1 (see the header of $0)" >&2; exit 2 ;;
  esac
done
cshapes="$root/build/cshapes"
"$root/scripts/install-deps.sh" --with-anchors
[[ -x "$cshapes" ]] || "$root/scripts/build.sh"
[[ -d "$data" ]] || { echo "benchmarks: no data at $data (give --data DIR: TOSCA meshes cat0.off, cat1.off, michael0.off)" >&2; exit 1; }
mkdir -p "$out"
# The processor: the Coulomb and SMACOF kernels' last bits depend on its maker (docs/benchmarks.md).
python3 -c "import json, os; model = next((l.split(':', 1)[1].strip() for l in open('/proc/cpuinfo') if l.startswith('model name')), 'unknown'); json.dump({'processor': model, 'cores': os.cpu_count()}, open('$out/machine.json', 'w'))"

bench() {  # bench NAME ARGS...: runs `cshapes -q bench ARGS --json` into DEST/NAME.json (DEST: OUT by default)
  local name=$1 dest=${dest:-$out}
  shift
  echo "== $name${CSHAPES_SIMD:+ (CSHAPES_SIMD=$CSHAPES_SIMD)}: cshapes bench $*" >&2
  "$cshapes" -q bench "$@" --json >"$dest/$name.json.tmp"
  mv "$dest/$name.json.tmp" "$dest/$name.json"
}
wait_idle() {  # waits (at most 3 minutes) for the 1-minute load average to fall below 0.5: timings are idle ones
  local waited=0
  while awk '{exit !($1 >= 0.5)}' /proc/loadavg && [[ $waited -lt 180 ]]; do sleep 5; waited=$((waited + 5)); done
  echo "== load average $(cut -d' ' -f1 /proc/loadavg) after waiting ${waited} s for an idle machine" >&2
}
converged_form() {  # the default Coulomb form of cat0, timed by its own summary, into DEST
  local dest=${dest:-$out}
  echo "== coulomb-cat0-converged${CSHAPES_SIMD:+ (CSHAPES_SIMD=$CSHAPES_SIMD)}: cshapes canon cat0.off --method coulomb" >&2
  "$cshapes" -q canon "$data/cat0.off" -o "$dest/cat0-coulomb.ply" --method coulomb --json >"$dest/coulomb-cat0-converged.json.tmp"
  mv "$dest/coulomb-cat0-converged.json.tmp" "$dest/coulomb-cat0-converged.json"
}
"$cshapes" --version >"$out/version.txt"

# Shapes at the paper's sizes (Table 1), remeshed from TOSCA.
[[ -f "$out/cat3505.off" ]] || "$cshapes" -q remesh "$data/cat0.off" -o "$out/cat3505.off" --vertices 3505
[[ -f "$out/michael22738.off" ]] || "$cshapes" -q remesh "$data/michael0.off" -o "$out/michael22738.off" --vertices 22738

# The iteration rows first: right after the million-point runs the machine needs a while to settle.
wait_idle
bench coulomb-iteration-3505 coulomb-iteration --mesh "$out/cat3505.off"
bench coulomb-iteration-22738 coulomb-iteration --mesh "$out/michael22738.off"
bench coulomb-3505 coulomb --points 3505 --mesh "$data/cat0.off"
bench coulomb-22738 coulomb --points 22738 --mesh "$data/cat0.off"
bench coulomb-100000 coulomb --points 100000 --mesh "$data/cat0.off"
bench coulomb-1000000-surface coulomb --points 1000000 --mesh "$data/cat0.off" --repeats 3 --fast-repeats 3
bench coulomb-1000000-uniform coulomb --points 1000000 --distribution uniform --repeats 3 --fast-repeats 3
bench geodesics-3505 geodesics --mesh "$out/cat3505.off" --anchor-samples 3505 --exact-samples 4
bench geodesics-22738 geodesics --mesh "$out/michael22738.off" --anchor-samples 64 --exact-samples 2 --fmm-samples 32
wait_idle  # after the geodesics' minutes on both cores
bench smacof-3505 smacof --points 3505
bench smacof-22738 smacof --points 22738 --iterations 5
bench smacof-cat0-acceleration smacof --mesh "$data/cat0.off" --acceleration --smacof-tolerance 1e-6
bench icp icp --a "$data/cat0.off" --b "$data/cat1.off"
# One form by each method against full classical MDS in the same run: the spectral forms at the paper's sizes,
# every method at 50,000 vertices (there the n × n reference needs 10 GB and minutes: timed once, in the
# Coulomb row; the landmark MDS rows are the issue's goal, ≤ 60 s and ≤ 2 GB).
for method in lbo diffusion spectral-mds; do
  bench form-$method-5000 form --mesh "$data/cat0.off" --method $method
  bench form-$method-22738 form --mesh "$out/michael22738.off" --method $method
done
[[ -f "$out/michael50000.off" ]] || "$cshapes" -q remesh "$data/michael0.off" -o "$out/michael50000.off" --vertices 50000
bench form-coulomb-50000 form --mesh "$out/michael50000.off" --method coulomb --repeats 1
for method in cmds smacof lbo diffusion spectral-mds; do
  bench form-$method-50000 form --mesh "$out/michael50000.off" --method $method --repeats 1 --reference none
done
# A whole canonical form with the default options (not a bench: its JSON summary has seconds and iterations).
converged_form

# The dispatched kernels' rows under every instruction set this CPU supports, one after the other.
wait_idle
for target in $("$cshapes" --version | sed -n 's/^kernels: .*this CPU: \(.*\))$/\1/p' | tr -d ','); do
  dest="$out/simd-$target"
  mkdir -p "$dest"
  export CSHAPES_SIMD=$target
  "$cshapes" --version >"$dest/version.txt"
  bench coulomb-iteration-3505 coulomb-iteration --mesh "$out/cat3505.off"
  bench coulomb-iteration-22738 coulomb-iteration --mesh "$out/michael22738.off"
  bench coulomb-22738 coulomb --points 22738 --mesh "$data/cat0.off"
  bench coulomb-100000 coulomb --points 100000 --mesh "$data/cat0.off"
  bench smacof-3505 smacof --points 3505
  converged_form
  unset CSHAPES_SIMD dest
done

# The main job: the README's experiment on tosca5k, six methods, from nothing (no cache).
if [[ $main_job -eq 1 ]]; then
  rm -rf "$out/main-job"
  echo "== main-job: experiments/run_paper.sh --data $data --out $out/main-job" >&2
  start=$(date +%s.%N)
  "$root/experiments/run_paper.sh" --data "$data" --out "$out/main-job" >"$out/main-job.log" 2>&1
  end=$(date +%s.%N)
  python3 -c "import json,sys; json.dump({'seconds': $end - $start, 'command': 'experiments/run_paper.sh --data $data'}, open('$out/main-job.json', 'w'))"
fi
echo "benchmarks: JSON in $out" >&2
echo
"$root/scripts/benchmark_ratios.py" "$out"
