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

# The Python module (README "Python"): `import rodend` under /usr/bin/python3 finds the package
# python/rodend of this clone through a .pth file in site-packages (as root the system's
# /usr/local one, else the user's), and the package finds the compiled part in build/python/.
# Set RODEND_PYTHON_PTH=0 to skip; the tests never rely on it (they set PYTHONPATH).
if [ "${RODEND_PYTHON_PTH:-1}" = 1 ] && [ "$build_dir" = build ] && [ -x /usr/bin/python3 ]; then
  if [ "$(id -u)" -eq 0 ]; then
    site=$(/usr/bin/python3 -c 'import site; print(site.getsitepackages()[0])')
  else
    site=$(/usr/bin/python3 -m site --user-site)
  fi
  if mkdir -p "$site" 2>/dev/null && printf '%s\n' "$(pwd)/python" > "$site/rodend.pth" 2>/dev/null; then
    echo "setup: /usr/bin/python3 imports rodend from $(pwd)/python ($site/rodend.pth)" >&2
  else
    echo "setup: could not write $site/rodend.pth: use PYTHONPATH=$(pwd)/python" >&2
  fi
fi
