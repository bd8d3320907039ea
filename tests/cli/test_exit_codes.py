#!/usr/bin/env python3
"""One exit-code table for every subcommand (README "Command line"; issue 35 item 8): a command
line that does not parse is bad input, exit 2 with a message, for every subcommand; help is 0;
`rodend metrics --json` is the catalogue as JSON."""
import json

from common import check, finish, run

bad = [[], ["run"], ["run", "x.json", "--threads", "0"], ["run", "x.json", "--bogus"],
       ["--bogus"], ["nonsense"], ["compare", "a"], ["merge"], ["report"], ["params"],
       ["signals", "--bogus"], ["metrics", "--bogus"], ["results-dir"]]
for args in bad:
    r = run(args)
    check(r.returncode == 2, f"rodend {' '.join(args)}: exit {r.returncode}, expected 2")
    check(r.stderr.strip() != "", f"rodend {' '.join(args)}: no message")
for args in (["--help"], ["run", "--help"], ["compare", "--help"], ["--version"]):
    r = run(args)
    check(r.returncode == 0, f"rodend {' '.join(args)}: exit {r.returncode}, expected 0")
r = run(["metrics", "--json"])
check(r.returncode == 0, f"metrics --json: exit {r.returncode}")
metrics = json.loads(r.stdout)
names = [line.split(" [")[0] for line in run(["metrics"]).stdout.splitlines()]
check([m["name"] for m in metrics] == names, "metrics --json lists other metrics than metrics")
check(all(set(m) == {"name", "unit", "description"} for m in metrics), "metrics --json fields")
finish("exit codes")
