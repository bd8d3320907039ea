"""Files written into a results folder from Python (the analysis's analysis.json, bands.h5 and
figures), by the rules of rodend's atomic writer (sweep/results/atomic_file.cpp,
docs/results.md "No write through a link"): the file is created fresh (O_CREAT | O_EXCL |
O_NOFOLLOW) under a temporary name nobody can guess, `.<name>.tmp.<host>.<pid>.<64 random
bits>`, in its final directory (opened once: the file is created, renamed and removed in it
whatever happens to the path meanwhile), written through that descriptor, then renamed over
the final name. A link planted at the final name is replaced, never followed; one planted at a
temporary name is never used; a failure removes the temporary file and leaves the final name
as it was. The directories on the way are taken as they are.
"""
import contextlib
import os
import secrets
import socket

__all__ = ["atomic_file"]


def _temp_name(name):
    return f".{name}.tmp.{socket.gethostname()}.{os.getpid()}.{secrets.randbits(64)}"


@contextlib.contextmanager
def atomic_file(path):
    """Yields a binary file object (read-write: h5py reads back what it wrote) open on a new
    temporary file beside `path`; renames it over `path` when the block ends without an
    exception, removes it otherwise. Creates the missing directories of `path`."""
    path = os.fspath(path)
    folder, name = os.path.split(path)
    os.makedirs(folder or ".", exist_ok=True)
    dir_fd = os.open(folder or ".", os.O_RDONLY | os.O_DIRECTORY | os.O_CLOEXEC)
    try:
        for attempt in range(17):
            temp = _temp_name(name)
            try:
                fd = os.open(temp, os.O_RDWR | os.O_CREAT | os.O_EXCL | os.O_NOFOLLOW |
                             os.O_CLOEXEC, 0o644, dir_fd=dir_fd)
                break
            except FileExistsError:
                if attempt == 16:
                    raise
        try:
            with os.fdopen(fd, "w+b") as fh:
                yield fh
            os.rename(temp, name, src_dir_fd=dir_fd, dst_dir_fd=dir_fd)
        except BaseException:
            with contextlib.suppress(OSError):
                os.unlink(temp, dir_fd=dir_fd)
            raise
    finally:
        os.close(dir_fd)
