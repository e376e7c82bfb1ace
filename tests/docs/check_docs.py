#!/usr/bin/env python3
"""The documentation true to the code (issue 59, item 5): every page (README.md, docs/*.md and
the README.md of each folder under src/) is read, and each of the following it names must exist:

- a repository path, in backticks or as a link: a word starting with src/, tests/, scripts/,
  docs/, studies/, examples/, bench/, tools/, fuzz/, cmake/ or .ci/ inside an inline code span
  (commands included: `bash scripts/x.sh`), one starting with dem/, scene/, vpp/, cli/ or python/
  (a source path as the includes spell it, under src/), a `../` path that leaves the page's
  folder, and the target of a Markdown link relative to the page (`[text](studies.md)`,
  `(../src/dem)`); a placeholder part (`<study>`, `$OUT`, `NAME`, `...`) ends the path at the
  folder before it, a glob (`*`) or braces (`{a,b}`) must match something, a name without an
  extension stands for its files (`dem/detect/broad_phase`: .h and .cpp);
- a code identifier in backticks: `Class::member` (the two last parts must occur as words in one
  file under src/), `function()` (the name must occur as a word under src/; `obj.method()` and
  `A::f()` by their last part, and the `::` rule too), "`Class`'s `member`" (as `Class::member`),
  a lone CamelCase name of two humps or more (`DamperRun`) or a name with a trailing underscore
  (`top_ring_`: private data) (a word under src/ or tests/, where fixtures live, or a ctest name);
- a test in backticks, `Suite.Name`: a gtest TEST(Suite, Name) under tests/ or a ctest name that
  CMakeLists.txt adds.

Deliberate exceptions are in ALLOWED below, each with its reason. Fenced code blocks are left out
(their commands and code are examples, not references). Exit 1 with one line per finding,
`page:line: ...`; 0 when the pages are clean.

usage: check_docs.py ROOT            check the repository at ROOT
       check_docs.py --self-test DIR  show that the check fails on a page naming a missing path and
                                       a missing identifier (and passes without them), in DIR
Run by ctest as Docs.PathsAndIdentifiersExist and Docs.CheckRefusesADeadReference.
"""
import glob
import os
import re
import sys

PREFIXES = ("src", "tests", "scripts", "docs", "studies", "examples", "bench", "tools", "fuzz", "cmake", ".ci")

# (page, the reference as written) -> why it may name something that does not exist. Keep it small:
# a page that can say it truly should.
ALLOWED = {
    ("docs/studies.md", "docs/data/paper_velocity_cycle1.csv"):
        "the table scripts/trust_studies.sh paper_velocity publishes; that part has not run, and the page says so",
}

# A path word inside a code span: one of the prefixes at a word start, up to a space, quote or
# closing bracket.
PATH_RE = re.compile(r"(?<![\w./$-])((?:%s)/[^\s`'\",;()\[\]]*)" % "|".join(re.escape(p) for p in PREFIXES))
# A source path as the includes spell it, relative to src/ (`dem/core/pressure.h`, `vpp/study/`).
SRC_PATH_RE = re.compile(r"(?<![\w./$-])((?:dem|scene|vpp|cli|python)/[^\s`'\",;()\[\]]*)")
LINK_RE = re.compile(r"\[(?:[^\]\\]|\\.)*\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)")
# `A::b` (any depth) and `name()` / `a.b()` / `A::b()`.
SCOPED_RE = re.compile(r"(?<![\w:])([A-Za-z_]\w*(?:::~?[A-Za-z_]\w*)+)")
CALL_RE = re.compile(r"(?<![\w.:])((?:[A-Za-z_]\w*(?:::|\.))*[A-Za-z_]\w*)\(\)")
WORD_RE = re.compile(r"[A-Za-z_]\w*")
# A path part that stands for a value: <study>, $OUT, ${X}, ..., NAME (upper case, when no such
# file exists), and a part with a glob or braces (matched by glob below).
PLACEHOLDER_RE = re.compile(r"[<>$]|\.\.\.|…|(?:^|[_.-])[A-Z][A-Z0-9]*[A-Z](?=$|[_.-])|(?:^|[_.-])[A-Z](?=$|[_.-])")
# `Suite.Name`: a test (gtest's TEST(Suite, Name) under tests/, or a ctest name in CMakeLists.txt).
TEST_RE = re.compile(r"^([A-Z]\w*)\.([A-Z]\w*)$")
# A lone identifier in a span that can only be code: CamelCase with two humps or more
# (`DamperRun`), or a member with the trailing underscore of private data (`top_ring_`).
CAMEL_RE = re.compile(r"^[A-Z][a-z0-9]+(?:[A-Z][a-z0-9]*)+$")
MEMBER_RE = re.compile(r"^[a-z_]\w*_$")
# "`Owner`'s `a`, `b`": members of Owner.
OWNED_RE = re.compile(r"`([A-Z]\w*)`'s ((?:`[A-Za-z_]\w*(?:\(\))?`(?:, | and | or )?)+)")
EXTERNAL_NAMESPACES = {"std", "CLI", "toml", "nlohmann", "hwy", "testing", "pybind11", "py", "benchmark", "np",
                       "numpy", "plt", "matplotlib", "math", "os", "sys", "subprocess", "scipy", "json"}


def pages(root):
    out = [os.path.join(root, "README.md")] if os.path.isfile(os.path.join(root, "README.md")) else []
    out += sorted(glob.glob(os.path.join(root, "docs", "*.md")))
    out += sorted(glob.glob(os.path.join(root, "src", "**", "README.md"), recursive=True))
    return out


def source_words(root, folder="src"):
    """Per file under ROOT/folder, the set of its words; and the union."""
    files = []
    for dirpath, _, names in os.walk(os.path.join(root, folder)):
        if "__pycache__" in dirpath:
            continue
        for n in names:
            if n.endswith((".h", ".cpp", ".cu", ".cuh", ".inl", ".py", ".cmake", ".txt")):
                with open(os.path.join(dirpath, n), encoding="utf-8", errors="replace") as f:
                    files.append(set(WORD_RE.findall(f.read())))
    union = set().union(*files) if files else set()
    return files, union


def spans(text):
    """(line number, code span text) of every inline code span outside fenced blocks, and
    (line number, line) of every line outside them (for the links)."""
    code, lines = [], []
    fence = None
    para, para_line = [], 0
    for n, line in enumerate(text.splitlines(), 1):
        m = re.match(r"^\s*(```+|~~~+)", line)
        if m:
            if fence is None:
                fence = m.group(1)[0] * 3
            elif line.strip().startswith(fence):
                fence = None
            continue
        if fence is not None:
            continue
        lines.append((n, line))
        # A span may run over a line break: lines are joined until the backticks pair up.
        if not para:
            para_line = n
        para.append(line)
        joined = "\n".join(para)
        if joined.count("`") % 2 and len(para) < 8:
            continue
        for m in re.finditer(r"(`+)(.+?)\1", joined, re.S):
            code.append((para_line + joined[:m.start()].count("\n"), m.group(2).strip()))
        para = []
    return code, lines


def expand_braces(p):
    m = re.search(r"\{([^{}]*)\}", p)
    if not m:
        return [p]
    return [q for alt in m.group(1).split(",") for q in expand_braces(p[:m.start()] + alt + p[m.end():])]


def path_exists(root, rel):
    """Whether the repository path `rel` (as written in a page, relative to ROOT) exists, a
    placeholder part ending it at the folder before."""
    rel = re.sub(r":\d+(?:-\d+)?$", "", rel)  # file:line
    rel = rel.split("#")[0].rstrip(".:")
    if not rel:
        return True
    for alt in expand_braces(rel):
        if not one_path_exists(root, alt):
            return False
    return True


def one_path_exists(root, rel):
    full = os.path.join(root, rel)
    if os.path.exists(full):
        return True
    if "." not in os.path.basename(rel.rstrip("/")) and glob.glob(glob.escape(full) + ".*"):
        return True  # a source file by its stem: dem/detect/broad_phase (.h and .cpp)
    if any(c in rel for c in "*?["):
        return bool(glob.glob(full))
    parts = rel.rstrip("/").split("/")
    for k, part in enumerate(parts):
        if PLACEHOLDER_RE.search(part):
            return os.path.isdir(os.path.join(root, *parts[:k])) if k else True
    return False


def test_names(root):
    """Every gtest TEST(Suite, Name) under tests/ as "Suite.Name", and the ctest names that
    CMakeLists.txt adds."""
    names = set()
    for dirpath, _, files in os.walk(os.path.join(root, "tests")):
        for n in files:
            if n.endswith((".cpp", ".h", ".cu")):
                with open(os.path.join(dirpath, n), encoding="utf-8", errors="replace") as f:
                    for m in re.finditer(r"\bTEST(?:_F|_P)?\(\s*(\w+)\s*,\s*(\w+)\s*\)", f.read()):
                        names.add(m.group(1) + "." + m.group(2))
    cm = os.path.join(root, "CMakeLists.txt")
    if os.path.isfile(cm):
        with open(cm, encoding="utf-8") as f:
            text = f.read()
        names |= set(re.findall(r"add_test\(\s*NAME\s+([\w.]+)", text))
        names |= set(re.findall(r"\"([A-Z]\w*\.[A-Z]\w*)\"", text))  # the grouped long tests' entries
    return names


def check(root):
    files, words = source_words(root)
    test_words = source_words(root, "tests")[1]
    tests = test_names(root)
    findings = []
    for page in pages(root):
        rel_page = os.path.relpath(page, root)
        with open(page, encoding="utf-8") as f:
            code, lines = spans(f.read())

        def flag(n, what, ref):
            if (rel_page, ref) not in ALLOWED:
                findings.append(f"{rel_page}:{n}: {what}")

        def owned(n, owner, member, ref):
            if not any(owner in w and member in w for w in files):
                flag(n, f"identifier '{ref}': no file under src/ names both '{owner}' and '{member}'", ref)

        for n, s in code:
            for m in PATH_RE.finditer(s):
                p = m.group(1)
                if not path_exists(root, p):
                    flag(n, f"path '{p}' does not exist", p)
            for m in SRC_PATH_RE.finditer(s):
                p = m.group(1)
                if not path_exists(os.path.join(root, "src"), p):
                    flag(n, f"path '{p}' does not exist under src/", p)
            for m in re.finditer(r"(?<![\w./-])(\.\./[^\s`'\",;()]*)", s):
                full = os.path.normpath(os.path.join(os.path.dirname(page), m.group(1)))
                if os.path.relpath(full, root).startswith(".."):
                    flag(n, f"path '{m.group(1)}' points outside the repository", m.group(1))
                elif not os.path.exists(full):
                    flag(n, f"path '{m.group(1)}' (from {os.path.dirname(rel_page) or '.'}/) does not exist", m.group(1))
            for m in SCOPED_RE.finditer(s):
                parts = m.group(1).replace("~", "").split("::")
                if parts[0] not in EXTERNAL_NAMESPACES:
                    owned(n, parts[-2], parts[-1], m.group(1))
            for m in CALL_RE.finditer(s):
                name = m.group(1)
                first, last = re.split(r"::|\.", name)[0], re.split(r"::|\.", name)[-1]
                if first not in EXTERNAL_NAMESPACES and last not in words:
                    flag(n, f"function '{name}()': '{last}' does not occur under src/", name + "()")
            if TEST_RE.match(s) and s not in tests:
                flag(n, f"test '{s}': no TEST({s.replace('.', ', ')}) under tests/ nor ctest entry", s)
            if (CAMEL_RE.match(s) or MEMBER_RE.match(s)) and not ({s} & (words | test_words | tests)):
                flag(n, f"identifier '{s}' does not occur under src/ or tests/", s)
        for n, line in lines:
            for m in OWNED_RE.finditer(line):
                for member in re.findall(r"`([A-Za-z_]\w*)(?:\(\))?`", m.group(2)):
                    owned(n, m.group(1), member, f"{m.group(1)}'s {member}")
            for m in LINK_RE.finditer(line):
                target = m.group(1)
                if re.match(r"^[a-z][a-z0-9+.-]*:", target) or target.startswith("#"):
                    continue  # a URL, a mail address, an anchor of this page
                path = target.split("#")[0]
                full = os.path.normpath(os.path.join(os.path.dirname(page), path))
                if not os.path.relpath(full, root).startswith(".."):
                    if not os.path.exists(full):
                        flag(n, f"link '{target}' does not exist", target)
                else:
                    flag(n, f"link '{target}' points outside the repository", target)
    return findings


def self_test(work):
    """A repository of two files and two pages: clean, it passes; with a page naming a missing
    path and a missing identifier, it fails and names both with their lines."""
    import shutil
    import subprocess
    shutil.rmtree(work, ignore_errors=True)

    def write(rel, text):
        os.makedirs(os.path.dirname(os.path.join(work, rel)), exist_ok=True)
        with open(os.path.join(work, rel), "w") as f:
            f.write(text)

    write("src/dem/world.h", "struct World {\n    void step();\n    double time = 0;\n    int ring_ = 0;\n};\n"
                             "struct WorldRun {};\nvoid reset_energy();\n")
    write("tests/test_world.cpp", "TEST(World, Steps) {}\n")
    write("scripts/run.sh", "#!/bin/sh\n")
    write("README.md", "# x\n\nRun `bash scripts/run.sh`; see [the model](docs/model.md).\n")
    write("docs/model.md", "# model\n\n`World::step()` advances `World::time`; `reset_energy()` starts over "
                           "(`src/dem/world.h`, `dem/world.h`, `docs/<name>.md`, [back](../README.md)).\n"
                           "`WorldRun`, `World`'s `ring_`; test `World.Steps`.\n\n"
                           "```\nbash scripts/gone.sh   # fenced: an example, not checked\n```\n")

    def run():
        r = subprocess.run([sys.executable, os.path.abspath(__file__), work], capture_output=True, text=True)
        return r.returncode, r.stdout + r.stderr

    rc, out = run()
    if rc != 0:
        sys.exit(f"self-test: a clean tree was refused:\n{out}")
    write("docs/bad.md", "# bad\n\nIt runs `bash scripts/removed.sh`.\n\n"
                         "The step calls `World::advance` and `gone_helper()`; "
                         "see [there](missing.md) and [out](../../elsewhere/x.md).\n"
                         "`GoneRun`'s `top_`, in `dem/gone.h` (`../../shared/x.md`); test `World.StepsBack`.\n")
    rc, out = run()
    want = ["docs/bad.md:3: path 'scripts/removed.sh' does not exist",
            "docs/bad.md:5: identifier 'World::advance'",
            "docs/bad.md:5: function 'gone_helper()'",
            "docs/bad.md:5: link 'missing.md' does not exist",
            "docs/bad.md:5: link '../../elsewhere/x.md' points outside the repository",
            "docs/bad.md:6: identifier 'GoneRun' does not occur",
            "docs/bad.md:6: identifier 'top_' does not occur",
            "docs/bad.md:6: identifier 'GoneRun's top_'",
            "docs/bad.md:6: path 'dem/gone.h' does not exist under src/",
            "docs/bad.md:6: path '../../shared/x.md' points outside the repository",
            "docs/bad.md:6: test 'World.StepsBack'"]
    missing = [w for w in want if w not in out]
    if rc == 0 or missing:
        sys.exit(f"self-test: the bad page was not refused as expected (exit {rc}; not named: {missing}):\n{out}")
    if "docs/model.md" in out or "README.md:" in out:
        sys.exit(f"self-test: a clean page was flagged:\n{out}")
    print(f"self-test: the clean pages pass; the bad page's {len(want)} dead references are named")


def main(argv):
    if len(argv) == 3 and argv[1] == "--self-test":
        self_test(argv[2])
        return 0
    if len(argv) != 2:
        sys.exit(__doc__)
    findings = check(argv[1])
    for f in findings:
        print(f)
    if findings:
        print(f"check_docs: {len(findings)} dead reference(s) (fix the page, or add a reasoned entry to "
              f"ALLOWED in tests/docs/check_docs.py)", file=sys.stderr)
        return 1
    print(f"check_docs: {len(pages(argv[1]))} pages, every path and identifier found")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
