"""The CMake package: `cmake --install` of this build into a temporary prefix, then a tiny
consumer project (tests/package/consumer) configured with find_package(rodend) against that
prefix only, built, and run (one gravity-drop case against the analytic free fall), with the
API reference's example examples/cpp/load_study.cpp (rodend::load_study on
studies/gravity-drop.json). The headers are included as <rodend/sweep/...>: only PREFIX/include
is on the consumer's include path, and no installed header includes "core/..." or "sweep/..."
(which another project's folders of those names could shadow). The installed rodend
executable runs too.

    test_package.py CMAKE BUILD_DIR [CXX_COMPILER_LAUNCHER]
"""
import os
import re
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
        generic = []
        for root, _, names in os.walk(os.path.join(prefix, "include", "rodend")):
            for n in names:
                with open(os.path.join(root, n), encoding="utf-8") as fh:
                    generic += [f"{n}: {line.strip()}" for line in fh
                                if re.match(r'\s*#.*"(core|sweep)/', line)]
        if generic:
            print("FAIL: installed headers include generic paths:\n" + "\n".join(generic[:10]),
                  file=sys.stderr)
            sys.exit(1)
        repo = os.path.dirname(os.path.dirname(here))
        args = [cmake, "-S", os.path.join(here, "consumer"), "-B", os.path.join(tmp, "build"),
                "-DCMAKE_BUILD_TYPE=Release", f"-DCMAKE_PREFIX_PATH={prefix}",
                f"-DRODEND_EXAMPLES={os.path.join(repo, 'examples')}"]
        if launcher:
            args.append(f"-DCMAKE_CXX_COMPILER_LAUNCHER={launcher}")
        step("configure the consumer", args)
        # ccache (when the build uses it): paths relative to the temporary folder, so that a
        # rerun hits the cache (the compile is most of this test's time)
        env = dict(os.environ, CCACHE_BASEDIR=tmp)
        step("build the consumer", [cmake, "--build", os.path.join(tmp, "build")], env=env)
        r = step("run the consumer", [os.path.join(tmp, "build", "consumer")])
        print(r.stdout.strip())
        study = os.path.join(repo, "studies", "gravity-drop.json")
        r = step("run the load_study example", [os.path.join(tmp, "build", "load_study"), study],
                 cwd=tmp)
        print(r.stdout.strip())
        if "study gravity-drop: scene gravity-drop" not in r.stdout or "first case: ok" not in r.stdout:
            print("FAIL: the load_study example's output", file=sys.stderr)
            sys.exit(1)
        r = step("run the installed rodend", [os.path.join(prefix, "bin", "rodend"), "scenes"])
        if "gravity-drop" not in r.stdout:
            print("FAIL: the installed rodend does not list gravity-drop", file=sys.stderr)
            sys.exit(1)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    print("package: all checks passed")


if __name__ == "__main__":
    main()
