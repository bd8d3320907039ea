"""Damaged case files are detected (issue 19): 4 KiB zeroed at random offsets of a case file
(several seeds: inside the raw history data of the uncompressed default, inside a compressed
chunk of a study written with output.compression_level 6, and anywhere in the file, HDF5's own
structures included) are reported by `rodend merge` as corrupt, naming the file (exit 1, no
summary written), and by `rodend run` (resume), which moves the file aside to <id>.h5.corrupt
byte for byte and reruns the case to results equal to the undamaged run.

    /usr/bin/python3 tests/cli/test_corruption.py [SEEDS]   # SEEDS per kind, 2 by default
(scripts/faults-long.sh runs it with 20 seeds per kind.)"""
import glob
import os
import random
import shutil
import sys
import tempfile

import h5py
import numpy as np

from common import assert_same_results, check, finish, run, write_study

SEEDS = int(sys.argv[1]) if len(sys.argv) > 1 else 2
BLOCK = 4096


def study(path, name, level):
    return write_study(path, {
        "name": name,
        "scene": "gravity-drop",
        "time": {"end": 0.05, "sample_interval": 1e-5},
        "output": {"compression_level": level},
        "grid": [{"key": "parameters.contact.restitution", "values": [0.3, 0.9]}],
    })


def chunk_ranges(path, compressed):
    """(offset, size) in the file of every stored chunk of /signals, non-empty ones only."""
    out = []
    with h5py.File(path, "r") as f:
        ub = f.userblock_size
        for name, d in f["signals"].items():
            if d.chunks is None or d.size == 0:
                continue
            check(bool(d.compression) == compressed, f"{name}: compression {d.compression}")
            for k in range(d.id.get_num_chunks()):
                info = d.id.get_chunk_info(k)
                out.append((info.byte_offset + ub, info.size))  # HDF5 addresses follow the user block
    return out


def damage(path, rng, where):
    """Zeroes BLOCK bytes (fewer at the end of a range) that are not all zero already; returns
    the offset."""
    data = bytearray(open(path, "rb").read())
    with h5py.File(path, "r") as f:
        ub = f.userblock_size
    if where == "anywhere":
        ranges = [(ub, len(data) - ub)]  # the HDF5 part; the header is covered by the others
    else:
        ranges = [r for r in chunk_ranges(path, where == "compressed chunk") if r[1] >= 64]
    for _ in range(1000):
        start, size = rng.choice(ranges)
        off = start + rng.randrange(max(size - 16, 1))
        end = min(off + BLOCK, start + size if where != "anywhere" else len(data))
        if any(data[off:end]):
            data[off:end] = bytes(end - off)
            open(path, "wb").write(data)
            return off
    raise RuntimeError(f"no non-zero block found in {path}")


with tempfile.TemporaryDirectory() as tmp:
    for level, kinds in ((0, ("uncompressed data", "anywhere")), (6, ("compressed chunk",))):
        name = f"corrupt{level}"
        s = study(os.path.join(tmp, name + ".json"), name, level)
        ref_root = os.path.join(tmp, "ref")
        r = run(["run", s, "--results-root", ref_root, "-q"])
        check(r.returncode == 0, f"reference run: {r.stderr}")
        ref = os.path.join(ref_root, name)
        cases = sorted(glob.glob(os.path.join(ref, "cases", "*.h5")))
        # the raw chunks really are where get_chunk_info says (the offsets the damage uses)
        with h5py.File(cases[0], "r") as f:
            d = f["signals/contact_force"]
            info = d.id.get_chunk_info(0)
            raw = open(cases[0], "rb").read()
            _, stored = d.id.read_direct_chunk((0,))
            off = info.byte_offset + f.userblock_size
            check(raw[off:off + len(stored)] == stored, f"level {level}: chunk offsets misread")
        for kind in kinds:
            for seed in range(SEEDS):
                rng = random.Random(1000 * level + 100 * kinds.index(kind) + seed)
                what = f"level {level}, {kind}, seed {seed}"
                work = os.path.join(tmp, "work", name)
                shutil.rmtree(os.path.join(tmp, "work"), ignore_errors=True)
                shutil.copytree(ref, work)
                victim = os.path.join(work, "cases", os.path.basename(rng.choice(cases)))
                off = damage(victim, rng, kind)
                damaged = open(victim, "rb").read()
                os.remove(os.path.join(work, "summary.h5"))
                os.remove(os.path.join(work, "summary.csv"))
                # merge: corrupt, with the path; exit 1; no summary; the file untouched
                r = run(["merge", work])
                check(r.returncode == 1 and "corrupt" in r.stderr and victim in r.stderr,
                      f"{what} (offset {off}): merge exit {r.returncode}: {r.stderr}")
                check(not os.path.exists(os.path.join(work, "summary.h5")),
                      f"{what}: merge wrote a summary")
                check(open(victim, "rb").read() == damaged, f"{what}: merge changed the file")
                # resume: reported, moved aside, rerun to the reference's results
                r = run(["run", s, "--results-root", os.path.join(tmp, "work")])
                check(r.returncode == 0 and f"corrupt case file {victim}" in r.stderr and
                      "1 of 2 cases already complete" in r.stderr,
                      f"{what} (offset {off}): resume exit {r.returncode}: {r.stderr}")
                aside = glob.glob(victim + ".corrupt*")
                check(len(aside) == 1 and open(aside[0], "rb").read() == damaged,
                      f"{what}: not moved aside byte for byte: {aside}")
                assert_same_results(ref, work, what)
                r = run(["merge", work])
                check(r.returncode == 0, f"{what}: merge after the rerun: {r.stderr}")
finish("corruption")
