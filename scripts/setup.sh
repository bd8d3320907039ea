#!/usr/bin/env bash
# Set-up for rodend: install the Debian 12 packages the project needs (only the
# missing ones), then configure and build. Non-interactive and idempotent.
#
#   bash scripts/setup.sh            # Release build in ./build
#   RODEND_BUILD_DIR=build-asan RODEND_CMAKE_ARGS="-DRODEND_SANITIZE=ON" bash scripts/setup.sh
#   RODEND_BUILD_TARGETS=rodend_tests bash scripts/setup.sh   # only the unit-test executable
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(
  build-essential cmake pkg-config git
  libeigen3-dev libboost-dev libhdf5-dev nlohmann-json3-dev catch2 libcli11-dev
  libsundials-dev libopenmpi-dev openmpi-bin libdeflate-dev hdf5-tools
  python3 python3-numpy python3-h5py python3-matplotlib
  python3-pandas python3-xarray python3-h5netcdf python3-jsonschema pybind11-dev python3-pybind11
  python3-openturns
  python3-pip python3-venv python3-setuptools python3-wheel
  python3-tqdm python3-nbclient python3-nbformat python3-ipykernel
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing Debian packages: ${missing[*]}" >&2
  sudo=""
  if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
  export DEBIAN_FRONTEND=noninteractive
  $sudo apt-get update -qq
  $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
else
  echo "setup: all Debian packages present" >&2
fi

build_dir="${RODEND_BUILD_DIR:-build}"
# shellcheck disable=SC2086
cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE="${RODEND_BUILD_TYPE:-Release}" \
  -DRODEND_WERROR="${RODEND_WERROR:-ON}" ${RODEND_CMAKE_ARGS:-} >/dev/null
# RODEND_BUILD_TARGETS: build only these targets (space-separated; default: all)
targets=()
for t in ${RODEND_BUILD_TARGETS:-}; do targets+=(--target "$t"); done
cmake --build "$build_dir" -j"$(nproc)" "${targets[@]}"

# The Python package (docs/python.md "Installing"): rodend installed with pip into a virtual
# environment of this clone, .venv/ (its own copy: nothing is written into the system's Python,
# and another clone has its own), which sees Debian's numpy, h5py, pandas and xarray
# (--system-site-packages). The extension is the one just built (build/ is configured for
# /usr/bin/python3, the venv's interpreter: setup.py reuses it, no second compilation); no
# package index is asked. Then `.venv/bin/python` (or, after `. .venv/bin/activate`, `python`)
# imports rodend. Set RODEND_PYTHON_VENV=0 to skip; the tests never rely on it.
# Earlier versions of this script wrote rodend.pth into /usr/bin/python3's site-packages, naming
# one clone's python/ folder for every user of that Python: removed when found.
for site in $(/usr/bin/python3 -c 'import site; print(*site.getsitepackages(), site.getusersitepackages())'); do
  if [ -f "$site/rodend.pth" ] && grep -qx '/.*/python' "$site/rodend.pth" && [ -w "$site" ]; then
    rm -f "$site/rodend.pth" && echo "setup: removed $site/rodend.pth (an earlier set-up's)" >&2
  fi
done
if [ "${RODEND_PYTHON_VENV:-1}" = 1 ] && [ "$build_dir" = build ] && [ -z "${RODEND_BUILD_TARGETS:-}" ] &&
  compgen -G "build/python/_rodend*.so" >/dev/null; then
  if [ ! -x .venv/bin/python ]; then
    /usr/bin/python3 -m venv --system-site-packages .venv
  fi
  if RODEND_PIP_BUILD_DIR="$(pwd)/build" .venv/bin/python -m pip install --no-index --no-cache-dir \
    --no-build-isolation --quiet . >.venv/rodend-install.log 2>&1; then
    echo "setup: rodend installed into $(pwd)/.venv (.venv/bin/python -c 'import rodend')" >&2
    # the Jupyter kernel "rodend": this .venv's python, for examples/study.ipynb (which names
    # it) and any notebook; registered for this user (~/.local/share/jupyter/kernels/rodend,
    # where every Jupyter of the user looks; written again on each set-up: the last clone set
    # up is the one it runs). RODEND_JUPYTER_KERNEL=0 skips it.
    if [ "${RODEND_JUPYTER_KERNEL:-1}" = 1 ]; then
      if .venv/bin/python -m ipykernel install --user --name rodend \
        --display-name "Python (rodend: $(pwd))" >.venv/kernel-install.log 2>&1; then
        echo "setup: Jupyter kernel 'rodend' runs $(pwd)/.venv/bin/python" >&2
      else
        echo "setup: registering the Jupyter kernel failed (see .venv/kernel-install.log)" >&2
      fi
    fi
  else
    echo "setup: pip install into .venv failed (see .venv/rodend-install.log); use" \
      "PYTHONPATH=$(pwd)/python" >&2
  fi
fi
