"""docs/signals.md, docs/metrics.md, docs/choices.md, the settings table of docs/studies.md, the
case record table of docs/results.md and python/rodend/analysis/catalogue.py are in step with
the catalogues."""
import subprocess
import sys

from common import check, finish, run

root = sys.argv[1]
for cmd, doc in ((["signals", "--markdown"], "docs/signals.md"), (["metrics", "--markdown"], "docs/metrics.md"),
                 (["choices", "--markdown"], "docs/choices.md"),
                 (["schema", "--markdown"], "docs/studies.md")):
    r = run(cmd)
    text = open(f"{root}/{doc}").read()
    check(r.returncode == 0 and r.stdout in text,
          f"{doc} is out of date: regenerate it with `rodend {' '.join(cmd)}`")
# the case record table of docs/results.md, from sweep/case_record.def
r = subprocess.run([sys.executable, f"{root}/scripts/record-table.py", root],
                   capture_output=True, text=True)
check(r.returncode == 0 and r.stdout in open(f"{root}/docs/results.md").read(),
      "docs/results.md's case record table is out of date: regenerate it with "
      "`bash scripts/gen-docs.sh`")
# the Python analysis's catalogues, from sweep/design_methods.def, distributions.def and
# case_record.def
r = subprocess.run([sys.executable, f"{root}/scripts/analysis-catalogue.py", root],
                   capture_output=True, text=True)
check(r.returncode == 0 and r.stdout == open(f"{root}/python/rodend/analysis/catalogue.py").read(),
      "python/rodend/analysis/catalogue.py is out of date: regenerate it with "
      "`bash scripts/gen-docs.sh`")
finish("docs")
