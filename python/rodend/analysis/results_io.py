"""Small helpers of reading HDF5 text attributes."""
import numpy as np


def text(v):
    if isinstance(v, (bytes, np.bytes_)):
        return v.decode("utf-8", "replace")
    return str(v)
