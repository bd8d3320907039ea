#!/usr/bin/env python3
"""Prints the case record's catalogue (sweep/case_record.def) as the markdown table of
docs/results.md (scripts/gen-docs.sh puts it there; the test cli.docs keeps it in step).

  scripts/record-table.py [REPO_ROOT]
"""
import pathlib
import re
import sys

root = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else pathlib.Path(__file__).parent.parent)
FIELD = re.compile(r'^RODEND_RECORD_FIELD\((\w+), (\w+), (\w+), "([^"]*)", "([^"]*)", "((?:[^"\\]|\\.)*)"\)$')
PLACE = {"identity": "summary (before the grid keys)", "run": "summary (after the grid keys)",
         "file": "case file only"}
TYPE = {"text": "string", "integer": "int64", "real": "float64", "json": "string (JSON)",
        "features": "string (JSON array)", "run_status": "string"}
print("| name | type | unit | in | description |")
print("|---|---|---|---|---|")
for line in (root / "sweep/case_record.def").read_text().splitlines():
    m = FIELD.match(line)
    if line.startswith("RODEND_RECORD_FIELD") and not m:
        sys.exit(f"sweep/case_record.def: cannot read {line!r}")
    if m:
        _, kind, place, name, unit, desc = m.groups()
        desc = desc.replace('\\"', '"').replace("|", "\\|")
        print(f"| `{name}` | {TYPE[kind]} | {unit or '—'} | {PLACE[place]} | {desc} |")
