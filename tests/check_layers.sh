#!/usr/bin/env bash
# The layer order (docs/design.md, "The pipeline"): each folder includes only from itself and the layers below it.
# Prints every include that breaks it and exits 1; registered with CTest as Layering.IncludesFollowTheOrder.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
declare -A allowed=(
  [core]="core"
  [canon]="core canon"
  [matching]="core matching"
  [eval]="core matching eval"
  [pipeline]="core canon matching eval pipeline"
  [experiments]="core canon matching eval pipeline experiments"
  [cli]="core canon matching eval pipeline experiments cli"
  [python]="core canon matching eval pipeline experiments python"
)
bad=0
for layer in "${!allowed[@]}"; do
  while IFS= read -r line; do
    file=${line%%:*}
    target=$(sed -E 's/.*#include "([a-z_]+)\/.*/\1/' <<<"$line")
    if [[ " ${allowed[$layer]} " != *" $target "* ]]; then
      echo "layering: $line  ($layer may include only: ${allowed[$layer]})"
      bad=1
    fi
  done < <(grep -rnE '^#include "[a-z_]+/' "$root/$layer" --include='*.h' --include='*.cpp' || true)
done
[[ $bad == 0 ]] && echo "layering: every include follows core -> canon, matching -> eval -> pipeline -> experiments -> cli, python"
exit $bad
