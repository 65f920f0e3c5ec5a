#!/usr/bin/python3
"""Every repository path the docs name must exist.

Usage: check_paths.py SOURCE_DIR. Prints `FILE:LINE: names PATH, which does not exist` for each
broken one; exit 0 clean, 1 if any path is broken, 2 on bad usage.

What counts as a path: a token that starts with one of the tree's top-level folders (those that
hold a file of the repository, and the fixed list TOP_FOLDERS, so that a folder removed whole is
still recognised) followed by `/`, not preceded by a character that continues a path or a word
(so build/tests/..., /tmp/docs/..., $DIR/scenarios/..., ../shared/... are not repository paths),
and made of path characters (letters, digits, `_ . - /` and the glob and placeholder signs). Each
such token must name a repository file or folder (`models/stats.h`, `.ci/run`, `scenarios/run`,
`tests/`); a glob (`*`, `?`, `[`) must match at least one repository file. `X.h/.cpp` is shorthand
for X.h and X.cpp; both must exist. Trailing sentence punctuation is not part of the path. A token
with a placeholder is skipped: `<dir>`, `${folder}`, `$VAR`, `{a,b}`, or a part after the first
spelt all in capitals without an extension (`tests/DIR/`). So prose must not join a top-level
folder's name to a word with `/` ("unit tests/benchmarks"), and an example of a user's own file
is written outside the tree's folders (`/tmp/...`, `my_scenarios/...`) or with a placeholder.

Which files: every tracked Markdown file (docs/*.md, README.md, every */README.md), where all such
paths are checked; and every other tracked text file, where the paths under docs/ are (a comment
citing a page). tests/docs/, whose self-tests spell out broken paths on purpose, is skipped.
Outside a git work tree every file but build trees and .git is read.
"""
import fnmatch
import os
import re
import subprocess
import sys

TOP_FOLDERS = [".ci", "models", "dpram", "uart82510", "pic8259", "camc_qi", "main_cpu", "comm_cpu",
               "scenarios", "tests", "docs", "scripts"]
PATH_CHARS = r"A-Za-z0-9_.\-/*?\[\]{}<>$"
SKIP_PREFIX = "tests/docs/"


def tracked_files(root):
    """The repository's files, relative to root: git's tracked files, or a walk outside git."""
    try:
        top = subprocess.run(["git", "rev-parse", "--show-toplevel"], cwd=root, capture_output=True,
                             text=True, check=False).stdout.strip()
    except OSError:
        top = ""
    if top and os.path.realpath(top) == os.path.realpath(root):
        out = subprocess.run(["git", "ls-files", "-z"], cwd=root, capture_output=True, check=True).stdout
        names = [n for n in out.decode("utf-8", "surrogateescape").split("\0") if n]
        return [n for n in names if os.path.lexists(os.path.join(root, n))]
    files = []
    for d, subdirs, names in os.walk(root):
        subdirs[:] = sorted(s for s in subdirs if s != ".git" and not s.startswith("build"))
        for n in names:
            files.append(os.path.relpath(os.path.join(d, n), root).replace(os.sep, "/"))
    return files


def candidate_re(tops):
    alternatives = "|".join(re.escape(t) for t in sorted(tops, key=len, reverse=True))
    return re.compile(r"(?<![A-Za-z0-9_.\-/$~])((?:%s)/[%s]*)" % (alternatives, PATH_CHARS))


def paths_named(token):
    """The paths a token names, to be checked ([] when it is not one to check)."""
    token = token.split("</", 1)[0]            # "docs/motion.md.</p>" in an HTML string
    token = token.rstrip(".")
    while token and token[-1] in "])}>" and token.count(token[-1]) > token.count({"]": "[", ")": "(", "}": "{", ">": "<"}[token[-1]]):
        token = token[:-1].rstrip(".")
    if re.search(r"[<>${}]", token):
        return []
    parts = token.rstrip("/").split("/")
    if any(re.fullmatch(r"[A-Z][A-Z0-9_]*", p) for p in parts[1:]):
        return []
    shorthand = re.fullmatch(r"(.*)\.(\w+)/\.(\w+)", token)
    if shorthand:
        return [shorthand.group(1) + "." + shorthand.group(2), shorthand.group(1) + "." + shorthand.group(3)]
    return [token]


def main(argv):
    if len(argv) != 2 or not os.path.isdir(argv[1]):
        print("usage: check_paths.py SOURCE_DIR (got %s)" % " ".join(repr(a) for a in argv[1:]), file=sys.stderr)
        return 2
    root = argv[1]
    files = tracked_files(root)
    file_set = set(files)
    dirs = set()
    for f in files:
        d = f
        while "/" in d:
            d = d.rsplit("/", 1)[0]
            dirs.add(d)
    tops = set(TOP_FOLDERS) | {f.split("/", 1)[0] for f in files if "/" in f}
    any_path = candidate_re(tops)
    docs_path = candidate_re(["docs"])

    def exists(path):
        if re.search(r"[*?\[]", path):
            return any(fnmatch.fnmatchcase(f, path) or fnmatch.fnmatchcase(f, path.rstrip("/") + "/*")
                       for f in files)
        if path.endswith("/"):
            return path.rstrip("/") in dirs
        return path in file_set or path in dirs

    bad = 0
    for name in sorted(files):
        if name.startswith(SKIP_PREFIX):
            continue
        pattern = any_path if name.endswith(".md") else docs_path
        try:
            with open(os.path.join(root, name), "rb") as f:
                data = f.read()
        except OSError:
            continue
        if b"\0" in data[:8192]:
            continue
        if pattern is docs_path and b"docs/" not in data:
            continue
        for number, line in enumerate(data.decode("utf-8", "replace").split("\n"), 1):
            for match in pattern.finditer(line):
                for path in paths_named(match.group(1)):
                    if not exists(path):
                        print("%s:%d: names %s, which does not exist" % (name, number, path))
                        bad = 1
    return bad


if __name__ == "__main__":
    sys.exit(main(sys.argv))
