#!/bin/sh
# A collection of mixed resolution from a folder of meshes: every mesh remeshed (`cshapes remesh`) to a
# random vertex count in [MIN, MAX], drawn from a seeded generator, so the same seed gives the same sizes.
# The sizes chosen are listed in OUT/sizes.csv. Used by the must-show run of issue 24:
#   scripts/make_mixed_resolution.sh ../shared/data/tosca5k results/mixed 1000 30000 24
# Usage: make_mixed_resolution.sh DATA OUT [MIN [MAX [SEED]]]   (CSHAPES: the binary, default build/cshapes)
set -eu
data=$1 out=$2 min=${3:-1000} max=${4:-30000} seed=${5:-24}
cshapes=${CSHAPES:-$(dirname "$0")/../build/cshapes}
mkdir -p "$out"
files=$(ls "$data" | grep -E '\.(off|ply|obj|stl)$' | sort)
# One size per file, in sorted file order (awk's generator, seeded: portable across shells).
sizes=$(echo "$files" | awk -v seed="$seed" -v lo="$min" -v hi="$max" \
  'BEGIN { srand(seed) } { printf "%s %d\n", $0, lo + int(rand() * (hi - lo + 1)) }')
echo "file,vertices" > "$out/sizes.csv.tmp"
echo "$sizes" | while read -r file n; do
  stem=${file%.*}
  if [ ! -s "$out/$stem.off" ]; then
    "$cshapes" --quiet remesh "$data/$file" -o "$out/$stem.off" --vertices "$n" >/dev/null
  fi
  echo "$stem.off,$n" >> "$out/sizes.csv.tmp"
  echo "$stem: $n vertices"
done
mv "$out/sizes.csv.tmp" "$out/sizes.csv"
