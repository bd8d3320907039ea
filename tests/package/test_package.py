"""The CMake package (issue 22): `cmake --install` of this build into a temporary prefix, then a
tiny consumer project (tests/package/consumer) configured with find_package(rodend) against
that prefix only, built, and run (one gravity-drop case against the analytic free fall). The
installed rodend executable runs too.

    test_package.py CMAKE BUILD_DIR [CXX_COMPILER_LAUNCHER]
"""
import os
import shutil
import subprocess
import sys
import tempfile


def step(what, cmd, **kw):
    r = subprocess.run(cmd, capture_output=True, text=True, **kw)
    if r.returncode != 0:
        print(f"FAIL: {what}: {' '.join(cmd)}\n{r.stdout[-3000:]}\n{r.stderr[-3000:]}",
              file=sys.stderr)
        sys.exit(1)
    return r


def main():
    cmake, build = sys.argv[1], sys.argv[2]
    launcher = sys.argv[3] if len(sys.argv) > 3 else ""
    here = os.path.dirname(os.path.abspath(__file__))
    tmp = tempfile.mkdtemp(prefix="rodend-package-")
    try:
        prefix = os.path.join(tmp, "install")
        step("install", [cmake, "--install", build, "--prefix", prefix])
        for f in ["lib/cmake/rodend/rodendConfig.cmake", "lib/cmake/rodend/rodendConfigVersion.cmake",
                  "lib/librodend_core.a", "lib/librodend_sweep.a", "bin/rodend",
                  "include/rodend/sweep/runner.hpp", "include/rodend/core/signals.def"]:
            if not os.path.exists(os.path.join(prefix, f)):
                print(f"FAIL: the install tree has no {f}", file=sys.stderr)
                sys.exit(1)
        args = [cmake, "-S", os.path.join(here, "consumer"), "-B", os.path.join(tmp, "build"),
                "-DCMAKE_BUILD_TYPE=Release", f"-DCMAKE_PREFIX_PATH={prefix}"]
        if launcher:
            args.append(f"-DCMAKE_CXX_COMPILER_LAUNCHER={launcher}")
        step("configure the consumer", args)
        # ccache (when the build uses it): paths relative to the temporary folder, so that a
        # rerun hits the cache (the compile is most of this test's time)
        env = dict(os.environ, CCACHE_BASEDIR=tmp)
        step("build the consumer", [cmake, "--build", os.path.join(tmp, "build")], env=env)
        r = step("run the consumer", [os.path.join(tmp, "build", "consumer")])
        print(r.stdout.strip())
        r = step("run the installed rodend", [os.path.join(prefix, "bin", "rodend"), "scenes"])
        if "gravity-drop" not in r.stdout:
            print("FAIL: the installed rodend does not list gravity-drop", file=sys.stderr)
            sys.exit(1)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    print("package: all checks passed")


if __name__ == "__main__":
    main()
