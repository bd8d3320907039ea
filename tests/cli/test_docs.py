"""docs/signals.md, docs/metrics.md, docs/choices.md, the settings table of docs/studies.md and
the case record table of docs/results.md are in step with the catalogues in the binary."""
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
finish("docs")
