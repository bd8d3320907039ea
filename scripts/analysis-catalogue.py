#!/usr/bin/env python3
"""Prints python/rodend/analysis/catalogue.py, the catalogues the Python analysis reads, from
sweep/design_methods.def, sweep/distributions.def and sweep/case_record.def (scripts/gen-docs.sh
writes it there; the test cli.docs_in_step keeps it in step).

  scripts/analysis-catalogue.py [REPO_ROOT]
"""
import pathlib
import re
import sys

root = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else pathlib.Path(__file__).parent.parent)
TEXT = r'"((?:[^"\\]|\\.)*)"'
METHOD = re.compile(r'^RODEND_CHOICE\((\w+), "([^"]+)", ' + TEXT + r', (\w+), (true|false), '
                    r'(true|false), (\d+), (\d+), (\d+)\)$')
DISTRIBUTION = re.compile(r'^RODEND_CHOICE\((\w+), "([^"]+)", ' + TEXT +
                          r', \(\{([^}]*)\}\), (true|false)\)$')
FIELD = re.compile(r'^RODEND_RECORD_FIELD\((\w+), (\w+), (\w+), "([^"]*)", "([^"]*)", ' + TEXT + r'\)$')


def lines(name, prefix, pattern):
    out = []
    for line in (root / "sweep" / name).read_text().splitlines():
        if line.startswith(prefix):
            m = pattern.match(line)
            if not m:
                sys.exit(f"sweep/{name}: cannot read {line!r}")
            out.append(m.groups())
    return out


def text(s):
    return repr(s.replace('\\"', '"'))


print('"""The catalogues of the Python analysis, generated from sweep/design_methods.def,')
print("sweep/distributions.def and sweep/case_record.def by scripts/analysis-catalogue.py")
print('(`bash scripts/gen-docs.sh`); a test keeps it in step. Do not edit."""')
print()
print("# design.method -> sample: an independent sample of the distributions (a saltelli base,")
print("# accepts design.correlation); distributions: the factors are distributions (not a file's")
print("# points); points per grid point: size * (per_factor * factors + extra); the first")
print("# iid_blocks * size points are an independent sample of the factors")
print("DESIGN_METHODS = {")
for _, name, doc, _, dist, sample, per, extra, iid in lines("design_methods.def",
                                                            "RODEND_CHOICE", METHOD):
    print(f'    "{name}": {{"distributions": {dist == "true"}, "sample": {sample == "true"}, '
          f'"per_factor": {per}, "extra": {extra}, "iid_blocks": {iid},')
    print(f'        "description": {text(doc)}}},')
print("}")
print()
print("# design.factors[i].distribution -> its parameters (design.json's keys) and whether its")
print("# support is finite")
print("DISTRIBUTIONS = {")
for _, name, doc, keys, bounded in lines("distributions.def", "RODEND_CHOICE", DISTRIBUTION):
    ks = tuple(k.strip().strip('"') for k in keys.split(","))
    print(f'    "{name}": {{"keys": {ks!r}, "bounded": {bounded == "true"}, '
          f'"description": {text(doc)}}},')
print("}")
print()
print("# the summary columns of the case record (its fields but those of the case file only):")
print("# neither grid coordinates nor metrics")
print("RECORD_COLUMNS = (")
for _, _, place, name, _, _ in lines("case_record.def", "RODEND_RECORD_FIELD", FIELD):
    if place != "file":
        print(f'    "{name}",')
print(")")
