"""Every file of tests/bad_inputs/ is rejected with exit code 2, a message that names the file
and the key path and says what was expected, and nothing written."""
import json
import os
import sys
import tempfile

from common import check, finish, run

corpus = sys.argv[1]
expected = json.load(open(os.path.join(corpus, "expected.json")))
files = sorted(f for f in os.listdir(corpus) if f.endswith(".json") and f != "expected.json")
check(sorted(expected) == files, f"expected.json does not list exactly the corpus: {files}")

for name in files:
    key, text = expected.get(name, ["?", "?"])
    with tempfile.TemporaryDirectory() as root:
        for cmd in (["run"], ["run", "--dry-run"]):
            r = run(cmd + [os.path.join(corpus, name), "--results-root", root, "-q"])
            msg = r.stderr.strip()
            check(r.returncode == 2, f"{name} {cmd}: exit code {r.returncode}, expected 2 ({msg})")
            check(name in msg, f"{name}: message does not name the file: {msg}")
            check(key == "" or f": {key}: " in msg, f"{name}: message does not name key '{key}': {msg}")
            check(text in msg, f"{name}: message lacks '{text}': {msg}")
            check("Traceback" not in msg and "terminate" not in msg, f"{name}: crash: {msg}")
            check(os.listdir(root) == [], f"{name}: something was written: {os.listdir(root)}")
finish("bad input")
