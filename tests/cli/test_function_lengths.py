#!/usr/bin/env python3
"""Every function and method, C++ and Python, in core/, sweep/, app/, python/, bench/, plots/
and scripts/ fits on one screen (<= 60 lines), and no file there is longer than 800 lines (a
file does one job): scripts/function-lengths.py over them passes, with no exceptions. First the
script itself is checked on synthetic sources: a 61-line function (C++: inline member,
ref-qualified member, free function, constructor with an initialiser list; Python: function,
method, a function whose nested def makes it long) is reported, a 60-line one and braces in
comments, strings, classes, namespaces and control statements are not; with --file-limit 800,
a file of 801 lines (.cpp, .hpp, .def or .py) fails, one of 800 passes.

  test_function_lengths.py REPO
"""
import pathlib
import subprocess
import sys
import tempfile

repo = pathlib.Path(sys.argv[1])
script = repo / "scripts" / "function-lengths.py"


def run(*paths):
    return subprocess.run([sys.executable, script, *map(str, paths)], capture_output=True,
                          text=True)


def body(n_lines):
    """The n_lines lines of a function after its signature line, closing brace included."""
    inner = "".join(f"  x += {i};  // {{ not a brace\n" for i in range(n_lines - 3))
    return "  int x = 0;\n" + inner + "  return x;\n}\n"


cases = {
    "free": ("namespace a {\nint f(int y) {\n", "}\n"),
    "member": ("struct S {\n  int g() const {\n", "};\n"),
    "ctor": ("class C {\n public:\n  C() : v_(1), w_{2} {\n", "  int v_, w_;\n};\n"),
    "ref_qualified": ("struct R {\n  [[nodiscard]] int h() const& {\n", "};\n"),
}


def py_body(n_lines, indent):
    """The n_lines lines of a Python def after its `def` line."""
    pad = " " * indent
    return "".join(f"{pad}x = {i}  # {{ not a brace\n" for i in range(n_lines - 1)) + \
        f"{pad}return x\n"


py_cases = {
    "py_function": lambda n: "import os\n\n\ndef f(y):\n" + py_body(n - 1, 4),
    "py_method": lambda n: "class K:\n    x = 1\n\n    def g(self):\n" + py_body(n - 1, 8),
    "py_nested": lambda n: "def outer():\n    def inner():\n" + py_body(n - 3, 8) +
    "    return inner\n",
}
failed = 0
with tempfile.TemporaryDirectory() as d:
    for name, (head, tail) in cases.items():
        for n, expect in ((60, 0), (61, 1)):
            src = pathlib.Path(d) / f"{name}_{n}.cpp"
            src.write_text(head + body(n - 1) + tail)  # the signature is the head's last line
            r = run(src)
            if r.returncode != expect:
                print(f"FAIL: {name} function of {n} lines: exit {r.returncode}, expected "
                      f"{expect}\n{r.stdout}{r.stderr}")
                failed += 1
    for name, make in py_cases.items():
        for n, expect in ((60, 0), (61, 1)):
            src = pathlib.Path(d) / f"{name}_{n}.py"
            src.write_text(make(n))
            r = run(src)
            if r.returncode != expect:
                print(f"FAIL: {name} of {n} lines: exit {r.returncode}, expected "
                      f"{expect}\n{r.stdout}{r.stderr}")
                failed += 1
    src = pathlib.Path(d) / "not_functions.cpp"
    src.write_text("namespace n {\nstruct T {\n" + "  int a;\n" * 70 + "};\n"
                   "const char* s = \"{\";\n"
                   "void h(int k) {\n  if (k) {\n" + "    k++;\n" * 20 + "  }\n}\n}\n")
    r = run(src)
    if r.returncode != 0:
        print(f"FAIL: a long struct or a string brace counted as a function\n{r.stdout}")
        failed += 1
    for suffix in (".cpp", ".hpp", ".def", ".py"):
        for n, expect in ((800, 0), (801, 1)):
            folder = pathlib.Path(d) / f"files_{n}{suffix.replace('.', '_')}"
            folder.mkdir()
            line = "# a line\n" if suffix == ".py" else "// a line\n"
            (folder / f"long{suffix}").write_text(line * n)
            r = run("--file-limit", "800", folder)
            if r.returncode != expect:
                print(f"FAIL: a {suffix} file of {n} lines under --file-limit 800: exit "
                      f"{r.returncode}, expected {expect}\n{r.stdout}{r.stderr}")
                failed += 1

FOLDERS = ("core", "sweep", "app", "python", "bench", "plots", "scripts")
FILE_LIMIT = 800
r = run("--file-limit", str(FILE_LIMIT), *(repo / f for f in FOLDERS))
too_long = []
for line in r.stdout.splitlines():
    parts = line.split()  # "  <lines>  <file>:<line>  <function>" or "  <lines>  <file>  (file)"
    if len(parts) == 3 and parts[0].isdigit():
        too_long.append(line)
if too_long or r.returncode != 0:
    print(f"FAIL: functions longer than 60 lines or files longer than {FILE_LIMIT} lines in " +
          ", ".join(FOLDERS) + " (split them into named stages, files by job):")
    print("\n".join(too_long) or r.stdout + r.stderr)
    failed += 1
else:
    print(r.stderr.strip())
sys.exit(1 if failed else 0)
