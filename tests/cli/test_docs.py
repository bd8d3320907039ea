"""docs/signals.md, docs/metrics.md, docs/choices.md and the settings table of docs/studies.md are
in step with the catalogues in the binary."""
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
finish("docs")
