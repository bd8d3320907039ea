"""`rodend analyze` from an installed tree finds its Python package relative to the install, not
through a path of the source tree: `cmake --install` of this build into a temporary prefix, then
the installed rodend analyses a small designed-study folder (Ishigami, Monte Carlo, written by
tests/cli/analyze_fixtures.py) from a temporary folder, with no PYTHONPATH and no
RODEND_BUILD_DIR, so that /usr/bin/python3 cannot import rodend by itself: the package must come
from PREFIX/share/rodend/python. With that folder moved away, it must stop with exit 2 and a
message naming where it looked (a rodend with the source path compiled in ran the analysis from
the source tree instead).

    test_installed_analyze.py CMAKE BUILD_DIR
"""
import json
import os
import shutil
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "cli"))
import analyze_fixtures as fx  # noqa: E402


def fail(what):
    print("FAIL: " + what, file=sys.stderr)
    sys.exit(1)


def main():
    cmake, build = sys.argv[1], sys.argv[2]
    tmp = tempfile.mkdtemp(prefix="rodend-installed-analyze-")
    try:
        prefix = os.path.join(tmp, "install")
        r = subprocess.run([cmake, "--install", build, "--prefix", prefix],
                           capture_output=True, text=True)
        if r.returncode != 0:
            fail(f"install: {r.stderr[-2000:]}")
        package = os.path.join(prefix, "share", "rodend", "python")
        if not os.path.isfile(os.path.join(package, "rodend", "analyze.py")):
            fail(f"the install tree has no {package}/rodend/analyze.py")
        fs = [fx.uniform(f"parameters.x{i}", -fx.PI, fx.PI, "rad") for i in (1, 2, 3)]
        x = fx.mc_points(fs, 200, 7)
        design = {"method": "monte-carlo", "size": 200, "seed": 7, "points": len(x), "factors": fs}
        folder = fx.write_folder(os.path.join(tmp, "ishigami"), design, x, {"y": fx.ishigami(x)})
        env = {k: v for k, v in os.environ.items()
               if k not in ("PYTHONPATH", "RODEND_BUILD_DIR", "RODEND_PYTHON")}
        env["MPLBACKEND"] = "Agg"
        rodend = os.path.join(prefix, "bin", "rodend")
        cmd = [rodend, "analyze", folder, "--no-plots"]
        r = subprocess.run(cmd, capture_output=True, text=True, env=env, cwd=tmp)
        if r.returncode != 0:
            fail(f"installed rodend analyze: rc {r.returncode}\n{r.stdout[-2000:]}\n{r.stderr[-2000:]}")
        with open(os.path.join(folder, "analysis", "analysis.json"), encoding="utf-8") as fh:
            doc = json.load(fh)
        if "y" not in doc["groups"][0]["metrics"]:
            fail("analysis.json has no metric y")
        shutil.move(package, os.path.join(tmp, "moved-away"))
        shutil.rmtree(os.path.join(folder, "analysis"))
        r = subprocess.run(cmd, capture_output=True, text=True, env=env, cwd=tmp)
        if r.returncode != 2 or package not in r.stderr or "/usr/bin/python3" not in r.stderr:
            fail(f"without the installed package: rc {r.returncode} (want 2), stderr "
                 f"{r.stderr[-1000:]!r} (want it to name {package} and /usr/bin/python3)")
        if os.path.exists(os.path.join(folder, "analysis")):
            fail("without the installed package, analysis/ was written")
        print(r.stderr.strip())
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    print("installed analyze: all checks passed")


if __name__ == "__main__":
    main()
