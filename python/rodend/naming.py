"""Names and labels of what rodend returns from Python: the CF
`Conventions` attribute, short `long_name`s (the sentence kept in `description`), the labels of
vector components, the labels of grid coordinates in the figures' display units, and the error
raised for an unknown name, which names the nearest valid ones. Nothing here touches a file:
the results layout on disk is unchanged."""
import difflib
import math

import numpy as np

# the CF version whose attribute names the results use (units, long_name; docs/results.md)
CONVENTIONS = "CF-1.8"

# vector components: (dimension, labels) by signal name; other vectors of width 3 are x, y, z
# (dimension component3, as in the files). The labels are those the signal catalogue gives
# (core/signals.def).
_EULER = ("euler_321", ["phi", "theta", "psi"])
_JOINTS = ("joint", ["ground-crank", "crank-rod", "rod-slider"])
_CHAMBERS = ("chamber", ["rear", "front"])
_COMPONENTS = {
    "body_euler_321": _EULER, "ball_euler_321": _EULER, "socket_euler_321": _EULER,
    "joint_normal_forces": _JOINTS, "joint_eccentricities": _JOINTS,
    "chamber_pressures": _CHAMBERS, "chamber_flows": _CHAMBERS,
}
_XYZ = ["x", "y", "z"]


def components(signal, width):
    """(dimension name, component labels) of a vector signal of `width` components."""
    if signal in _COMPONENTS and len(_COMPONENTS[signal][1]) == width:
        return _COMPONENTS[signal]
    if width <= 3:
        return f"component{width}", _XYZ[:width]
    return f"component{width}", [str(k) for k in range(width)]


def short_name(key):
    """A short long_name for an axis label: the last words of a key path, underscores as
    spaces ("parameters.contact.clearance" -> "contact clearance", "max_penetration" ->
    "max penetration")."""
    parts = [p for p in str(key).split(".") if p]
    if len(parts) > 1 and parts[0] in ("parameters", "integrator", "time", "health",
                                       "metrics", "wear_evolution", "design"):
        parts = parts[1:]
    return " ".join(parts).replace("_", " ")


def coordinate_names(keys, taken=()):
    """{key: name} of a study's grid and design keys as xarray names, without dots so that
    `.sel(clearance=...)` works: each key by its last part (a leading `parameters.` left
    out), with the parts before it joined by `_` where two keys would share a name or a name is
    in `taken` (`contact_clearance`); the whole key with `_` for `.` where even that collides."""
    parts = {}
    for k in keys:
        p = k.split(".")
        parts[k] = p[1:] if p[0] == "parameters" and len(p) > 1 else p
    depth = dict.fromkeys(parts, 1)
    while True:
        names = {k: "_".join(p[-depth[k]:]) for k, p in parts.items()}
        seen = {}
        for k, n in names.items():
            seen.setdefault(n, []).append(k)
        clash = [k for k, n in names.items() if len(seen[n]) > 1 or n in taken]
        longer = [k for k in clash if depth[k] < len(parts[k])]
        if not longer:
            break
        for k in longer:
            depth[k] += 1
    for k in clash:  # even the whole key collides
        names[k] = k.replace(".", "_")
    return names


def attrs(key, units, sentence):
    """CF attributes of one variable: units, a short long_name and the sentence as
    description (left out when it says nothing more than the short name)."""
    out = {"units": units, "long_name": short_name(key)}
    if sentence and sentence != out["long_name"]:
        out["description"] = sentence
    return out


class UnknownName(KeyError, ValueError):
    """An unknown signal, metric, scene or grid name; the message names the nearest valid
    ones. A KeyError (dict-like lookups) and a ValueError (bad arguments)."""

    def __str__(self):
        return str(self.args[0]) if self.args else ""


def unknown(kind, name, valid, where=""):
    """The UnknownName for `name`, not one of `valid` (a `kind` such as "signal")."""
    valid = sorted(str(v) for v in valid)
    near = difflib.get_close_matches(str(name), valid, n=3, cutoff=0.6)
    msg = f"unknown {kind} {name!r}" + (f" {where}" if where else "")
    if near:
        msg += "; nearest: " + ", ".join(near)
    elif valid:
        shown = ", ".join(valid[:12]) + (", ..." if len(valid) > 12 else "")
        msg += f"; valid: {shown}"
    return UnknownName(msg)


def check_names(kind, names, valid, where=""):
    """Raises UnknownName for the first of `names` not in `valid`."""
    valid = set(valid)
    for n in names:
        if n not in valid:
            raise unknown(kind, n, valid, where)


_DATASET = None


def dataset(data_vars=None, coords=None, attrs=None):
    """An xarray.Dataset whose missing variable (`ds["contact_forse"]`) raises UnknownName
    naming the nearest ones (a KeyError, as xarray's own), instead of a bare KeyError."""
    global _DATASET
    if _DATASET is None:
        import xarray as xr

        class Dataset(xr.Dataset):
            """xarray.Dataset; an unknown variable name raises rodend.UnknownName."""
            __slots__ = ()

            def __getitem__(self, key):
                try:
                    return super().__getitem__(key)
                except KeyError:
                    if not isinstance(key, str):
                        raise
                    raise unknown("variable", key, list(self.data_vars) + list(self.coords),
                                  "(not in this Dataset)") from None

        _DATASET = Dataset
    return _DATASET(data_vars, coords=coords, attrs=attrs)


class Names(dict):
    """A dict whose missing key raises UnknownName naming the nearest keys."""

    def __init__(self, data, kind):
        super().__init__(data)
        self._kind = kind

    def __missing__(self, key):
        raise unknown(self._kind, key, self.keys())


def short_key(key):
    """A grid key without the 'parameters.' prefix (contact.clearance)."""
    return key[len("parameters."):] if key.startswith("parameters.") else key


def format_value(value):
    """A coordinate value for a label: its shortest readable form (0.0001, 5e-05, constant)."""
    if isinstance(value, (bool, np.bool_)):
        return str(bool(value)).lower()
    if isinstance(value, (int, np.integer)):
        return str(int(value))
    if isinstance(value, (float, np.floating)):
        v = float(value)
        if math.isfinite(v) and v == int(v) and abs(v) < 1e15:
            return str(int(v))
        return f"{v:.6g}"
    if isinstance(value, (list, tuple, np.ndarray)):
        return "[" + ", ".join(format_value(v) for v in value) + "]"
    if isinstance(value, (bytes, np.bytes_)):
        return value.decode("utf-8", "replace")
    return str(value)


def unit_suffix(unit):
    """' m' for a unit worth printing, '' for none or dimensionless."""
    return "" if unit in ("", "1", "-", None) else " " + unit


# the display units of the figures (value * factor): axes and legend labels say the same unit
DISPLAY_UNITS = {
    "m": ("mm", 1e3),
    "rad": ("deg", 180.0 / math.pi),
    "Pa": ("bar", 1e-5),
    "m^3/s": ("L/min", 6e4),
}


def coordinate_label(key, value, unit):
    """"contact.clearance = 0.1 mm": a grid coordinate in the display unit of the figures."""
    if unit in DISPLAY_UNITS and isinstance(value, (int, float, np.integer, np.floating)) \
            and not isinstance(value, (bool, np.bool_)):
        name, factor = DISPLAY_UNITS[unit]
        return f"{short_key(key)} = {format_value(float(value) * factor)} {name}"
    return f"{short_key(key)} = {format_value(value)}{unit_suffix(unit)}"
