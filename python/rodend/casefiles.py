"""A study's case files and summary.h5 on disk: the checksum every reader checks first
(docs/results.md, "Crash safety"), the attributes' text and units, and the case files opened
one at a time, each checked the first time it is read (rodend.open_results reads them lazily)."""
import os

import h5py
import numpy as np


_USER_BLOCK = 512
_MAGIC = b"RODEND-CHECKSUM 1\n"
_HDF5_SIGNATURE = b"\x89HDF\r\n\x1a\n"


class CorruptFile(ValueError):
    """A results file (case file or summary.h5) whose bytes are damaged; the message names it."""


def verify_checksum(path, kind="case file"):
    """Checks the checksum header of a case file or summary.h5 (docs/results.md, "Crash
    safety") before any HDF5 reader sees the file: the 512-byte user block exactly as rodend
    writes it, the size it states, the CRC-32 of the rest. True when it holds, False for a
    file without a user block (written before checksums); raises CorruptFile naming the file."""
    import re
    import zlib
    bad = f"corrupt {kind} {os.fspath(path)}: "
    with open(path, "rb") as fh:
        head = fh.read(_USER_BLOCK)
        if head[:8] == _HDF5_SIGNATURE:
            return False
        if not head.startswith(_MAGIC):
            raise CorruptFile(bad + ("empty file" if not head else
                                     'no checksum header ("RODEND-CHECKSUM") and not an HDF5 file'))
        m = re.match(rb"crc32 ([0-9a-f]{8})\nbytes ([0-9]+)\n", head[len(_MAGIC):])
        if len(head) < _USER_BLOCK or not m:
            raise CorruptFile(bad + "damaged checksum header")
        stored, size = int(m.group(1), 16), int(m.group(2))
        expected = (_MAGIC + b"crc32 %08x\nbytes %d\n" % (stored, size)).ljust(_USER_BLOCK, b"\0")
        if head != expected:
            raise CorruptFile(bad + "damaged checksum header")
        actual = os.fstat(fh.fileno()).st_size
        if actual != size:
            raise CorruptFile(bad + f"{actual} bytes, its checksum header says {size} "
                              "(truncated or extended)")
        crc = 0
        for block in iter(lambda: fh.read(1 << 20), b""):
            crc = zlib.crc32(block, crc)
    if crc != stored:
        raise CorruptFile(bad + f"content does not match its checksum (CRC-32 {crc:08x}, "
                          f"stored {stored:08x})")
    return True


def _text(v):
    if isinstance(v, (bytes, np.bytes_)):
        return v.decode("utf-8", "replace")
    return str(v)


def _units(ds):
    return _text(ds.attrs.get("units", ds.attrs.get("unit", "")))


def _long_name(ds):
    return _text(ds.attrs.get("long_name", ds.attrs.get("description", "")))


class CaseFiles:
    """The case files of a study folder, in summary order (`case_ids`), opened on demand.
    Each is checked (checksum, the case id it holds) before its first read."""

    def __init__(self, folder, case_ids):
        self.folder = folder
        self.case_ids = list(case_ids)
        self._checked = set()

    def path(self, i):
        return os.path.join(self.folder, "cases", f"{self.case_ids[i]}.h5")

    def check_present(self):
        """FileNotFoundError naming the first case file the summary lists that is missing."""
        for i in range(len(self.case_ids)):
            self._missing(i)

    def _missing(self, i):
        path = self.path(i)
        if not os.path.isfile(path):
            # reported, never shown as NaN histories of a case the summary lists
            raise FileNotFoundError(f"{path}: the case file of case {self.case_ids[i]} (a row "
                                    f"of {self.folder}/summary.h5) is missing")

    def open(self, i):
        """The h5py.File of case i (the caller closes it)."""
        self._missing(i)
        path, cid = self.path(i), self.case_ids[i]
        if i not in self._checked:
            verify_checksum(path, "case file")  # a damaged file never reaches HDF5
        f = h5py.File(path, "r")
        held = _text(f.attrs.get("case_id", ""))
        if held != cid:
            f.close()
            raise CorruptFile(f"{path}: holds case {held}, not {cid} (a case file copied or "
                              "moved under another case's name)")
        self._checked.add(i)
        return f
