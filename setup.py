"""Builds rodend's compiled part (rodend._rodend, pybind11) with CMake for the Python running
pip, next to the pure-Python package python/rodend (pyproject.toml; docs/python.md
"Installing"):

    python3 -m venv --system-site-packages .venv
    .venv/bin/pip install --no-build-isolation .

The CMake build directory is build-pip/<python tag>/ in this clone (kept, so a second install
is incremental), or $RODEND_PIP_BUILD_DIR. An existing CMake build directory (the clone's
build/, say) is reused only when it was configured for the same interpreter (the same binary
after symlinks: a venv's python is its base interpreter); it is then built, never reconfigured.
$RODEND_CMAKE_ARGS adds CMake arguments to a fresh configuration (a compiler launcher, say).
"""
import os
import re
import shlex
import shutil
import subprocess
import sys
import sysconfig

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

HERE = os.path.dirname(os.path.abspath(__file__))


def cmake_build_dir():
    given = os.environ.get("RODEND_PIP_BUILD_DIR")
    if given:
        return os.path.abspath(given)
    tag = sysconfig.get_config_var("SOABI") or f"py{sys.version_info[0]}{sys.version_info[1]}"
    return os.path.join(HERE, "build-pip", tag)


def configured_python(build_dir):
    """The interpreter an existing CMake build directory was configured for (None if none)."""
    cache = os.path.join(build_dir, "CMakeCache.txt")
    if not os.path.isfile(cache):
        return None
    with open(cache, encoding="utf-8", errors="replace") as f:
        m = re.search(r"^RODEND_PYTHON_EXECUTABLE:FILEPATH=(.*)$", f.read(), re.M)
    return m.group(1).strip() if m else ""


def cmake_project_version():
    """The version of project(rodend VERSION x.y.z ...) in CMakeLists.txt: one source."""
    with open(os.path.join(HERE, "CMakeLists.txt"), encoding="utf-8") as f:
        m = re.search(r"^project\(rodend VERSION ([0-9.]+)", f.read(), re.M)
    if not m:
        sys.exit("rodend: no project(rodend VERSION ...) in CMakeLists.txt")
    return m.group(1)


class CMakeExtension(Extension):
    def __init__(self, name):
        super().__init__(name, sources=[])


class CMakeBuild(build_ext):
    """build_ext for rodend._rodend: configure (when new) and build the CMake target _rodend."""

    def build_extension(self, ext):
        build_dir = cmake_build_dir()
        python = sys.executable
        cmake = shutil.which("cmake")
        if cmake is None:
            sys.exit("rodend: cmake not found (Debian: apt-get install cmake; scripts/setup.sh "
                     "installs everything the build needs)")
        existing = configured_python(build_dir)
        if existing is None:
            args = [cmake, "-S", HERE, "-B", build_dir, "-DCMAKE_BUILD_TYPE=Release",
                    f"-DRODEND_PYTHON_EXECUTABLE={python}", "-DRODEND_BUILD_TESTS=OFF",
                    "-DRODEND_BUILD_BENCHMARKS=OFF", "-DRODEND_MPI=OFF"]
            args += shlex.split(os.environ.get("RODEND_CMAKE_ARGS", ""))
            subprocess.check_call(args)
        elif os.path.realpath(existing) != os.path.realpath(python):
            sys.exit(f"rodend: the CMake build directory {build_dir} is configured for "
                     f"{existing or 'no Python'}, not for {python}; unset RODEND_PIP_BUILD_DIR "
                     "or name another directory")
        jobs = os.environ.get("CMAKE_BUILD_PARALLEL_LEVEL") or str(os.cpu_count() or 1)
        subprocess.check_call([cmake, "--build", build_dir, "--target", "_rodend", "-j", jobs])
        built = [f for f in os.listdir(os.path.join(build_dir, "python"))
                 if f.startswith("_rodend") and f.endswith(sysconfig.get_config_var("EXT_SUFFIX"))]
        if not built:
            sys.exit(f"rodend: no _rodend{sysconfig.get_config_var('EXT_SUFFIX')} in "
                     f"{build_dir}/python after the build")
        target = self.get_ext_fullpath(ext.name)
        os.makedirs(os.path.dirname(target), exist_ok=True)
        shutil.copyfile(os.path.join(build_dir, "python", built[0]), target)


# setuptools' own scratch (build/lib..., the egg-info) goes beside the CMake build, not into the
# clone's build/ (CMake's) nor its python/ folder
scratch = os.path.join(cmake_build_dir(), "setuptools")
os.makedirs(scratch, exist_ok=True)
setup(version=cmake_project_version(), ext_modules=[CMakeExtension("rodend._rodend")], cmdclass={"build_ext": CMakeBuild},
      options={"build": {"build_base": scratch}, "egg_info": {"egg_base": scratch}})
