#!/usr/bin/env bash
# Installs, with apt-get, the Debian packages cshapes needs that are missing. Idempotent; silent when
# everything is present. Usage: scripts/install-deps.sh [--with-optional | --with-anchors]
#   required: compiler, CMake and Ninja, Eigen, CGAL, nanoflann, CLI11, nlohmann-json, Spectra, SuiteSparse,
#             GoogleTest, OpenMPI (mpirun runs and their tests), Python matplotlib (plots), the Python
#             module's pybind11, python3-dev and pytest, mkdocs and mkdocs-material (the documentation site),
#             Universal Ctags (the function sizes of scripts/code_sizes.py)
#   --with-anchors: also the benchmark anchors (scikit-learn, Open3D: scripts/benchmarks.sh)
#   --with-optional: the anchors and clang (fuzzers)
set -euo pipefail

required=(g++ cmake make ninja-build libeigen3-dev libcgal-dev libgmp-dev libmpfr-dev libnanoflann-dev
  libcli11-dev nlohmann-json3-dev libspectra-dev libsuitesparse-dev libgtest-dev libopenmpi-dev openmpi-bin python3
  python3-matplotlib python3-numpy python3-dev pybind11-dev python3-pytest mkdocs mkdocs-material universal-ctags)
anchors=(python3-sklearn python3-open3d)
optional=("${anchors[@]}" clang libomp-dev)

wanted=("${required[@]}")
[[ "${1:-}" == "--with-optional" ]] && wanted+=("${optional[@]}")
[[ "${1:-}" == "--with-anchors" ]] && wanted+=("${anchors[@]}")

missing=()
for pkg in "${wanted[@]}"; do
  status=$(dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null || true)
  [[ "$status" == "install ok installed" ]] || missing+=("$pkg")
done
[[ ${#missing[@]} -eq 0 ]] && exit 0

sudo=""
if [[ $(id -u) -ne 0 ]]; then
  command -v sudo >/dev/null || { echo "install-deps: need root (or sudo) to install: ${missing[*]}" >&2; exit 1; }
  sudo="sudo"
fi
echo "install-deps: installing ${missing[*]}" >&2
export DEBIAN_FRONTEND=noninteractive
# Refresh the package lists only when they are missing or older than a day.
if [[ -z "$(find /var/lib/apt/lists -maxdepth 1 -name '*Packages*' -mmin -1440 2>/dev/null | head -1)" ]]; then
  $sudo apt-get update -qq >&2
fi
$sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >&2
