#!/usr/bin/python3
"""Regenerates the fuzzer's seed corpus fuzz/corpus/ from the study files the project ships, so
the seeds cannot drift from what they copy:

    studies/NAME.json                      -> fuzz/corpus/study-NAME.json
    tests/regression/studies/reg-NAME.json -> fuzz/corpus/reg-NAME.json
    tests/bad_inputs/NAME.json             -> fuzz/corpus/bad-NAME.json   (not expected.json,
                                              the bad-input test's table of expected messages)

Each seed is a byte-for-byte copy (a malformed file stays malformed: NUL bytes, syntax errors).
The prefixes study-, reg- and bad- belong to this script: a seed under one of them whose source
is gone is removed. A seed under any other name is hand-written and left as it is.

    /usr/bin/python3 scripts/gen-fuzz-corpus.py          # regenerate fuzz/corpus/
    /usr/bin/python3 scripts/gen-fuzz-corpus.py --check  # exit 1, listing the differences, when
                                                         # fuzz/corpus/ is not what it would write
                                                         # (CTest cli.fuzz_corpus)
"""
import os
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CORPUS = os.path.join(ROOT, "fuzz", "corpus")
# (source folder, seed prefix, files of the folder that are not studies)
SOURCES = [
    ("studies", "study-", set()),
    (os.path.join("tests", "regression", "studies"), "reg-", set()),
    (os.path.join("tests", "bad_inputs"), "bad-", {"expected.json"}),
]
PREFIXES = tuple(prefix for _, prefix, _ in SOURCES)


def wanted():
    """{seed name: bytes} of every generated seed."""
    seeds = {}
    for folder, prefix, skip in SOURCES:
        src = os.path.join(ROOT, folder)
        for name in sorted(os.listdir(src)):
            if not name.endswith(".json") or name in skip:
                continue
            seed = name if name.startswith(prefix) else prefix + name
            if seed in seeds:
                raise SystemExit(f"gen-fuzz-corpus: two sources for fuzz/corpus/{seed}")
            with open(os.path.join(src, name), "rb") as f:
                seeds[seed] = f.read()
    return seeds


def differences(seeds):
    """(seed, what) for every generated seed that is missing, differs or is stale."""
    present = {n for n in os.listdir(CORPUS) if n.startswith(PREFIXES)}
    out = []
    for seed, data in sorted(seeds.items()):
        path = os.path.join(CORPUS, seed)
        if seed not in present:
            out.append((seed, "missing"))
        else:
            with open(path, "rb") as f:
                if f.read() != data:
                    out.append((seed, "differs from its source"))
    for seed in sorted(present - set(seeds)):
        out.append((seed, "has no source any more"))
    return out


def main(argv):
    check = "--check" in argv
    if set(argv) - {"--check"}:
        print(__doc__, file=sys.stderr)
        return 2
    seeds = wanted()
    diffs = differences(seeds)
    if check:
        for seed, what in diffs:
            print(f"fuzz/corpus/{seed}: {what}", file=sys.stderr)
        if diffs:
            print(f"{len(diffs)} seed(s) out of date: run /usr/bin/python3 "
                  "scripts/gen-fuzz-corpus.py", file=sys.stderr)
            return 1
        print(f"fuzz/corpus: {len(seeds)} generated seeds up to date")
        return 0
    for seed, what in diffs:
        path = os.path.join(CORPUS, seed)
        if seed in seeds:
            with open(path, "wb") as f:
                f.write(seeds[seed])
        else:
            os.remove(path)
        print(f"fuzz/corpus/{seed}: {'removed' if seed not in seeds else 'written'} ({what})")
    print(f"fuzz/corpus: {len(seeds)} generated seeds, {len(diffs)} changed")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
