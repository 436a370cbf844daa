#!/usr/bin/env bash
# The README's test command: installs what is missing, builds into build/, runs every test with CTest,
# then the Python module's tests (pytest, tests/python) with the interpreter it was built for, the documentation
# site (scripts/docs.py site: the tutorials run and draw their pictures, then mkdocs build --strict), then each mesh
# reader's fuzzer for a bounded time when clang is present. Exits non-zero on any failure and ends with each
# phase's wall time ("time: build N s, ctest N s, ...") and one summary line "tests: N passed, N failed" (CTest
# tests, Python tests and fuzzers together).
#   CSHAPES_FUZZ_SECONDS=N   seconds per fuzzer (default 12, at most 30; 0 skips fuzzing)
set -uo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$root"

# Each phase's wall time, printed before the summary line (the whole run is to stay under 25 minutes).
times=()
phase_start=$SECONDS
phase_done() { times+=("$1 $((SECONDS - phase_start)) s"); phase_start=$SECONDS; }

scripts/install-deps.sh || exit 1
scripts/build.sh || { echo "tests: the build failed"; exit 1; }
phase_done build

# Tests never depend on timing, so threads that sleep while waiting keep a busy machine responsive.
export OMP_WAIT_POLICY=${OMP_WAIT_POLICY:-PASSIVE}
log=$(mktemp)
trap 'rm -f "$log"' EXIT
ctest --test-dir build --output-on-failure -j"$(nproc)" --timeout 900 2>&1 | tee "$log"
ctest_status=${PIPESTATUS[0]}
total=$(sed -n 's/.* tests failed out of \([0-9]*\).*/\1/p' "$log" | tail -1)
failed=$(sed -n 's/.*, \([0-9]*\) tests failed out of.*/\1/p' "$log" | tail -1)
total=${total:-0}
failed=${failed:-0}
[[ $ctest_status -ne 0 && $failed -eq 0 ]] && failed=1
phase_done ctest

# The Python module's tests, from the build tree (PYTHONPATH=build/python).
py_passed=0
py_failed=0
interpreter=$(cat build/python/interpreter 2>/dev/null || true)
if [[ -n "$interpreter" ]] && ls build/python/cshapes/_cshapes*.so >/dev/null 2>&1; then
  PYTHONPATH="$root/build/python${PYTHONPATH:+:$PYTHONPATH}" "$interpreter" -m pytest -q -p no:cacheprovider \
    tests/python 2>&1 | tee "$log"
  py_status=${PIPESTATUS[0]}
  summary=$(grep -E '^(=+ )?[0-9]+ (passed|failed|error)' "$log" | tail -1)
  py_passed=$(grep -oE '[0-9]+ passed' <<<"$summary" | grep -oE '[0-9]+' || echo 0)
  py_failed=$(( $(grep -oE '[0-9]+ failed' <<<"$summary" | grep -oE '[0-9]+' || echo 0) + \
                $(grep -oE '[0-9]+ errors?' <<<"$summary" | grep -oE '[0-9]+' || echo 0) ))
  [[ $py_status -ne 0 && $py_failed -eq 0 ]] && py_failed=1
else
  echo "python: the module was not built (see the CMake output: pybind11-dev, python3-dev)"
  py_failed=1
fi
phase_done pytest

# The documentation site (mkdocs.yml, docs/), built by scripts/docs.py site: the tutorials run (their outputs
# checked) and draw the pictures they show, each compared with the committed one; then mkdocs build --strict
# from a copy of docs/ with those pictures (build/docs-src): a page missing from the navigation, a broken link
# or image, or a picture the tutorial no longer draws fails.
docs_passed=0
docs_failed=0
if PYTHONPATH="$root/build/python${PYTHONPATH:+:$PYTHONPATH}" "${interpreter:-/usr/bin/python3}" \
     scripts/docs.py site build/cshapes 2>&1 | tee "$log"; then
  echo "docs: the site built, tutorials included (build/site)"
  docs_passed=1
else
  echo "docs: the site build FAILED (scripts/docs.py site)"
  docs_failed=1
fi
phase_done docs

fuzz_passed=0
fuzz_failed=0
if [[ -x tests/fuzz/run.sh ]]; then
  tests/fuzz/run.sh 2>&1 | tee "$log"
  fuzz_status=${PIPESTATUS[0]}
  fuzz_passed=$(grep -c '^fuzz .*, 0 crashes$' "$log" || true)
  fuzz_failed=$(grep -c '^fuzz .*FAILED' "$log" || true)
  [[ $fuzz_status -ne 0 && $fuzz_failed -eq 0 ]] && fuzz_failed=1
fi

phase_done fuzz
echo "time: $(printf '%s, ' "${times[@]}")total $SECONDS s"
passed=$(( total - failed + py_passed + docs_passed + fuzz_passed ))
failed=$(( failed + py_failed + docs_failed + fuzz_failed ))
echo "tests: $passed passed, $failed failed"
[[ $ctest_status -eq 0 && $failed -eq 0 ]]
