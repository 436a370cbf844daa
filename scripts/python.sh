#!/usr/bin/env bash
# Runs Python with an interpreter that has matplotlib and numpy. Debian's python3-matplotlib installs for
# /usr/bin/python3, while the python3 first on PATH may be another interpreter (pyenv, conda) without it.
# Usage: scripts/python.sh SCRIPT.py [args...]     ($CSHAPES_PYTHON overrides the choice)
set -euo pipefail
for candidate in ${CSHAPES_PYTHON:-} /usr/bin/python3 python3; do
  if command -v "$candidate" >/dev/null 2>&1 && "$candidate" -c 'import matplotlib, numpy' 2>/dev/null; then
    exec "$candidate" "$@"
  fi
done
echo "cshapes: no Python interpreter with matplotlib and numpy found; run scripts/install-deps.sh" \
     "(Debian: python3-matplotlib) or set CSHAPES_PYTHON" >&2
exit 1
