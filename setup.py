"""Builds rodend's compiled part (rodend._rodend, pybind11) with CMake for the Python running
pip, next to the pure-Python package python/rodend (pyproject.toml; docs/python.md
"Installing"):

    python3 -m venv --system-site-packages .venv
    .venv/bin/pip install --no-build-isolation .

Which CMake build directory: $RODEND_PIP_BUILD_DIR when given; else the clone's own build
(build/, or $RODEND_BUILD_DIR) when it was configured for a Python whose extensions this one
loads (the same extension suffix, .cpython-311-x86_64-linux-gnu.so say: a venv of that Python,
another 3.11 build): it is then built (the target _rodend only, up to date after
scripts/setup.sh: nothing compiles) and never reconfigured; else build-pip/<python tag>/ in this
clone, configured afresh (the whole library compiles: minutes) and kept, so that a second
install is incremental. $RODEND_CMAKE_ARGS adds CMake arguments to a fresh configuration (a
compiler launcher, say).

Before anything is built, the build requirements are checked (setuptools >= 61, wheel, cmake,
pybind11's CMake files; with --no-build-isolation pip takes them from the environment) and a
missing one stops the install with what is missing and how to get it (without wheel, setuptools
would otherwise say only "invalid command 'bdist_wheel'").
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


RUNTIME = ("numpy", "pandas", "xarray", "h5py")  # pyproject.toml's dependencies, and h5py


def missing_requirements():
    """The build requirements this Python lacks (names as pip knows them), and the run-time
    ones (which pip installs itself from a package index, unless --no-index)."""
    import importlib.util
    build = []
    try:
        import setuptools
        if int(setuptools.__version__.split(".")[0]) < 61:
            build.append(f"setuptools>=61 (this Python has {setuptools.__version__})")
    except ImportError:
        build.append("setuptools>=61")
    if not bdist_wheel_found():
        build.append("wheel")
    if shutil.which("cmake") is None:
        build.append("cmake (the program)")
    if not pybind11_cmake_found():
        build.append("pybind11")
    runtime = [m for m in RUNTIME if importlib.util.find_spec(m) is None]
    return build, runtime


def bdist_wheel_found():
    """setuptools' bdist_wheel command: its own (setuptools >= 70.1) or the wheel package's,
    registered by its distribution's entry points (an importable wheel module is not enough)."""
    import importlib.util
    if importlib.util.find_spec("setuptools.command.bdist_wheel") is not None:
        return True
    from importlib.metadata import entry_points
    try:
        commands = entry_points(group="distutils.commands")
    except TypeError:  # Python < 3.10
        commands = entry_points().get("distutils.commands", [])
    return any(ep.name == "bdist_wheel" for ep in commands)


def pybind11_cmake_found():
    """pybind11's CMake package: Debian's pybind11-dev, or the pybind11 Python package's."""
    for d in ("/usr/lib/cmake/pybind11", "/usr/share/cmake/pybind11",
              "/usr/local/lib/cmake/pybind11", "/usr/local/share/cmake/pybind11"):
        if os.path.isfile(os.path.join(d, "pybind11Config.cmake")):
            return True
    try:
        import pybind11
        return os.path.isdir(pybind11.get_cmake_dir())
    except (ImportError, AttributeError, RuntimeError):
        return False


def check_requirements():
    build, runtime = missing_requirements()
    if not build:
        return
    also = f" (and, to run rodend: {', '.join(runtime)})" if runtime else ""
    sys.exit(
        f"rodend: cannot build with {sys.executable}: missing build requirements: "
        f"{', '.join(build)}{also}. Either:\n"
        f"  - use a Python that has them all: Debian's, in a venv that sees its packages:\n"
        f"      /usr/bin/python3 -m venv --system-site-packages ENV && "
        f"ENV/bin/pip install --no-build-isolation --no-index {HERE}\n"
        f"    (Debian: apt-get install python3-setuptools python3-wheel pybind11-dev "
        f"python3-pybind11 python3-numpy python3-pandas python3-xarray python3-h5py cmake;\n"
        f"    scripts/setup.sh installs them all);\n"
        f"  - or install them into this environment from a package index first:\n"
        f"      {sys.executable} -m pip install setuptools wheel pybind11 "
        f"{' '.join(RUNTIME)}\n"
        f"    (or drop --no-build-isolation: pip then fetches the build requirements itself).")


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


def python_ext_suffix(python):
    """The extension suffix of the Python `python` (None when it cannot be run)."""
    if os.path.realpath(python) == os.path.realpath(sys.executable):
        return sysconfig.get_config_var("EXT_SUFFIX")
    try:
        out = subprocess.run([python, "-c", "import sysconfig; "
                              "print(sysconfig.get_config_var('EXT_SUFFIX'))"],
                             capture_output=True, text=True, timeout=60)
    except (OSError, subprocess.SubprocessError):
        return None
    return out.stdout.strip() if out.returncode == 0 else None


def compatible(build_dir):
    """(True, its Python) when build_dir is a CMake build configured for a Python whose
    extensions this one loads; (False, why) otherwise; (None, "") when there is no build."""
    existing = configured_python(build_dir)
    if existing is None:
        return None, ""
    if not existing:
        return False, "configured without the Python module"
    ours = sysconfig.get_config_var("EXT_SUFFIX")
    if os.path.realpath(existing) == os.path.realpath(sys.executable) or \
            python_ext_suffix(existing) == ours:
        return True, existing
    return False, f"configured for {existing}, whose extensions are not {ours}"


def cmake_build_dir():
    """The CMake build directory: $RODEND_PIP_BUILD_DIR, else the clone's build when this
    Python loads its extensions, else build-pip/<python tag>."""
    given = os.environ.get("RODEND_PIP_BUILD_DIR")
    if given:
        return os.path.abspath(given)
    clone_build = os.path.abspath(os.path.join(HERE, os.environ.get("RODEND_BUILD_DIR", "build")))
    if compatible(clone_build)[0]:
        return clone_build
    tag = sysconfig.get_config_var("SOABI") or f"py{sys.version_info[0]}{sys.version_info[1]}"
    return os.path.join(HERE, "build-pip", tag)


class CMakeExtension(Extension):
    def __init__(self, name):
        super().__init__(name, sources=[])


class CMakeBuild(build_ext):
    """build_ext for rodend._rodend: configure (when new) and build the CMake target _rodend."""

    def build_extension(self, ext):
        build_dir = cmake_build_dir()
        python = sys.executable
        cmake = shutil.which("cmake")
        ok, why = compatible(build_dir)
        if ok is None:
            print(f"rodend: configuring {build_dir} for {python} (the clone has no CMake build "
                  "for this Python's extensions); the whole library compiles (minutes)",
                  file=sys.stderr)
            args = [cmake, "-S", HERE, "-B", build_dir, "-DCMAKE_BUILD_TYPE=Release",
                    f"-DRODEND_PYTHON_EXECUTABLE={python}", "-DRODEND_BUILD_TESTS=OFF",
                    "-DRODEND_BUILD_BENCHMARKS=OFF", "-DRODEND_MPI=OFF"]
            args += shlex.split(os.environ.get("RODEND_CMAKE_ARGS", ""))
            subprocess.check_call(args)
        elif not ok:
            sys.exit(f"rodend: the CMake build directory {build_dir} is {why}; unset "
                     "RODEND_PIP_BUILD_DIR or name another directory")
        else:
            print(f"rodend: reusing the CMake build {build_dir} (configured for {why}; "
                  "extension suffix " + sysconfig.get_config_var("EXT_SUFFIX") + ")",
                  file=sys.stderr)
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


# setuptools' own scratch (build/lib..., the egg-info) goes into the CMake build's folder
# setuptools/, not among CMake's files nor into the clone's python/ folder
check_requirements()
scratch = os.path.join(cmake_build_dir(), "setuptools")
os.makedirs(scratch, exist_ok=True)
setup(version=cmake_project_version(), ext_modules=[CMakeExtension("rodend._rodend")], cmdclass={"build_ext": CMakeBuild},
      options={"build": {"build_base": scratch}, "egg_info": {"egg_base": scratch}})
