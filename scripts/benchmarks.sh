#!/usr/bin/env bash
# Reruns every benchmark behind docs/benchmarks.md's table and writes one JSON file per row into OUT
# (default: results/benchmarks), then prints every ratio (scripts/benchmark_ratios.py). Each benchmark measures
# its reference in the same run. On a fresh Debian machine it first installs what is missing, the anchors
# included (scikit-learn and Open3D, Debian's python3-sklearn and python3-open3d), and builds.
#   scripts/benchmarks.sh [OUT] [--data DIR]     (DIR: tosca5k, default ../shared/data/tosca5k)
# Takes a few minutes on 2 cores (remeshing included); run it on an otherwise idle machine. Exits 1 when an
# anchor could not run.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
out="${1:-$root/results/benchmarks}"
data="$root/../shared/data/tosca5k"
[[ "${2:-}" == "--data" ]] && data="$3"
cshapes="$root/build/cshapes"
"$root/scripts/install-deps.sh" --with-anchors
[[ -x "$cshapes" ]] || "$root/scripts/build.sh"
[[ -d "$data" ]] || { echo "benchmarks: no data at $data (give --data DIR: TOSCA meshes cat0.off, cat1.off, michael0.off)" >&2; exit 1; }
mkdir -p "$out"

bench() {  # bench NAME ARGS...: runs `cshapes -q bench ARGS --json` into OUT/NAME.json
  local name=$1
  shift
  echo "== $name: cshapes bench $*" >&2
  "$cshapes" -q bench "$@" --json >"$out/$name.json.tmp"
  mv "$out/$name.json.tmp" "$out/$name.json"
}

# Shapes at the paper's sizes (Table 1), remeshed from TOSCA.
[[ -f "$out/cat3505.off" ]] || "$cshapes" -q remesh "$data/cat0.off" -o "$out/cat3505.off" --vertices 3505
[[ -f "$out/michael22738.off" ]] || "$cshapes" -q remesh "$data/michael0.off" -o "$out/michael22738.off" --vertices 22738

# The iteration rows first: right after the million-point runs the machine needs a while to settle.
bench coulomb-iteration-3505 coulomb-iteration --mesh "$out/cat3505.off"
bench coulomb-iteration-22738 coulomb-iteration --mesh "$out/michael22738.off"
bench coulomb-3505 coulomb --n 3505 --mesh "$data/cat0.off"
bench coulomb-22738 coulomb --n 22738 --mesh "$data/cat0.off"
bench coulomb-100000 coulomb --n 100000 --mesh "$data/cat0.off"
bench coulomb-1000000-surface coulomb --n 1000000 --mesh "$data/cat0.off" --repeats 3
bench coulomb-1000000-uniform coulomb --n 1000000 --distribution uniform --repeats 3
bench geodesics-3505 geodesics --mesh "$out/cat3505.off" --anchor-samples 3505 --exact-samples 4
bench geodesics-22738 geodesics --mesh "$out/michael22738.off" --anchor-samples 64 --exact-samples 2 --fmm-samples 32
bench smacof-3505 smacof --n 3505
bench smacof-22738 smacof --n 22738 --iters 5
bench smacof-cat0-acceleration smacof --mesh "$data/cat0.off" --acceleration --tolerance 1e-6
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
echo "== coulomb-cat0-converged: cshapes canon cat0.off --method coulomb" >&2
"$cshapes" -q canon "$data/cat0.off" -o "$out/cat0-coulomb.ply" --method coulomb --json >"$out/coulomb-cat0-converged.json.tmp"
mv "$out/coulomb-cat0-converged.json.tmp" "$out/coulomb-cat0-converged.json"
echo "benchmarks: JSON in $out" >&2
echo
"$root/scripts/benchmark_ratios.py" "$out"
