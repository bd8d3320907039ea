"""Every file a comment of the code names exists (the code's comments are read like the docs).

    test_comment_paths.py REPO

The comments of the tracked sources (C++ `//`, Python, shell and CMake `#`, and Python's
docstrings) under core/, sweep/, app/, python/, plots/, bench/, scripts/, tests/, cmake/, fuzz/
and .ci/ are scanned for file
names with a source or document ending (`sweep/results/case_file.cpp`, `case_file.cpp`,
`docs/model.md`). A name with a folder must exist relative to the repository, to the commenting
file's folder or to one of its ancestors; a bare name must be the name of a tracked file, or of
a file of a library named in EXTERNAL. Placeholders are skipped: an ALL-CAPS word (`NAME`),
`<...>`, `*`, `{...}`, a one-letter stem (`docs/x.md`), the throwaway files the prove
scripts create, and a bare name the file itself has as a string literal (`"presets.md"`: a file
it writes). docs/ and README.md are checked by cli.doc_refs.
Before the tree, the checker is run on a synthetic file with one dangling name of each kind and
must report both, so this test can fail.
"""
import ast
import os
import re
import subprocess
import sys
import tempfile

from common import check, finish

ROOTS = ["core", "sweep", "app", "python", "plots", "bench", "scripts", "tests", "cmake",
         "fuzz", ".ci", "CMakeLists.txt"]
# files of other projects that comments cite by name, and the project
EXTERNAL = {"rosenbrock4.hpp": "Boost.Odeint", "catch.hpp": "Catch2",
            "regex_automaton.h": "libstdc++"}
PATH = re.compile(r"(?<![\w./<-])((?:[\w.-]+/)*[\w-]+\.(?:cpp|hpp|py|def|sh|md|c|h|in|cff))\b")
PLACEHOLDER = re.compile(r"[A-Z]{3,}|<|\*|\{|(^|/)\w\.\w+$|throwaway")
C_LIKE = {".cpp", ".hpp", ".c", ".h", ".def"}
HASH = {".py", ".sh", ".txt", ".cmake", ".in", ""}


def comment_of(line, ext):
    if ext in C_LIKE:
        i = line.find("//")
    elif ext in HASH:
        i = line.find("#")
    else:
        return ""
    return line[i + 1:] if i >= 0 else ""


def dangling(repo, path, names):
    """The names a file's comments give that name nothing, as 'file:line: name'."""
    ext = os.path.splitext(path)[1]
    if os.path.basename(path) == "CMakeLists.txt":
        ext = ".txt"
    try:
        with open(os.path.join(repo, path), encoding="utf-8") as f:
            lines = f.read().splitlines()
    except (UnicodeDecodeError, FileNotFoundError):
        return []
    texts = [(n, comment_of(line, ext)) for n, line in enumerate(lines, 1)]
    if ext == ".py":
        texts += docstring_lines(lines)
    source = "\n".join(lines)
    out = []
    for n, text in texts:
        for m in PATH.finditer(text):
            name = m.group(1)
            if PLACEHOLDER.search(name) or resolves(repo, path, name, names) or \
                    ("/" not in name and (f'"{name}"' in source or f"'{name}'" in source)):
                continue
            if f"{path}:{n}: {name}" not in out:
                out.append(f"{path}:{n}: {name}")
    return out


def docstring_lines(lines):
    """[(line number, text)] of every docstring of a Python file (module, class, function)."""
    try:
        tree = ast.parse("\n".join(lines))
    except SyntaxError:
        return []
    out = []
    for node in ast.walk(tree):
        if isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)) \
                and node.body and isinstance(node.body[0], ast.Expr) \
                and isinstance(node.body[0].value, ast.Constant) \
                and isinstance(node.body[0].value.value, str):
            d = node.body[0]
            out += [(n, lines[n - 1]) for n in range(d.lineno, d.end_lineno + 1)]
    return out


def resolves(repo, path, name, names):
    if "/" not in name:
        return name in names or name in EXTERNAL
    folder = os.path.dirname(path)
    while True:
        if os.path.exists(os.path.join(repo, folder, name)):
            return True
        if not folder:
            return False
        folder = os.path.dirname(folder)


def tracked(repo, *paths):
    out = subprocess.run(["git", "ls-files", *paths], cwd=repo, capture_output=True, text=True)
    return out.stdout.split()


def self_check():
    with tempfile.TemporaryDirectory() as d:
        os.makedirs(os.path.join(d, "core"))
        with open(os.path.join(d, "core", "a.cpp"), "w") as f:
            f.write("int x;  // see core/gone.cpp and missing.hpp, not core/a.cpp\n")
        got = dangling(d, "core/a.cpp", {"a.cpp"})
        check(got == ["core/a.cpp:1: core/gone.cpp", "core/a.cpp:1: missing.hpp"],
              f"the checker reports both dangling names of the synthetic file, got {got}")
        with open(os.path.join(d, "core", "b.py"), "w") as f:
            f.write('"""Reads core/gone.py and writes out.md."""\nOUT = "out.md"\n'
                    'def f():\n    """As core/b.py and core/lost.py."""\n')
        got = dangling(d, "core/b.py", {"b.py"})
        check(got == ["core/b.py:1: core/gone.py", "core/b.py:4: core/lost.py"],
              f"the checker reports the dangling names of the docstrings, got {got}")


def main():
    repo = sys.argv[1]
    self_check()
    names = {os.path.basename(p) for p in tracked(repo)}
    files = [p for p in tracked(repo, *ROOTS)
             if os.path.splitext(p)[1] not in {".json", ".h5", ".csv", ".png", ".ipynb", ".md"}]
    bad = [b for p in files for b in dangling(repo, p, names)]
    for b in bad:
        check(False, f"a comment names a file that does not exist: {b}")
    print(f"comment_paths: {len(files)} files read, {len(bad)} dangling name(s)")
    finish("comment_paths")


main()
