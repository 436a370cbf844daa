#!/usr/bin/env bash
# The layer order (docs/design.md, "The pipeline"): each folder includes only from itself and the layers below it.
# Prints every include that breaks it and exits 1; registered with CTest as Layering.IncludesFollowTheOrder.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
rooms="support mesh operators geodesics data"
declare -A allowed=(
  [support]="support"
  [mesh]="support mesh"
  [operators]="support mesh operators"
  [geodesics]="support mesh operators geodesics"
  [data]="support mesh operators geodesics data"
  [canon]="$rooms canon"
  [matching]="$rooms matching"
  [eval]="$rooms matching eval"
  [pipeline]="$rooms canon matching eval pipeline"
  [experiments]="$rooms canon matching eval pipeline experiments"
  [cli]="$rooms canon matching eval pipeline experiments cli"
  [python]="$rooms canon matching eval pipeline experiments python"
)
bad=0
for layer in "${!allowed[@]}"; do
  while IFS= read -r line; do
    file=${line%%:*}
    if [[ "$line" =~ \#include\ \"cshapes/([a-z_]+)/ ]]; then
      target=${BASH_REMATCH[1]}
    else
      target=$(sed -E 's/.*#include "([a-z_]+)\/.*/\1/' <<<"$line")
      # A skin's own headers (cli/, python/) are named from the repository; the rooms only as cshapes/ROOM/.
      if [[ "$target" != "$layer" || " $rooms canon matching eval pipeline experiments " == *" $layer "* ]]; then
        echo "layering: $line  (a room's header is included as \"cshapes/ROOM/FILE\")"
        bad=1
        continue
      fi
    fi
    if [[ " ${allowed[$layer]} " != *" $target "* ]]; then
      echo "layering: $line  ($layer may include only: ${allowed[$layer]})"
      bad=1
    fi
  done < <(grep -rnE '^#include "[a-z_]+/' "$root/$layer" --include='*.h' --include='*.cpp' --include='*.inl' || true)
done
[[ $bad == 0 ]] && echo "layering: every include follows support -> mesh -> operators -> geodesics -> data -> canon, matching -> eval -> pipeline -> experiments -> cli, python"
exit $bad
