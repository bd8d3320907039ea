#!/usr/bin/env python3
"""Lists the functions of C++ and Python sources with their length in lines (signature to
closing brace or last line), longest first, and fails (exit 1) when one is longer than the limit.

  scripts/function-lengths.py [--limit 60] [--all] [--file-limit N] PATH...   (files or dirs)

With --file-limit, a file (.cpp, .hpp, .def or .py) of more than N lines fails it too: a file
does one job, and one that grows past N has taken on a second.

C++: a function is a brace block at namespace or class level (a method defined in a class body
counts as a function of its own) whose head (the text since the last ';', '{' or '}') ends in
')' plus qualifiers, or is a constructor's initialiser list; control statements, classes,
namespaces, enums and initialisers are not. Lambdas and local classes count towards the
function that contains them. Comments, strings and character literals are blanked first, so
braces in them do not count.

Python: every `def` at module or class level (methods too), from its `def` line to its last
line, read with the ast module; a function nested in another counts towards the one that
contains it, as a lambda does in C++.
"""
import argparse
import ast
import pathlib
import re
import sys

LEAD = re.compile(r"(\s|(public|private|protected)\s*:(?!:))*")
CONTROL = re.compile(r"^\s*(if|for|while|switch|catch|do|else|try|return)\b")
TYPE_HEAD = re.compile(r"\b(class|struct|union|enum|namespace)\b[^()]*$")
QUALIFIERS = r"(\s|&|const|override|final|noexcept(\([^()]*\))?|mutable|->\s*[\w:<>,\s*&]+)*"
FUNC_TAIL = re.compile(r"\)" + QUALIFIERS + r"$")
INIT_LIST = re.compile(r"\)\s*:\s*[\w:]+\s*[({]")  # Ctor(...) : member(...), ... {
INIT_ELEM = re.compile(r"\)\s*:\s*[\w:]+\s*[({].*[,:]\s*[\w:]+$|\)\s*:\s*[\w:]+$")  # ... , m_{


def blank(src: str) -> str:
    """Comments, string and character literals replaced by spaces (newlines kept)."""
    pat = re.compile(
        r'//[^\n]*|/\*.*?\*/|R"(?P<d>[^(]*)\(.*?\)(?P=d)"|"(\\.|[^"\\\n])*"|\'(\\.|[^\'\\\n])*\'',
        re.S)
    return pat.sub(lambda m: re.sub(r"[^\n]", " ", m.group(0)), src)


def functions(path: pathlib.Path):
    text = blank(path.read_text())
    depth = 0
    head_start = 0  # offset where the current head begins
    func_depth = None  # depth at which the enclosing function body opened
    func_begin = 0
    func_name = ""
    keep = []  # per open block: a brace initialiser of a constructor's member (head continues)
    for i, ch in enumerate(text):
        if ch == "{":
            keep.append(False)
            if func_depth is None:
                head = text[head_start:i]
                flat = " ".join(head.split())
                if INIT_ELEM.search(flat):
                    keep[-1] = True
                    depth += 1
                    continue
                is_func = (
                    flat
                    and not CONTROL.match(flat)
                    and not TYPE_HEAD.search(flat)
                    and not flat.endswith("=")
                    and (FUNC_TAIL.search(flat) or INIT_LIST.search(flat))
                )
                if is_func:
                    func_depth = depth
                    lead = LEAD.match(head).end()  # blanks and access labels
                    func_begin = text.count("\n", 0, head_start + lead) + 1
                    name = re.search(r"([~\w:]+(<[^()]*>)?|operator\s*\S+)\s*\(", flat)
                    func_name = name.group(1) if name else flat[:40]
            depth += 1
            head_start = i + 1
        elif ch == "}":
            depth -= 1
            if keep and keep.pop():
                continue
            if func_depth is not None and depth == func_depth:
                end = text.count("\n", 0, i) + 1
                yield func_name, func_begin, end - func_begin + 1
                func_depth = None
            head_start = i + 1
        elif ch == ";":
            if func_depth is None:
                head_start = i + 1


def python_functions(path: pathlib.Path):
    """(qualified name, first line, lines) of each def at module or class level."""
    tree = ast.parse(path.read_text(), filename=str(path))

    def walk(node, prefix):
        for child in ast.iter_child_nodes(node):
            if isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef)):
                yield prefix + child.name, child.lineno, child.end_lineno - child.lineno + 1
            elif isinstance(child, ast.ClassDef):
                yield from walk(child, prefix + child.name + ".")
            elif not isinstance(child, ast.Lambda):
                yield from walk(child, prefix)  # defs under if/try at module level

    yield from walk(tree, "")


def measure(path: pathlib.Path):
    return python_functions(path) if path.suffix == ".py" else functions(path)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("paths", nargs="+")
    ap.add_argument("--limit", type=int, default=60)
    ap.add_argument("--all", action="store_true", help="list every function, not only the long")
    ap.add_argument("--file-limit", type=int, help="also fail on a file longer than this")
    a = ap.parse_args()
    files, sources = [], []  # C++ and Python files (functions); those and the .def catalogues
    for p in map(pathlib.Path, a.paths):
        found = [p]
        if p.is_dir():
            found = sorted(q for q in p.rglob("*") if q.suffix in (".cpp", ".hpp", ".def", ".py")
                           and "__pycache__" not in q.parts)
        sources += found
        files += [q for q in found if q.suffix != ".def"]
    rows = [(n, f, name, line) for f in files for name, line, n in measure(f)]
    rows.sort(key=lambda r: -r[0])
    long = [r for r in rows if r[0] > a.limit]
    for n, f, name, line in rows if a.all else long:
        print(f"{n:5d}  {f}:{line}  {name}")
    print(f"{len(rows)} functions in {len(files)} files; {len(long)} longer than {a.limit} lines",
          file=sys.stderr)
    big = []
    if a.file_limit is not None:
        sizes = [(len(f.read_text().splitlines()), f) for f in sources]
        big = [(n, f) for n, f in sizes if n > a.file_limit]
        for n, f in sorted(big, key=lambda r: -r[0]):
            print(f"{n:5d}  {f}  (file)")
        print(f"{len(sources)} files; {len(big)} longer than {a.file_limit} lines", file=sys.stderr)
    return 1 if long or big else 0


if __name__ == "__main__":
    sys.exit(main())
