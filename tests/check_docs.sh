#!/usr/bin/env bash
# The documentation against the program (scripts/docs.py), one CTest test per mode:
#   tests/check_docs.sh reference BUILD   docs/reference/cli.md is what the commands' --help say now
#   tests/check_docs.sh commands BUILD    every `cshapes COMMAND --option` in README.md and docs/ exists
#   tests/check_docs.sh tutorial BUILD    docs/tutorial-cli.md and the shell blocks of docs/outside-methods.md run
#                                         from top to bottom in an empty folder, each
#                                         step printing what the page shows under it
#   tests/check_docs.sh history BUILD     the Results section of the site holds under 5% dated or history text
#   tests/check_docs.sh readme-table BUILD  README.md's "Results at a glance" table is the results page's
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
mode=$1
build=$(cd "$2" && pwd)
python=/usr/bin/python3
[[ -x $python ]] || python=python3
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
case "$mode" in
  reference)
    "$python" "$root/scripts/docs.py" cli-reference "$build/cshapes" "$scratch/cli.md"
    if ! diff -u "$root/docs/reference/cli.md" "$scratch/cli.md"; then
      echo "docs/reference/cli.md is out of date: run scripts/docs.py cli-reference build/cshapes docs/reference/cli.md" >&2
      exit 1
    fi ;;
  commands)
    "$python" "$root/scripts/docs.py" check-commands "$build/cshapes" "$root/README.md" "$root"/docs/*.md ;;
  tutorial)
    "$python" "$root/scripts/docs.py" run-shell "$root/docs/tutorial-cli.md" "$scratch/tutorial" "$build/cshapes"
    "$python" "$root/scripts/docs.py" run-shell "$root/docs/outside-methods.md" "$scratch/outside" "$build/cshapes" ;;
  history)
    "$python" "$root/scripts/check_pages.py" results ;;
  readme-table)
    "$python" "$root/scripts/check_pages.py" readme-table "$root/README.md" "$root/docs/results.md" ;;
  *)
    echo "usage: tests/check_docs.sh reference|commands|tutorial|history|readme-table BUILD" >&2
    exit 2 ;;
esac
