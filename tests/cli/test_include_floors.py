#!/usr/bin/env python3
"""No file of core/ includes a header of a floor above it (docs/architecture.md, "Layers"):
the parameters know no scene, the contact interface not its template evaluation, the steppers
not the driver. Each rule: the files of a floor, and the headers they may not include.

  test_include_floors.py REPO
"""
import pathlib
import re
import sys

repo = pathlib.Path(sys.argv[1])
RULES = [
    # the parameters: below the scenes, their composed defaults and the profile reader
    (["core/params.hpp", "core/params.cpp", "core/profile_data.hpp"],
     ["core/scene.hpp", "core/scene_parameters.hpp", "core/scenes/"]),
    # the contact interface: below its template evaluation and the dual numbers of the Jacobian
    (["core/contact.hpp", "core/contact.cpp"], ["core/contact_eval.hpp", "core/dual.hpp"]),
    # the steppers: below the driver, sharing only core/integrator_settings.hpp with it
    (["core/stepper.hpp", "core/steppers_*.cpp", "core/cvode/*", "core/integrator_settings.hpp"],
     ["core/integrator.hpp", "core/driver/"]),
]
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)
bad = []
for floor, above in RULES:
    files = sorted({f for pattern in floor for f in repo.glob(pattern)})
    if not files:
        bad.append(f"no file matches {floor}: the rule is stale")
    for f in files:
        for inc in INCLUDE.findall(f.read_text()):
            if any(inc == a or (a.endswith("/") and inc.startswith(a)) for a in above):
                bad.append(f"{f.relative_to(repo)} includes {inc}, a floor above it")
for b in bad:
    print(b)
print(f"include floors: {len(bad)} violation(s)")
sys.exit(1 if bad else 0)
