#!/usr/bin/env bash
# Comments say what the code does and why, never when or on which machine something was measured: figures with
# their date and machine belong in docs/ and docs/changelog.md. Scans the comments of the library's rooms and
# the skins (support mesh operators geodesics data canon matching eval pipeline experiments cli python: *.h *.cpp
# *.inl after "//", *.py *.sh after "#") for dated or lab-note wording and prints file:line for each, exit 1;
# exit 0 when there is none.
# Registered with CTest as Layering.NoDatedNotesInCode.
#   tests/check_dated_notes.sh [ROOT]   ROOT: the source tree to scan (default: this one)
set -euo pipefail
root=${1:-$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)}
root=$(cd "$root" && pwd)
folders=(support mesh operators geodesics data canon matching eval pipeline experiments cli python)

# Case-insensitive: an ISO date, a weekday, re-measured, and the machine a figure came from.
notes='20[0-9][0-9]-[01][0-9]-[0-3][0-9]|\b(mon|tues|wednes|thurs|fri|satur|sun)day\b|\bre-?measured\b'
notes+='|\bthis machine\b|\bdevelopment machine\b|\bmachine shared\b|\bquiet machine\b|\b(slower|faster) day\b'
notes+='|\b[0-9]+-core machine\b|\bmeasured on [0-9]+ cores\b'
# Case-sensitive: a month and a day ("Nov 26", "November 3").
dates='\b(Jan|Feb|Mar|Apr|Jun|Jul|Aug|Sep|Sept|Oct|Nov|Dec|January|February|March|April|June|July|August'
dates+='|September|October|November|December)\.? [0-3]?[0-9]\b'

cd "$root"
present=()
for f in "${folders[@]}"; do [[ -d $f ]] && present+=("$f"); done
[[ ${#present[@]} -gt 0 ]] || { echo "dated notes: none of ${folders[*]} under $root"; exit 2; }

bad=0
while IFS= read -r hit; do
  file=${hit%%:*}
  rest=${hit#*:}
  line=${rest%%:*}
  text=${rest#*:}
  # Only the comment: a whole-line comment, or what follows a comment marker after code.
  case $file in
    *.py | *.sh) marker='#' ;;
    *) marker='//' ;;
  esac
  re="(^|[[:space:]])${marker}(.*)\$"
  [[ $text =~ $re ]] || continue
  comment=${BASH_REMATCH[2]}
  if grep -qiE -- "$notes" <<<"$comment" || grep -qE -- "$dates" <<<"$comment"; then
    echo "dated notes: $file:$line: $(sed -E 's/^[[:space:]]+//' <<<"$text")"
    bad=1
  fi
done < <(grep -rnHE -e "$notes" -e "$dates" -i "${present[@]}" \
           --include='*.h' --include='*.cpp' --include='*.inl' --include='*.py' --include='*.sh' | sort -t: -k1,1 -k2,2n)
if [[ $bad == 0 ]]; then
  echo "dated notes: none in the comments of ${present[*]} (measurements belong in docs/ and docs/changelog.md)"
else
  echo "dated notes: comments say what the code does and why; move when and where it was measured to docs/"
fi
exit $bad
