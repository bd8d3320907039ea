"""The compiled module rodend._rodend, found and loaded on first use (running, the catalogues,
InputError, __version__); reading results never needs it. Its names become attributes of the
package once it is loaded.

Where it is looked for: $RODEND_BUILD_DIR/python (a build directory of another name), next to
the package, then <repo>/build/python (where `bash scripts/setup.sh` builds it).
"""
import glob
import importlib.util
import os
import sys
import threading

# what the compiled module gives, as attributes of this package once it is loaded
_FROM_EXTENSION = {"_ext": None, "InputError": "InputError", "__version__": "__version__",
                   "SCHEMA_VERSION": "schema_version"}
_LOADING = threading.Lock()


def get():
    """The compiled module, loaded on first use (ImportError naming where it was looked for
    when it is not built); its names become attributes of the package."""
    package = sys.modules[__package__]
    with _LOADING:  # once, whichever thread asks first
        if "_ext" not in vars(package):
            ext = load()
            for k, v in _FROM_EXTENSION.items():
                setattr(package, k, getattr(ext, v) if v else ext)
    return package._ext


def load():
    here = os.path.dirname(os.path.abspath(__file__))
    repo = os.path.dirname(os.path.dirname(here))
    places = []
    if os.environ.get("RODEND_BUILD_DIR"):
        b = os.environ["RODEND_BUILD_DIR"]
        places.append(os.path.join(b if os.path.isabs(b) else os.path.join(repo, b), "python"))
    places += [here, os.path.join(repo, "build", "python")]
    for place in places:
        for path in sorted(glob.glob(os.path.join(place, "_rodend*.so"))):
            spec = importlib.util.spec_from_file_location("rodend._rodend", path)
            module = importlib.util.module_from_spec(spec)
            try:
                spec.loader.exec_module(module)
            except ImportError:
                continue  # built for another Python
            sys.modules["rodend._rodend"] = module
            return module
    raise ImportError(
        "rodend: the compiled module _rodend was not found in " + ", ".join(places) +
        ": build it with `bash scripts/setup.sh` (needs pybind11-dev), or set RODEND_BUILD_DIR "
        "to the build directory (reading results needs no compiled module: "
        "rodend.open_results, rodend.study)")
