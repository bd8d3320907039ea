#!/usr/bin/env bash
# Set-up for rodend: install the Debian 12 packages the project needs (only the
# missing ones), then configure and build. Non-interactive and idempotent.
#
#   bash scripts/setup.sh            # Release build in ./build, every target
#   RODEND_BUILD_DIR=build-asan RODEND_CMAKE_ARGS="-DRODEND_SANITIZE=ON" bash scripts/setup.sh
#   RODEND_BUILD_TARGETS=rodend_tests bash scripts/setup.sh   # only the unit-test executable
#
# Warnings are errors (-Werror, RODEND_WERROR=ON) in a build this script configures afresh,
# unless RODEND_WERROR_DEFAULT says otherwise (scripts/main.sh: OFF, a user's build); a build
# directory configured before keeps its setting (switching it would recompile everything);
# RODEND_WERROR=ON|OFF sets it either way (.ci/run: ON). Each step prints what it took.
set -euo pipefail
cd "$(dirname "$0")/.."
step_start=$(date +%s)
took() {  # "setup: STEP took Ns", then restart the clock
  local now
  now=$(date +%s)
  echo "setup: $1 took $((now - step_start)) s" >&2
  step_start=$now
}

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
took "the Debian packages"

build_dir="${RODEND_BUILD_DIR:-build}"
werror=()
if [ -n "${RODEND_WERROR:-}" ]; then
  werror=(-DRODEND_WERROR="$RODEND_WERROR")
elif [ ! -f "$build_dir/CMakeCache.txt" ]; then
  werror=(-DRODEND_WERROR="${RODEND_WERROR_DEFAULT:-ON}")
fi
# shellcheck disable=SC2086
cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE="${RODEND_BUILD_TYPE:-Release}" \
  "${werror[@]}" ${RODEND_CMAKE_ARGS:-} >/dev/null
if grep -q '^RODEND_WERROR:BOOL=ON' "$build_dir/CMakeCache.txt"; then
  echo "setup: $build_dir: warnings are errors (RODEND_WERROR=ON)" >&2
else
  echo "setup: $build_dir: warnings are not errors (RODEND_WERROR=OFF; the tests' own code and CI keep -Werror)" >&2
fi
took "configuring $build_dir"
# RODEND_BUILD_TARGETS: build only these targets (space-separated; default: all)
targets=()
for t in ${RODEND_BUILD_TARGETS:-}; do targets+=(--target "$t"); done
cmake --build "$build_dir" -j"$(nproc)" "${targets[@]}"
took "building ${RODEND_BUILD_TARGETS:-every target}"

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
python_built=0  # the Python module is among the targets built
case " ${RODEND_BUILD_TARGETS:-_rodend} " in *" _rodend "*) python_built=1 ;; esac
if [ "${RODEND_PYTHON_VENV:-1}" = 1 ] && [ "$build_dir" = build ] && [ "$python_built" = 1 ] &&
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
    # up is the one it runs). RODEND_JUPYTER_KERNEL=0 skips it. PYDEVD_DISABLE_FILE_VALIDATION:
    # without it every start of the kernel prints the debugger's four-line warning on Python
    # 3.11's frozen modules ("may make the debugger miss breakpoints") under jupyter-execute
    # and in Jupyter's log, which says nothing about rodend.
    if [ "${RODEND_JUPYTER_KERNEL:-1}" = 1 ]; then
      if .venv/bin/python -m ipykernel install --user --name rodend \
        --display-name "Python (rodend: $(pwd))" --env PYDEVD_DISABLE_FILE_VALIDATION 1 \
        >.venv/kernel-install.log 2>&1; then
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
if [ "${RODEND_PYTHON_VENV:-1}" = 1 ] && [ "$python_built" = 1 ] && [ -x .venv/bin/python ]; then
  took "the Python package in .venv"
fi
