"""Every file path, link and command of README.md and docs/*.md is checked.

    test_doc_refs.py REPO BUILD_DIR

What is checked, and how a piece of documentation opts out:

- Paths in backticks (inline code, and the words of checked command blocks) whose first
  component is a top-level entry of the repository (`core/...`, `studies/...`, `docs/...`,
  `CITATION.cff`): the file or folder exists. `<name>`, `{a,b}`, `*` and ALL-CAPS words
  (`SCENE`, `GROUP`) are placeholders: the path is then a pattern that must match at least one
  file. `build/...` is looked up in the build directory under test; `results/...`, `build-*/`
  and paths whose first component is not in the repository (`cases/<id>.h5`, `RESULTS_DIR/...`)
  name things a run creates and are not checked. A path that leaves the repository (`../x`) is
  an error.
- Links `[text](target)`: a relative target resolves (from the document's folder) to a file or
  folder of the repository, and a `#fragment` names a heading of the target (GitHub's anchors).
- Fenced blocks, by their info string:
  `sh` / `bash` (also `sh runnable`, which cli.doc_blocks runs): every command is checked.
  A `rodend` command (`rodend`, `build/rodend`, `./build/rodend`, also after `mpirun`, `srun`,
  `valgrind` and `VAR=value` prefixes) must succeed: `run` with `--dry-run` added (resolves and
  validates every case, runs nothing); `scenes`, `params`, `signals`, `metrics`, `schema`,
  `results-dir` as they are; the subcommands that need results (`merge`, `report`, `compare`)
  must exist and every option given must be one their `--help` lists. `bash X` names an
  existing script; `/usr/bin/python3 X` an existing script, and every `--option` given must be
  one `X --help` lists (when X uses argparse). `build/X` (not rodend) exists in the build
  directory. Commands run in a temporary folder laid out like a clone, so nothing is written
  into the repository.
  `json study`: the block is a study file; `rodend run --dry-run` must accept it.
  `json`: the block parses as JSON.
  `text`, `console-example`, `python`, `cmake`: examples of user input or output, and
  non-runnable code: not checked (their paths neither). A block without an info string is an
  error: say what it is.
- The pointers of `rodend --help` and of every subcommand's `--help`: paths
  as above, `README.md#anchor` / `docs/x.md#anchor` and `README "Section"` / `docs/x.md
  "Section"` must name a heading of that document.
- No "issue N" in README.md, docs/, app/, python/rodend/, studies/, examples/ or the help texts
  (check_issue_mentions).
Before checking the documents, the checker is run on a document with one fault of each kind and
on a help text with a dangling pointer of each kind, and must report every one, so this test
can fail.
"""
import glob
import json
import os
import re
import shlex
import shutil
import subprocess
import sys
import tempfile

from common import check, finish, rodend_path

CHECKED_SHELL = {"sh", "bash", "shell"}
NOT_CHECKED = {"text", "console-example", "python", "cmake", "console"}
RODEND_NAMES = {"rodend", "build/rodend", "./build/rodend"}
LAUNCHERS = {"mpirun", "mpiexec", "srun", "valgrind", "time", "env", "nice"}
RUN_AS_IS = {"scenes", "params", "signals", "metrics", "schema", "results-dir"}
# the variables a documented command may use (the Slurm job script's)
DOC_ENV = {"SLURM_ARRAY_TASK_ID": "1", "SLURM_ARRAY_TASK_COUNT": "16", "SLURM_CPUS_PER_TASK": "2"}
SKIP_FIRST = {"results", "fuzz-work"}
FENCE = re.compile(r"^( {0,3})(`{3,}|~{3,})(.*)$")
SPAN = re.compile(r"(?<!`)(`+)(?!`)(.+?)(?<!`)\1(?!`)", re.S)
LINK = re.compile(r"\[([^\]]*)\]\(([^)\s]+)\)")
# a help text's pointer into a document: README "Section", docs/x.md#anchor
SECTION_POINTER = re.compile(r'\b(README(?:\.md)?|docs/[\w.-]+\.md)(?:#([\w-]+)|\s+"([^"]+)")')


class Checker:
    def __init__(self, repo, build):
        self.repo, self.build = repo, build
        self.top = {e for e in os.listdir(repo)
                    if not e.startswith("build") and e not in SKIP_FIRST and e != ".git"}
        self.help_cache = {}
        self.work = tempfile.mkdtemp(prefix="rodend-docrefs-")
        for d in ("studies", "plots", "examples", "python", "tests", "scripts", "bench"):
            os.symlink(os.path.join(repo, d), os.path.join(self.work, d))
        os.makedirs(os.path.join(self.work, "build"))
        os.symlink(rodend_path(), os.path.join(self.work, "build", "rodend"))
        self.env = dict(os.environ, PYTHONPATH=os.path.join(repo, "python"),
                        RODEND_BUILD_DIR=build, MPLBACKEND="Agg", **DOC_ENV)
        self.commands = self.paths = self.links = 0

    def close(self):
        shutil.rmtree(self.work, ignore_errors=True)

    # ---- paths -------------------------------------------------------------------------------
    def check_path(self, token, where, problems):
        """One word that may be a repository path."""
        t = token.strip().strip("\"'`[](),;:")
        while t.endswith("}") and t.count("}") > t.count("{"):
            t = t[:-1].rstrip("\"'`[](),;:")
        while t.startswith("{") and t.count("{") > t.count("}"):
            t = t[1:].lstrip("\"'`[](),;:")
        if "=" in t:
            t = t.split("=", 1)[1].strip("\"'")
        t = t.split("#", 1)[0]
        if not t or "://" in t or t.startswith("/") or t.startswith("-") or t.startswith("$"):
            return
        while t.startswith("./"):
            t = t[2:]
        if t.startswith("../"):
            problems.append(f"{where}: `{token}` points outside the repository")
            return
        first = t.split("/", 1)[0]
        if first == "build":
            self.paths += 1
            if not (os.path.exists(os.path.join(self.build, t[6:])) or t == "build/"):
                problems.append(f"{where}: `{t}` is not in the build directory")
            return
        if first not in self.top:
            return
        self.paths += 1
        if os.path.exists(os.path.join(self.repo, t)):
            return
        pattern = re.sub(r"<[^>]*>", "*", t)
        pattern = re.sub(r"\b[A-Z][A-Z_0-9]+\b", "*", pattern)
        if pattern != t or "*" in t or "{" in t:
            for p in expand_braces(pattern):
                if glob.glob(os.path.join(self.repo, p)):
                    return
            problems.append(f"{where}: `{t}` matches no file of the repository")
        else:
            problems.append(f"{where}: `{t}` does not exist in the repository")

    # ---- links -------------------------------------------------------------------------------
    def check_link(self, doc, target, where, problems, anchors_of):
        if re.match(r"^[a-z]+:", target):
            return
        self.links += 1
        path, _, frag = target.partition("#")
        if not path:
            if frag not in anchors_of(doc):
                problems.append(f"{where}: link `{target}`: no heading with anchor #{frag}")
            return
        full = os.path.normpath(os.path.join(os.path.dirname(doc), path)) if path else doc
        if not full.startswith(self.repo + os.sep) and full != self.repo:
            problems.append(f"{where}: link `{target}` leaves the repository")
            return
        if not os.path.exists(full):
            problems.append(f"{where}: link `{target}`: no such file")
            return
        if frag and full.endswith(".md") and frag not in anchors_of(full):
            problems.append(f"{where}: link `{target}`: no heading with anchor #{frag}")

    # ---- commands ----------------------------------------------------------------------------
    def run(self, cmd, timeout=300):
        return subprocess.run(cmd, cwd=self.work, env=self.env, capture_output=True, text=True,
                              timeout=timeout)

    def help_text(self, cmd):
        key = tuple(cmd)
        if key not in self.help_cache:
            r = self.run(cmd + ["--help"], timeout=120)
            self.help_cache[key] = r.stdout + r.stderr if r.returncode == 0 else None
        return self.help_cache[key]

    def check_shell_block(self, code, where, problems):
        text = re.sub(r"\\\n", " ", code)
        for n, line in enumerate(text.split("\n")):
            if not line.strip() or line.lstrip().startswith("#"):
                continue
            try:
                words = shlex.split(line, comments=True)
            except ValueError as e:
                problems.append(f"{where}: cannot parse `{line.strip()}`: {e}")
                continue
            for w in words:
                self.check_path(w, where, problems)
            if "$(" in line:  # a command substitution: its parts are not a simple command
                continue
            cmd = []
            for w in words + [";"]:
                if w in (";", "&&", "||", "|"):
                    if cmd:
                        self.check_command(cmd, where, problems)
                    cmd = []
                else:
                    cmd.append(w)

    def check_command(self, words, where, problems):
        while words and re.match(r"^[A-Za-z_][A-Za-z0-9_]*=", words[0]):
            words = words[1:]
        if words and words[0] in LAUNCHERS:
            rest = [i for i, w in enumerate(words) if w in RODEND_NAMES]
            if not rest:
                return
            words = words[rest[0]:]
        if not words:
            return
        head, args = words[0], words[1:]
        shown = " ".join(words)
        if head in RODEND_NAMES:
            self.commands += 1
            args = [expand_vars(a, where, problems) for a in args]
            self.check_rodend(args, f"{where}: `{shown}`", problems)
        elif head in ("bash", "sh"):
            script = next((a for a in args if not a.startswith("-")), None)
            if script and not os.path.isfile(os.path.join(self.repo, script)):
                problems.append(f"{where}: `{shown}`: no script {script}")
            self.commands += 1
        elif head in ("/usr/bin/python3", "python3"):
            if not args or args[0] in ("-c", "-m"):
                return
            self.commands += 1
            script, opts = args[0], [a.split("=")[0] for a in args[1:] if a.startswith("--")]
            if not os.path.isfile(os.path.join(self.repo, script)):
                problems.append(f"{where}: `{shown}`: no script {script}")
                return
            with open(os.path.join(self.repo, script), encoding="utf-8") as f:
                has_help = "argparse" in f.read()  # only then is --help safe to ask for
            helptext = self.help_text(["/usr/bin/python3", os.path.join(self.repo, script)]) \
                if has_help else None
            for o in opts:
                if helptext is not None and o not in helptext:
                    problems.append(f"{where}: `{shown}`: {script} has no option {o}")
        elif head.startswith("build/") or head.startswith("./build/"):
            self.commands += 1
            rel = head.split("build/", 1)[1]
            if not os.path.isfile(os.path.join(self.build, rel)):
                problems.append(f"{where}: `{shown}`: {head} is not in the build directory")

    def check_rodend(self, args, where, problems):
        exe = rodend_path()
        if not args or args[0] in ("--help", "-h", "--version"):
            r = self.run([exe] + args[:1])
            if r.returncode != 0:
                problems.append(f"{where}: exit {r.returncode}: {r.stderr.strip()[-500:]}")
            return
        sub = args[0]
        top_help = self.help_text([exe]) or ""
        if not re.search(rf"^\s+{re.escape(sub)}\s", top_help, re.M):
            problems.append(f"{where}: no subcommand {sub}")
            return
        if sub == "run" or sub in RUN_AS_IS:
            cmd = [exe] + args + (["--dry-run"] if sub == "run" and "--dry-run" not in args else [])
            r = self.run(cmd)
            if r.returncode != 0:
                problems.append(f"{where}: exit {r.returncode}: {r.stderr.strip()[-500:]}")
            return
        helptext = self.help_text([exe, sub]) or ""
        for a in args[1:]:
            if a.startswith("-"):
                opt = a.split("=")[0]
                if not re.search(rf"(^|[\s,]){re.escape(opt)}([\s,=]|$)", helptext, re.M):
                    problems.append(f"{where}: `rodend {sub}` has no option {opt}")

    def check_help_text(self, text, where, problems, anchors_of):
        """One help text: its paths exist, its section pointers name headings."""
        for w in text.split():
            self.check_path(w, where, problems)
        for m in SECTION_POINTER.finditer(text):
            doc = "README.md" if m.group(1).startswith("README") else m.group(1)
            full = os.path.join(self.repo, doc)
            anchor = m.group(2) or slug(m.group(3))
            self.links += 1
            if os.path.isfile(full) and anchor not in anchors_of(full):
                problems.append(f"{where}: `{m.group(0)}`: {doc} has no heading #{anchor}")

    def check_help_texts(self, anchors_of):
        """`rodend --help` and every subcommand's --help."""
        exe, problems = rodend_path(), []
        top = self.help_text([exe]) or ""
        check(top, "rodend --help failed")
        self.check_help_text(top, "rodend --help", problems, anchors_of)
        subs = re.findall(r"^  ([a-z][a-z-]*)  ", top.split("Subcommands:")[-1], re.M)
        check(len(subs) >= 10, f"only {subs} found as subcommands in rodend --help")
        for sub in subs:
            text = self.help_text([exe, sub])
            if text is None:
                problems.append(f"rodend {sub} --help failed")
                continue
            self.check_help_text(text, f"rodend {sub} --help", problems, anchors_of)
        return problems

    def check_study_block(self, code, where, problems):
        path = os.path.join(self.work, "doc-study.json")
        with open(path, "w", encoding="utf-8") as f:
            f.write(code)
        r = self.run([rodend_path(), "run", path, "--dry-run"])
        self.commands += 1
        if r.returncode != 0:
            problems.append(f"{where}: the study is refused: {r.stderr.strip()[-500:]}")

    # ---- one document ------------------------------------------------------------------------
    def check_text(self, doc, text, anchors_of):
        """Problems of one document (its path `doc` locates its relative links)."""
        problems = []
        rel = os.path.relpath(doc, self.repo)
        prose, lines, i = [], text.split("\n"), 0
        while i < len(lines):
            m = FENCE.match(lines[i])
            if not m:
                prose.append((i + 1, lines[i]))
                i += 1
                continue
            start, marker, info = i + 1, m.group(2), m.group(3).strip()
            body = []
            i += 1
            while i < len(lines) and not lines[i].strip().startswith(marker):
                body.append(lines[i])
                i += 1
            i += 1
            code = "\n".join(body) + "\n"
            where = f"{rel}:{start}"
            words = info.split()
            lang, flags = (words[0], words[1:]) if words else ("", [])
            if not lang:
                problems.append(f"{where}: a code block without an info string (sh, json, text, "
                                f"console-example, ...: see tests/cli/test_doc_refs.py)")
            elif lang in CHECKED_SHELL:
                self.check_shell_block(code, where, problems)
            elif lang == "json":
                try:
                    json.loads(code)
                except ValueError as e:
                    problems.append(f"{where}: the JSON block does not parse: {e}")
                    continue
                if "study" in flags:
                    self.check_study_block(code, where, problems)
            elif lang not in NOT_CHECKED:
                problems.append(f"{where}: unknown info string `{info}`")
        # prose: inline code spans and links, with line numbers
        joined = "\n".join(line for _, line in prose)
        starts = []
        pos = 0
        for n, line in prose:
            starts.append((pos, n))
            pos += len(line) + 1

        def line_of(offset):
            n = prose[0][0] if prose else 1
            for p, ln in starts:
                if p > offset:
                    break
                n = ln
            return n

        for m in SPAN.finditer(joined):
            where = f"{rel}:{line_of(m.start())}"
            for w in m.group(2).split():
                self.check_path(w, where, problems)
        no_code = SPAN.sub(lambda m: " " * len(m.group(0)), joined)
        for m in LINK.finditer(no_code):
            self.check_link(doc, m.group(2), f"{rel}:{line_of(m.start())}", problems, anchors_of)
        return problems


def expand_braces(p):
    m = re.search(r"\{([^{}]*)\}", p)
    if not m:
        return [p]
    return [x for alt in m.group(1).split(",") for x in expand_braces(p[:m.start()] + alt + p[m.end():])]


def expand_vars(word, where, problems):
    def sub(m):
        name = m.group(1) or m.group(2)
        if name not in DOC_ENV:
            problems.append(f"{where}: `{word}` uses ${name}, which the test does not define")
            return "x"
        return DOC_ENV[name]
    return re.sub(r"\$\{([A-Za-z_][A-Za-z0-9_]*)\}|\$([A-Za-z_][A-Za-z0-9_]*)", sub, word)


def slug(heading):
    s = heading.strip().lower()
    s = re.sub(r"[^\w\- ]", "", s)
    return s.replace(" ", "-")


def make_anchors_of(extra=None):
    cache = dict(extra or {})

    def anchors_of(path):
        if path not in cache:
            seen, out, fenced = {}, set(), None
            with open(path, encoding="utf-8") as f:
                for line in f:
                    m = FENCE.match(line.rstrip("\n"))
                    if m:
                        fenced = None if fenced and line.strip().startswith(fenced) else \
                            (fenced or m.group(2))
                        continue
                    h = re.match(r"^#{1,6}\s+(.*?)\s*#*\s*$", line)
                    if h and not fenced:
                        s = slug(re.sub(r"`", "", h.group(1)))
                        k = seen.get(s, 0)
                        seen[s] = k + 1
                        out.add(s if k == 0 else f"{s}-{k}")
            cache[path] = out
        return cache[path]
    return anchors_of


def self_test(checker, repo):
    """A document with one fault of each kind: the checker must report every one."""
    doc = os.path.join(repo, "docs", "self-test.md")
    faults = {
        "core/no_such_file.cpp": "The law lives in `core/no_such_file.cpp`.",
        "no such file": "See [nowhere](nowhere.md).",
        "no heading with anchor": "See [the model](model.md#no-such-section).",
        "outside the repository": "The thesis is in `../shared/seeds/`.",
        "matches no file": "Each scene's file `core/scenes/<scene>.nothing.json`.",
        "no script scripts/nothing.sh": "```sh\nbash scripts/nothing.sh\n```",
        "exit 2": "```sh\n./build/rodend run studies/default.json --set parameters.contact.clearence=1\n```",
        "has no option --colour": "```sh\nrodend compare --colour results/a results/b\n```",
        "no subcommand frobnicate": "```sh\nrodend frobnicate\n```",
        "the study is refused": "```json study\n{\"scene\": \"no-such-scene\", \"time\": {\"end\": 1, \"sample_interval\": 0.1}}\n```",
        "without an info string": "```\nbash scripts/main.sh\n```",
        "does not parse": "```json\n{\"a\": }\n```",
    }
    text = "# Self test\n\n" + "\n\n".join(faults.values()) + "\n"
    problems = checker.check_text(doc, text, make_anchors_of({doc: {"self-test"}}))
    for what in faults:
        check(any(what in p for p in problems),
              f"the checker misses a fault ({what}); it reported:\n" + "\n".join(problems))
    # and the same kinds of reference, correct, give nothing
    clean = ("# Clean\n\nThe law lives in `core/contact.hpp`, each scene in "
             "`core/scenes/<scene>.params.json`; see [the model](model.md#contact-laws) and "
             "[below](#clean).\n\n```sh\nbash scripts/test.sh\n./build/rodend run "
             "studies/default.json -j 2\nrodend params gravity-drop\n```\n\n```text\n"
             "rodend run MY.json\n```\n")
    false_alarms = checker.check_text(doc, clean, make_anchors_of({doc: {"clean"}}))
    check(not false_alarms, "the checker reports correct references:\n" + "\n".join(false_alarms))
    help_faults = {"docs/no-such.md": "details in docs/no-such.md.",
                   "no heading #comparing-results": 'see README "Comparing results"',
                   "no heading #nowhere": "see docs/results.md#nowhere"}
    problems = []
    checker.check_help_text("\n".join(help_faults.values()), "help", problems, make_anchors_of())
    for what in help_faults:
        check(any(what in p for p in problems),
              f"the help checker misses a fault ({what}); it reported:\n" + "\n".join(problems))
    problems = []
    checker.check_help_text('see docs/results.md "Comparing results", README.md#quick-start, '
                            "plots/plot_study.py", "help", problems, make_anchors_of())
    check(not problems, "the help checker reports correct pointers:\n" + "\n".join(problems))
    print(f"self-test: all {len(faults)} planted faults reported, none on the correct document; "
          f"all {len(help_faults)} dangling help pointers reported")


ISSUE = re.compile(r"\bissues? (?:\d+|#\d+)|\bthe issue's\b", re.I)


def issue_mentions(repo, help_text):
    """Docs, help texts and the Python package's text speak of the software, not of the
    project's issues: "issue 31", "issues 18", "the issue's" in README.md, docs/*.md, app/,
    python/rodend/, the shipped studies (their descriptions head the report), the examples and
    rodend's help texts, each reported with its file and line."""
    files = [os.path.join(repo, "README.md")] + sorted(glob.glob(os.path.join(repo, "docs", "*.md")))
    files += sorted(glob.glob(os.path.join(repo, "studies", "*.json")))
    files += sorted(glob.glob(os.path.join(repo, "examples", "*.*")))
    files += sorted(glob.glob(os.path.join(repo, "app", "*.[ch]pp")))
    files += sorted(glob.glob(os.path.join(repo, "python", "rodend", "**", "*.py"), recursive=True))
    found = []
    for path in files:
        with open(path, encoding="utf-8") as f:
            for n, line in enumerate(f, 1):
                if ISSUE.search(line):
                    found.append(f"{os.path.relpath(path, repo)}:{n}: {line.strip()[:120]}")
    found += [f"rodend --help texts: {m.group(0)}" for m in ISSUE.finditer(help_text)]
    return found


def help_texts():
    """rodend --help and every subcommand's --help, concatenated."""
    import subprocess
    out = subprocess.run([rodend_path(), "--help"], capture_output=True, text=True).stdout
    subs = re.findall(r"^\s{2}([a-z][a-z-]+)\s", re.split(r"(?i)subcommands:", out)[-1], re.M)
    check(len(subs) >= 10, f"rodend --help lists {subs}: is the parser still finding them?")
    for sub in subs:
        out += subprocess.run([rodend_path(), sub, "--help"], capture_output=True, text=True,
                              timeout=120).stdout
    return out


def check_issue_mentions(repo):
    check(issue_mentions(repo, "see issue 12") != [] and
          issue_mentions(repo, "the issue's goal") != [], "the issue check finds nothing")
    found = issue_mentions(repo, help_texts())
    check(not found, "issue numbers in user-facing text (say what the software does instead):\n"
          + "\n".join(found))


def main():
    repo, build = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
    check_issue_mentions(repo)
    checker = Checker(repo, build)
    try:
        self_test(checker, repo)
        checker.commands = checker.paths = checker.links = 0
        files = [os.path.join(repo, "README.md")] + sorted(glob.glob(os.path.join(repo, "docs", "*.md")))
        anchors_of = make_anchors_of()
        problems = []
        for doc in files:
            with open(doc, encoding="utf-8") as f:
                found = checker.check_text(doc, f.read(), anchors_of)
            print(f"{os.path.relpath(doc, repo)}: {len(found)} problem(s)")
            problems += found
        found = checker.check_help_texts(anchors_of)
        print(f"rodend's help texts: {len(found)} problem(s)")
        problems += found
        check(not problems, f"{len(problems)} dangling paths, links or failing commands:\n"
                            + "\n".join(problems))
        check(checker.commands >= 20 and checker.paths >= 200 and checker.links >= 50,
              f"only {checker.commands} commands, {checker.paths} paths and {checker.links} "
              f"links checked: is the parser still finding them?")
        print(f"{len(files)} documents: {checker.paths} paths, {checker.links} links, "
              f"{checker.commands} commands checked")
    finally:
        checker.close()
    finish("doc_refs")


if __name__ == "__main__":
    main()
