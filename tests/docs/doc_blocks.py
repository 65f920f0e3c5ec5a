#!/usr/bin/python3
"""Docs that run: the command blocks of a Markdown page, run against the build, and the output the
page quotes, checked (docs/regression.md "Docs that run").

Usage: doc_blocks.py SOURCE_DIR BUILD_DIR PAGE.md [PAGE.md ...]

A block is a fenced block (```) or an indented one (four spaces, after a blank line). Every fenced
block without a language and every indented block must say what it is, in an HTML comment on the
nearest line before it that is not blank:

  <!-- doc-test: run -->              each command line runs (bash, a line ending in \\ joins the
                                      next) and must exit 0;
  <!-- doc-test: run exits=0,0,1 -->  ... with these exit codes, one per command;
  <!-- doc-test: output -->           the block's lines, up to a line `...`, are the first lines
                                      the last command of the run block before it printed
                                      (trailing spaces aside);
  <!-- doc-test: synopsis -->         a usage line with placeholders: `rcsim CMD --help` must work;
  <!-- doc-test: skip REASON -->      not run, for the reason given (which must not be empty).

A fenced block with a language (```yaml, ```json) is an example and is not run. A block without a
comment is an error naming the page and line, so a page cannot grow a command nobody runs.

The commands run as a user would type them at the top of a clone, in a scratch folder that looks
like one: the source tree's folders are linked in, and `build/` holds links to the build's
programs and ROMs (rcsim, comm_fw*.rom/.json, tests/) beside fresh room for what the commands
write. `rcsim` alone is build/rcsim. A `cmake --build build ...` line is not run: the tests run
after the build, which made every target. Exit 0 when every block holds; 1 naming each that does
not.
"""
import os
import re
import shutil
import subprocess
import sys
import tempfile

ANNOTATION = re.compile(r"^<!--\s*doc-test:\s*(\w+)\s*(.*?)\s*-->\s*$")
BUILD_PRODUCTS = ["rcsim", "comm_fw.rom", "comm_fw.json", "comm_fw.map", "comm_fw_c.rom", "comm_fw_c.json", "tests"]
TIMEOUT_S = 300


def blocks(path):
    """Yields (line number, kind, language, lines, annotation line) for each block of the page."""
    with open(path, encoding="utf-8") as f:
        text = f.read().split("\n")
    i = 0
    while i < len(text):
        line = text[i]
        if line.startswith("```"):
            language = line[3:].strip()
            start = i
            i += 1
            body = []
            while i < len(text) and not text[i].startswith("```"):
                body.append(text[i])
                i += 1
            i += 1
            yield start + 1, "fenced", language, body, annotation_before(text, start)
            continue
        if line.startswith("    ") and line.strip() and (i == 0 or not text[i - 1].strip()):
            start = i
            body = []
            while i < len(text) and (text[i].startswith("    ") or not text[i].strip()):
                body.append(text[i][4:])
                i += 1
            while body and not body[-1].strip():
                body.pop()
            yield start + 1, "indented", "", body, annotation_before(text, start)
            continue
        i += 1


def annotation_before(text, start):
    j = start - 1
    while j >= 0 and not text[j].strip():
        j -= 1
    if j < 0:
        return None
    m = ANNOTATION.match(text[j].strip())
    return (m.group(1), m.group(2)) if m else None


def commands(body):
    """The block's command lines, continuations joined; comments after # stay (bash ignores them)."""
    out, pending = [], ""
    for line in body:
        if not line.strip():
            continue
        if line.rstrip().endswith("\\"):
            pending += line.rstrip()[:-1] + " "
            continue
        out.append((pending + line).strip())
        pending = ""
    return out


def scratch_clone(source, build):
    """A folder that looks like the top of a clone with its build (module docstring)."""
    w = tempfile.mkdtemp(prefix="rcsim_doc_blocks.")
    for entry in os.listdir(source):
        if entry not in ("build", ".git"):
            os.symlink(os.path.join(source, entry), os.path.join(w, entry))
    os.mkdir(os.path.join(w, "build"))
    for product in BUILD_PRODUCTS:
        if os.path.exists(os.path.join(build, product)):
            os.symlink(os.path.join(build, product), os.path.join(w, "build", product))
    os.mkdir(os.path.join(w, "bin"))
    os.symlink(os.path.join(build, "rcsim"), os.path.join(w, "bin", "rcsim"))
    return w


def run(command, cwd):
    env = dict(os.environ, PATH=os.path.join(cwd, "bin") + os.pathsep + os.environ.get("PATH", ""))
    try:
        p = subprocess.run(["bash", "-c", command], cwd=cwd, env=env, capture_output=True, text=True,
                           timeout=TIMEOUT_S)
        return p.returncode, p.stdout, p.stderr
    except subprocess.TimeoutExpired:
        return None, "", "timed out after %d s" % TIMEOUT_S


def check_page(page, w, failures):
    name = os.path.basename(page)
    last_output = None  # stdout of the last command of the last run block
    for line, kind, language, body, note in blocks(page):
        where = "%s:%d" % (name, line)
        if kind == "fenced" and language:
            continue
        if note is None:
            failures.append(where + ": %s block without <!-- doc-test: ... -->" %
                            ("an indented" if kind == "indented" else "a fenced"))
            continue
        what, args = note
        if what == "skip":
            if not args:
                failures.append(where + ": doc-test skip without a reason")
            continue
        if what == "synopsis":
            for c in commands(body):
                words = c.split()
                sub = words[1] if words[0] == "rcsim" and len(words) > 1 else None
                if not sub:
                    failures.append(where + ": a synopsis that is not `rcsim COMMAND ...`: " + c)
                    continue
                code, out, err = run("rcsim %s --help" % sub, w)
                if code != 0:
                    failures.append(where + ": `rcsim %s --help` exits %s" % (sub, code))
            continue
        if what == "output":
            if last_output is None:
                failures.append(where + ": an output block with no run block before it")
                continue
            check_output(where, body, last_output, failures)
            continue
        if what != "run":
            failures.append(where + ": unknown doc-test kind '%s'" % what)
            continue
        run_block(where, body, args, w, failures)
        last_output = run_block.last_stdout


def run_block(where, body, args, w, failures):
    cmds = [c for c in commands(body) if not c.startswith("cmake --build build")]
    exits = [0] * len(cmds)
    m = re.match(r"exits=([\d,]+)$", args)
    if m:
        exits = [int(x) for x in m.group(1).split(",")]
    elif args:
        failures.append(where + ": doc-test run: unknown arguments '%s'" % args)
        return
    if len(exits) != len(cmds):
        failures.append(where + ": exits= names %d codes for %d commands" % (len(exits), len(cmds)))
        return
    run_block.last_stdout = ""
    for c, want in zip(cmds, exits):
        code, out, err = run(c, w)
        run_block.last_stdout = out
        print("%s: $ %s  -> exit %s" % (where, c, code))
        if code != want:
            failures.append("%s: `%s` exits %s, the page says %d\n%s%s" % (where, c, code, want, out[-2000:], err[-2000:]))
            return


run_block.last_stdout = ""


def check_output(where, body, actual, failures):
    want = []
    for line in body:
        if line.strip() == "...":
            break
        want.append(line.rstrip())
    got = [line.rstrip() for line in actual.split("\n")]
    for n, line in enumerate(want):
        if n >= len(got) or got[n] != line:
            failures.append("%s: output line %d: the page quotes\n  %r\nthe command printed\n  %r" %
                            (where, n + 1, line, got[n] if n < len(got) else "(nothing)"))
            return


def main():
    if len(sys.argv) < 4:
        sys.exit("usage: doc_blocks.py SOURCE_DIR BUILD_DIR PAGE.md [PAGE.md ...]")
    source, build, pages = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2]), sys.argv[3:]
    w = scratch_clone(source, build)
    failures = []
    try:
        for page in pages:
            check_page(os.path.join(source, page), w, failures)
    finally:
        shutil.rmtree(w, ignore_errors=True)
    for f in failures:
        print("FAIL: " + f)
    print("doc blocks: %d failure(s) in %s" % (len(failures), ", ".join(pages)))
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
