#!/usr/bin/env python3
"""Docs that cannot drift: README.md and docs/*.md checked against the repository and the tool.

    check_docs.py commands --repo ROOT --crex CREX --work DIR    (Docs.EveryCommandInTheDocsRuns)
    check_docs.py python --repo ROOT --python-path DIR --work DIR (Docs.PythonExamplesRun)
    check_docs.py files --repo ROOT                               (Docs.QuotedFilesAreTheRepoFiles)

Python 3, standard library only. Every failure names the doc, its line, and what is wrong.

Which lines are commands (fenced code blocks only; inline spans are described further down):
  ```console   lines starting with "$ " are commands; the lines after one, up to the next "$ ",
               are its shown output.
  ```sh/bash   every line that is neither blank nor a comment.
  ``` (plain)  lines whose program is crex (or a path ending in /crex), python3, bash, mpirun or time;
               the block's other lines are text (grammars, printed output).
  A line ending in a backslash continues on the next.

Markers, as a command's trailing shell comment (a reader sees them; the shell ignores them):
  # long[: why]      too slow for CI: only its help is run (`crex SUB --help`, `python3 SCRIPT
                     --help`), which must exit 0 and list every flag the command uses.
  # not-run: why     needs what CI does not have (mpirun, an installed prefix, a machine's
                     packages): not run, listed as skipped with why.
  A command with an elided argument (a word "...") is not run either, listed as "elided".
  Any other comment is a description. crex commands that are not run still have their
  subcommand and flags checked against `crex SUB --help`.

How commands run (`commands`): a doc's commands run in doc order, each by bash, in a scratch
folder of that doc (the repo's top-level entries linked in, an empty out/ as a clone has after
`tools/dev.sh demo`, no build tree but build/release/apps/crex/crex), with CREX_CACHE inside it.
`crex` on PATH and build/release/apps/crex/crex are a wrapper that makes each render tiny with
one fixed rule, tiny() below; so "$(crex reference -q)" and --reference auto agree on the size.
Exit status expected: 1 when the command's shown output has an error (error[...] or, in JSON,
"errors": N > 0), else 0.
Shown output must appear in the real output (stdout and stderr), in order: a shown line "..." is
a gap, "..." inside a line matches anything. Some commands cannot run unmarked, and the test
fails until they are marked: mpirun, tools/dev.sh, a program under an installed prefix (/opt),
and python3 scripts (no tiny size for them) other than those that use the Python module
(PYTHONPATH=..., `import crex`), which `python` runs. A block that holds a pipeline
(`pipeline NAME ...`) and is not a quoted file is written to the scratch folder and checked
with `crex check`: no error, no warning.

Inline spans (`crex SUB --flag ...` in the text) are checked as commands that are not run: SUB
must be a subcommand and every flag must be in its help; `python3 bench/...py --flag` likewise.

`python`: the commands that use the Python module, then each doc's ```python blocks in doc order
as one script (a block whose first line is "# not-run: why" is skipped), with PYTHONPATH set.

`files`:
  * every link [text](target) (not http/https/mailto) resolves to a file of the repo (and a
    #anchor to a heading of that doc);
  * every path the text names under a top-level folder of the repo (examples/..., stdlib/...,
    docs/..., runtime/..., ...) exists (a glob must match; a module without its extension,
    runtime/driver/run_plan, is its .h/.cpp; a path with a placeholder part in capitals, like
    stdlib/pipelines/NAME.pipe, is not checked);
  * nothing points outside the clone: no ../ leaving the repo, no shared/spec, spec/*.md or
    "spec §" (the docs say it in their own words);
  * a quoted file is the file: a fenced block right after a line ending in "`PATH` in full:" is
    PATH byte for byte; one after a line ending in "from `PATH`:" is a run of PATH's lines.
"""
import argparse
import difflib
import glob
import json
import os
import re
import shlex
import shutil
import subprocess
import sys
import time

# ---------------------------------------------------------------------------------------------
# The tiny rule: what the wrapper does to every crex command line before running it.
TINY_SIZE = "32x24"        # --size of run and reference, set or appended
TINY_SPP = 4               # --spp capped at 4 (reference: appended when absent; its default is 1024)
TINY_FRAMES = 3            # --frames A..B[:S] keeps its first 3 frames
# run only, capped or appended (they cost nothing without an irradiance cache): the cache's
# hemisphere rays per record and its caustic photons, whose defaults (256, 200000) cost seconds
# even at 32x24.
TINY_RUN_CAPS = {"--ad": 32, "--caustic-photons": 20000}
RENDERING = ("run", "reference")


def tiny(args):
    """The crex arguments a doc command runs with in CI (see TINY_* above)."""
    if not args or args[0] not in RENDERING or "--help" in args or "-h" in args:
        return list(args)
    out, seen = [], set()
    i = 0
    while i < len(args):
        a = args[i]
        name, eq, val = a.partition("=")
        capped = TINY_RUN_CAPS if args[0] == "run" else {}
        flag = name if name in ("--size", "--spp", "--frames") or name in capped else None
        if flag and not eq and i + 1 < len(args):
            val, i = args[i + 1], i + 1
        if flag == "--size":
            val = TINY_SIZE
        elif flag == "--spp":
            val = str(min(int(val), TINY_SPP)) if val.isdigit() else val
        elif flag in capped:
            val = str(min(int(val), capped[flag])) if val.isdigit() else val
        elif flag == "--frames":
            m = re.fullmatch(r"(\d+)\.\.(\d+)(?::(\d+))?", val)
            if m:
                first, last, step = int(m.group(1)), int(m.group(2)), int(m.group(3) or 1)
                val = f"{first}..{min(last, first + step * (TINY_FRAMES - 1))}" + (f":{step}" if m.group(3) else "")
        if flag:
            seen.add(flag)
            out += [flag, val]
        else:
            out.append(a)
        i += 1
    if "--size" not in seen:
        out += ["--size", TINY_SIZE]
    if args[0] == "reference" and "--spp" not in seen:
        out += ["--spp", str(TINY_SPP)]
    if args[0] == "run":
        for flag, cap in TINY_RUN_CAPS.items():
            if flag not in seen:
                out += [flag, str(cap)]
    return out


# ---------------------------------------------------------------------------------------------
# Reading the docs.
SUBCOMMANDS = ("check", "plan", "run", "compare", "reference", "scene-info", "help")
FENCE = re.compile(r"^(\s*)(`{3,}|~{3,})\s*([\w+-]*)")


def doc_files(repo):
    return ["README.md"] + sorted(os.path.relpath(p, repo) for p in glob.glob(os.path.join(repo, "docs", "*.md")))


class Block:
    def __init__(self, doc, line, lang, caption):
        self.doc, self.line, self.lang, self.caption = doc, line, lang, caption
        self.lines = []  # (line number, text)


def read_doc(repo, doc):
    """Returns (lines, blocks, text_lines): text_lines are the (number, text) outside fences."""
    with open(os.path.join(repo, doc), encoding="utf-8") as f:
        lines = f.read().split("\n")
    blocks, text, block, fence, indent = [], [], None, None, 0
    last_text = ""
    for n, line in enumerate(lines, 1):
        m = FENCE.match(line)
        if block is None:
            if m:
                fence, indent = m.group(2), len(m.group(1))
                block = Block(doc, n, m.group(3).lower(), last_text)
            else:
                text.append((n, line))
                if line.strip():
                    last_text = line.strip()
        elif m and m.group(2).startswith(fence) and not m.group(3) and line.strip() == m.group(2):
            blocks.append(block)
            block, last_text = None, ""
        else:
            block.lines.append((n, line[indent:] if line[:indent].strip() == "" else line))
    return lines, blocks, text


def split_comment(line):
    """(command, comment) of a shell line: the comment starts at a '#' outside quotes after a blank."""
    quote, prev, i = None, " ", 0
    while i < len(line):
        c = line[i]
        if quote:
            if c == quote:
                quote = None
            elif c == "\\" and quote == '"':
                i += 1
        elif c in "'\"":
            quote = c
        elif c == "\\":
            i += 1
        elif c == "#" and prev in " \t":
            return line[:i].rstrip(), line[i + 1:].strip()
        prev = c
        i += 1
    return line.rstrip(), ""


class Command:
    def __init__(self, doc, line, text, comment):
        self.doc, self.line, self.text, self.comment = doc, line, text, comment
        self.shown = []  # output lines a console block shows after it
        self.mode, self.why = "run", ""
        c = comment.lower()
        if c == "long" or c.startswith("long:") or c.startswith("long "):
            self.mode, self.why = "long", comment[4:].lstrip(" :")
        elif c.startswith("not-run"):
            self.mode, self.why = "skip", comment[7:].lstrip(" :") or "(no reason given)"
        try:
            self.words = shlex.split(text)
        except ValueError:
            self.words = text.split()
        if self.mode == "run" and "..." in self.words:
            self.mode, self.why = "skip", "elided (...)"

    def where(self):
        return f"{self.doc}:{self.line}"

    def program(self):
        """(index of the program word, the program) past VAR=value prefixes and time/mpirun wrappers."""
        for i, w in enumerate(self.words):
            if re.fullmatch(r"[A-Za-z_]\w*=.*", w):
                continue
            return i, w
        return len(self.words), ""

    def crex_args(self):
        """The arguments after the crex program word (under mpirun or time too), or None."""
        for i, w in enumerate(self.words):
            if w == "crex" or w.endswith("/crex"):
                return self.words[i + 1:]
        return None

    def uses_python_module(self):
        _, prog = self.program()
        return bool(re.search(r"(^|/)python3?$", prog)) and ("PYTHONPATH=" in self.text or "import crex" in self.text)


def is_command_line(lang, line):
    words = line.split()
    if not words:
        return False
    prog = next((w for w in words if not re.fullmatch(r"[A-Za-z_]\w*=\S*", w)), "")
    if prog == "crex" or prog.endswith("/crex"):
        rest = words[words.index(prog) + 1:]
        return not rest or rest[0] in SUBCOMMANDS or rest[0].startswith("-")
    return prog in ("python3", "bash", "mpirun", "time", "/usr/bin/time") or prog.endswith("/python3")


def commands_of(blocks):
    cmds = []
    for b in blocks:
        if b.lang not in ("", "sh", "bash", "shell", "console"):
            continue
        pending, start, current = "", 0, None
        for n, line in b.lines:
            if b.lang == "console":
                if line.startswith("$ ") or pending:
                    body = line[2:] if not pending else line
                elif current is not None:
                    current.shown.append(line)
                    continue
                else:
                    continue
            else:
                body = line
                if not pending and (not body.strip() or body.lstrip().startswith("#")):
                    continue
                if not pending and b.lang == "" and not is_command_line("", body):
                    continue
            if not pending:
                start = n
            else:
                body = body.lstrip()  # a continuation's indent is layout, not an argument
            if body.rstrip().endswith("\\"):
                pending += body.rstrip()[:-1] + " "
                continue
            text, comment = split_comment(pending + body)
            pending = ""
            current = Command(b.doc, start, text.strip(), comment)
            cmds.append(current)
    return cmds


def inline_commands(doc, text_lines):
    """Inline spans `crex SUB ...` and `python3 bench/... --flag` of the text, as unrun commands."""
    out = []
    # Paragraphs, so that a span broken across lines is one span (said at the line it starts on).
    paragraphs, current, prev = [], [], None
    for n, line in text_lines:
        if not line.strip() or (prev is not None and n != prev + 1):
            if current:
                paragraphs.append(current)
            current = []
        if line.strip():
            current.append((n, line))
        prev = n
    if current:
        paragraphs.append(current)
    for para in paragraphs:
        text, starts = "", []
        for n, line in para:
            starts.append((len(text), n))
            text += line + " "
        for m in re.finditer(r"`([^`]+)`", text):
            n = max(ln for off, ln in starts if off <= m.start())
            span = " ".join(m.group(1).split())
            words = span.split()
            if len(words) >= 2 and words[0] == "crex" and re.fullmatch(r"[a-z][a-z-]*", words[1]) and \
                    not words[1].endswith(":") and (words[1] in SUBCOMMANDS or len(words) > 2 or words[1] in ("help",)):
                # `crex "..."` (a pipeline setting) and `crex run: ...` (a message) are not commands.
                c = Command(doc, n, span, "")
                c.mode, c.why = "inline", ""
                out.append(c)
            elif words and words[0] == "python3" and len(words) > 1 and words[1].endswith(".py"):
                c = Command(doc, n, span, "")
                c.mode = "inline"
                out.append(c)
    return out


# ---------------------------------------------------------------------------------------------
class Report:
    def __init__(self):
        self.failures = []

    def fail(self, where, message):
        self.failures.append(f"{where}: {message}")
        print(f"FAIL {where}: {message}", flush=True)

    def finish(self, what):
        if self.failures:
            print(f"\n{len(self.failures)} problem(s) in the docs ({what}):")
            for f in self.failures:
                print("  " + f.split("\n")[0])
            return 1
        print(f"\nthe docs hold ({what})")
        return 0


def tail(text, n=15):
    lines = text.rstrip("\n").split("\n")
    return "\n".join("      | " + l for l in lines[-n:])


def flags_of(words):
    out = []
    for w in words:
        w = w.strip("[](),")  # `crex plan FILE [--scene S]`
        if re.fullmatch(r"--?[A-Za-z][\w-]*(=.*)?", w):
            out.append(w.split("=")[0])
    return out


class Helps:
    """`crex SUB --help` and `python3 SCRIPT --help`, each run once."""

    def __init__(self, crex, repo):
        self.crex, self.repo, self.cache = crex, repo, {}

    def get(self, key, argv):
        if key not in self.cache:
            p = subprocess.run(argv, cwd=self.repo, capture_output=True, text=True, timeout=120)
            self.cache[key] = (p.returncode, p.stdout + p.stderr)
        return self.cache[key]

    def crex_help(self, sub):
        return self.get(("crex", sub), [self.crex, sub, "--help"])

    def script_help(self, script):
        return self.get(("py", script), [sys.executable, script, "--help"])


def flags_in_help(cmd, report, program, rc, text, words):
    """`program --help` exited 0 (`rc`, `text`) and names every flag among `words`."""
    if rc != 0:
        report.fail(cmd.where(), f"`{program} --help` exited {rc}\n{tail(text)}")
        return
    for f in flags_of(words):
        if not re.search(r"(?<![\w-])" + re.escape(f) + r"(?![\w-])", text):
            report.fail(cmd.where(), f"`{program}` has no flag {f} (not in `{program} --help`)\n    in: {cmd.text}")


def check_flags(cmd, helps, report):
    """The subcommand exists and every flag the command uses is in its help."""
    args = cmd.crex_args()
    if args is not None:
        if not args or args[0].startswith("-"):
            return  # `crex --help` and the like
        sub = args[0]
        if sub not in SUBCOMMANDS:
            report.fail(cmd.where(), f"`crex {sub}`: crex has no subcommand {sub!r} (it has {', '.join(SUBCOMMANDS)})\n    in: {cmd.text}")
            return
        rc, text = helps.crex_help(sub)
        flags_in_help(cmd, report, f"crex {sub}", rc, text, args[1:])
        return
    i, prog = cmd.program()
    if re.search(r"(^|/)python3$", prog) and i + 1 < len(cmd.words) and cmd.words[i + 1].endswith(".py"):
        script = cmd.words[i + 1]
        if not os.path.isfile(os.path.join(helps.repo, script)):
            report.fail(cmd.where(), f"{script} is not a file of the repo\n    in: {cmd.text}")
            return
        rc, text = helps.script_help(script)
        flags_in_help(cmd, report, f"python3 {script}", rc, text, cmd.words[i + 2:])


def shown_output_matches(shown, actual):
    """None when the shown lines appear in order in actual, else the first shown line missing."""
    lines = [l.rstrip() for l in actual.split("\n")]
    pos = 0
    for s in shown:
        s = s.rstrip()
        if not s.strip() or s.strip() == "...":
            continue
        pattern = re.compile("^" + ".*".join(re.escape(part) for part in s.split("...")) + "$")
        while pos < len(lines) and not pattern.match(lines[pos]):
            pos += 1
        if pos == len(lines):
            return s
        pos += 1
    return None


def make_scratch(repo, work, name, build_links):
    d = os.path.join(work, name)
    os.makedirs(d)
    for entry in os.listdir(repo):
        if entry in (".git", "build", "out") or entry.startswith("."):
            continue
        os.symlink(os.path.join(repo, entry), os.path.join(d, entry))
    os.makedirs(os.path.join(d, "out"))
    for rel, target in build_links.items():
        os.makedirs(os.path.dirname(os.path.join(d, rel)), exist_ok=True)
        os.symlink(target, os.path.join(d, rel))
    return d


def write_wrapper(work, crex):
    bindir = os.path.join(work, "bin")
    os.makedirs(bindir, exist_ok=True)
    wrapper = os.path.join(bindir, "crex")
    here = os.path.dirname(os.path.abspath(__file__))
    with open(wrapper, "w") as f:
        f.write(f"""#!{sys.executable}
# crex as the docs test runs it: every render made tiny (tests/docs/check_docs.py, tiny()).
import json, os, sys
sys.dont_write_bytecode = True  # nothing written into the source tree
sys.path.insert(0, {here!r})
from check_docs import tiny
args = tiny(sys.argv[1:])
log = os.environ.get("CREX_DOCS_LOG")
if log:
    with open(log, "a") as f:
        f.write(json.dumps(args) + "\\n")
os.execv({crex!r}, [{crex!r}] + args)
""")
    os.chmod(wrapper, 0o755)
    return bindir, wrapper


def must_be_marked(cmd):
    """Why a command cannot run unmarked in CI, or ''."""
    i, prog = cmd.program()
    if prog == "mpirun" or "mpirun" in cmd.words:
        return "mpirun"
    if prog == "bash" and any(w.endswith("dev.sh") for w in cmd.words):
        return "tools/dev.sh (installs packages, builds everything)"
    if re.search(r"(^|/)python3$", prog) and not cmd.uses_python_module():
        return "a python3 script (no tiny size for it)"
    if prog.startswith("/opt/") or prog.startswith("/usr/local/"):
        return "an installed prefix"
    return ""


def run_commands(args):
    repo = os.path.abspath(args.repo)
    crex = os.path.abspath(args.crex)
    work = os.path.abspath(args.work)
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    bindir, wrapper = write_wrapper(work, crex)
    helps = Helps(crex, repo)
    report = Report()
    ran, longs, skipped, elsewhere, inline = [], [], [], [], 0
    t0 = time.monotonic()
    for doc in doc_files(repo):
        _, blocks, text = read_doc(repo, doc)
        cmds = commands_of(blocks)
        for c in inline_commands(doc, text):
            check_flags(c, helps, report)
            inline += 1
        pipes = [b for b in blocks if b.lines and b.lines[0][1].startswith("pipeline ") and not quoted_path(b.caption)[0]]
        if not cmds and not pipes:
            continue
        scratch = make_scratch(repo, work, doc.replace("/", "_"), {"build/release/apps/crex/crex": wrapper})
        env = dict(os.environ, PATH=bindir + os.pathsep + os.environ.get("PATH", ""),
                   CREX_CACHE=os.path.join(scratch, ".cache"), CREX_DOCS_LOG=os.path.join(scratch, ".crex_log"))
        for b in pipes:
            path = os.path.join(scratch, f"doc_line{b.line}.pipe")
            with open(path, "w") as f:
                f.write("\n".join(l for _, l in b.lines) + "\n")
            start = time.monotonic()
            p = subprocess.run([crex, "check", path], cwd=scratch, capture_output=True, text=True, timeout=120)
            label = f"crex check <the pipeline of {doc}:{b.line}>"
            if p.returncode != 0 or "warning[" in p.stderr:
                report.fail(f"{doc}:{b.line}", f"the pipeline in this block does not check clean (exit {p.returncode})\n{tail(p.stderr)}")
            ran.append((f"{doc}:{b.line}", label, [], time.monotonic() - start))
        for c in cmds:
            if c.crex_args() is not None:
                check_flags(c, helps, report)
            if c.uses_python_module():
                elsewhere.append(c)
                continue
            if c.mode == "run":
                why = must_be_marked(c)
                if why:
                    report.fail(c.where(), f"{why}: mark it `# long` (help only) or `# not-run: why`\n    in: {c.text}")
                    continue
            if c.mode == "skip":
                skipped.append(c)
                continue
            if c.mode == "long":
                check_flags(c, helps, report)
                longs.append(c)
                continue
            open(env["CREX_DOCS_LOG"], "w").close()
            start = time.monotonic()
            try:
                p = subprocess.run(["bash", "-c", c.text], cwd=scratch, env=env, capture_output=True, text=True,
                                   timeout=args.timeout)
                rc, out, err = p.returncode, p.stdout, p.stderr
            except subprocess.TimeoutExpired as e:
                rc, out, err = "timeout", (e.stdout or b"").decode(errors="replace"), \
                    (e.stderr or b"").decode(errors="replace") + f"\n(killed after {args.timeout} s)"
            seconds = time.monotonic() - start
            with open(env["CREX_DOCS_LOG"]) as f:
                effective = ["crex " + shlex.join(json.loads(l)) for l in f if l.strip()]
            ran.append((c.where(), c.text, effective, seconds))
            expected = 1 if any("error[" in s or re.search(r'"errors": [1-9]', s) for s in c.shown) else 0
            if rc != expected:
                report.fail(c.where(), f"exit {rc} (expected {expected}): {c.text}\n"
                            + "".join(f"    ran as: {e}\n" for e in effective)
                            + f"    stderr (last lines):\n{tail(err or out)}")
                continue
            missing = shown_output_matches(c.shown, out + err)
            if missing is not None:
                report.fail(c.where(), f"the doc shows output the command does not print: {missing!r}\n    command: {c.text}\n"
                            f"    its output:\n{tail(out + err, 30)}")
    total = time.monotonic() - t0
    print(f"\n== {len(ran)} doc commands ran (each render at {TINY_SIZE}, spp <= {TINY_SPP}):")
    for where, text, effective, seconds in ran:
        print(f"RAN  {where}: {text}   [{seconds:.2f} s]")
        for e in effective:
            print(f"       as: {e}")
    print(f"\n== {len(longs)} long commands (their --help only):")
    for c in longs:
        print(f"LONG {c.where()}: {c.text}" + (f"   ({c.why})" if c.why else ""))
    print(f"\n== {len(skipped)} commands not run:")
    for c in skipped:
        print(f"SKIP {c.where()}: {c.text}   ({c.why})")
    print(f"\n== {len(elsewhere)} commands that use the Python module (Docs.PythonExamplesRun runs them):")
    for c in elsewhere:
        print(f"PY   {c.where()}: {c.text}")
    print(f"\n== {inline} commands quoted in the text (`crex SUB ...`): subcommand and flags checked against --help")
    print(f"\n{total:.1f} s in all")
    return report.finish("commands")


def run_python(args):
    repo = os.path.abspath(args.repo)
    work = os.path.abspath(args.work)
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    report = Report()
    env = dict(os.environ, PYTHONPATH=os.path.abspath(args.python_path), PYTHONDONTWRITEBYTECODE="1",
               CREX_CACHE=os.path.join(work, ".cache"))
    links = {"build/release/python": os.path.abspath(args.python_path)}
    t0 = time.monotonic()
    for doc in doc_files(repo):
        _, blocks, _ = read_doc(repo, doc)
        cmds = [c for c in commands_of(blocks) if c.uses_python_module()]
        pyblocks = [b for b in blocks if b.lang == "python"]
        if not cmds and not pyblocks:
            continue
        scratch = make_scratch(repo, work, doc.replace("/", "_"), links)
        for c in cmds:
            if c.mode != "run":
                print(f"SKIP {c.where()}: {c.text}   ({c.why or 'long'})")
                continue
            p = subprocess.run(["bash", "-c", c.text], cwd=scratch, env=env, capture_output=True, text=True, timeout=args.timeout)
            print(f"RAN  {c.where()}: {c.text}")
            if p.returncode != 0:
                report.fail(c.where(), f"exit {p.returncode} (expected 0): {c.text}\n{tail(p.stderr)}")
        run_blocks = [b for b in pyblocks if not (b.lines and b.lines[0][1].startswith("# not-run"))]
        for b in pyblocks:
            if b not in run_blocks:
                print(f"SKIP {doc}:{b.line}: python block ({b.lines[0][1][1:].strip()})")
        if run_blocks:
            # One script, each block's lines at their doc line numbers, so a traceback names them.
            script, where = [], {}
            for b in run_blocks:
                for n, l in b.lines:
                    where[len(script) + 1] = n
                    script.append(l)
            path = os.path.join(scratch, "doc_blocks.py")
            with open(path, "w") as f:
                f.write("\n".join(script) + "\n")
            p = subprocess.run([sys.executable, path], cwd=scratch, env=env, capture_output=True, text=True, timeout=args.timeout)
            print(f"RAN  {doc}: its {len(run_blocks)} python blocks (lines " + ", ".join(str(b.line) for b in run_blocks) + ")")
            if p.returncode != 0:
                m = re.findall(r'File ".*doc_blocks\.py", line (\d+)', p.stderr)
                line = where.get(int(m[-1]), run_blocks[0].line) if m else run_blocks[0].line
                report.fail(f"{doc}:{line}", f"the python blocks fail here (exit {p.returncode})\n{tail(p.stderr)}")
    print(f"\n{time.monotonic() - t0:.1f} s in all")
    return report.finish("python")


# ---------------------------------------------------------------------------------------------
TOP = ("apps", "base", "bench", "cmake", "compiler", "docs", "examples", "grammar", "python", "runtime", "stdlib", "tests", "tools")
PATH_IN_TEXT = re.compile(r"(?<![\w./$@-])((?:" + "|".join(TOP) + r")/[A-Za-z0-9_./*%-]*[A-Za-z0-9_*])")
LINK = re.compile(r"!?\[[^\]]*\]\(\s*([^)\s]+)(?:\s+\"[^\"]*\")?\s*\)")
OUTSIDE = [
    (re.compile(r"(?<![\w.])\.\./"), "a path that climbs out with ../"),
    (re.compile(r"shared/(spec|seed|style|hooks)"), "a folder outside the clone"),
    (re.compile(r"\bspec/(crex|pipeline)\.md"), "the spec files, which are not in a clone"),
    (re.compile(r"\bspec(?:'s)? ?§"), "a section of the spec, which is not in a clone"),
    (re.compile(r"/work/"), "a path of one machine"),
]


def quoted_path(caption):
    """(path, 'full' | 'excerpt') when a block's caption says it quotes a file, else (None, None)."""
    m = re.search(r"`([^`]+)` in full:$", caption)
    if m:
        return m.group(1), "full"
    m = re.search(r"\bfrom `([^`]+)`:$", caption)
    if m:
        return m.group(1), "excerpt"
    return None, None


def slug(heading):
    s = heading.strip().lower()
    s = re.sub(r"[^\w\- ]", "", s)
    return s.replace(" ", "-")


def anchors(lines):
    out, fence = set(), False
    for l in lines:
        if FENCE.match(l):
            fence = not fence
        elif not fence and l.startswith("#"):
            out.add(slug(l.lstrip("#")))
    return out


def placeholder(path):
    return any(re.fullmatch(r"[A-Z][A-Z_0-9]*(\.[\w%]+)*", part) or "%" in part for part in path.split("/"))


def check_files(args):
    repo = os.path.realpath(args.repo)
    report = Report()
    checked_paths, checked_links, quotes = 0, 0, 0
    for doc in doc_files(repo):
        lines, blocks, _ = read_doc(repo, doc)
        docdir = os.path.dirname(os.path.join(repo, doc))
        for n, line in enumerate(lines, 1):
            for pattern, what in OUTSIDE:
                m = pattern.search(line)
                if m and not (what.startswith("a path that climbs") and inside_link(line, m.start(), docdir, repo)):
                    report.fail(f"{doc}:{n}", f"points outside the clone ({what}): {line.strip()[:120]}")
                    break
            for m in LINK.finditer(line):
                target = m.group(1)
                if re.match(r"[a-z]+:", target):
                    continue
                checked_links += 1
                path, _, anchor = target.partition("#")
                full = os.path.realpath(os.path.join(docdir, path)) if path else os.path.join(repo, doc)
                if not full.startswith(repo + os.sep) or not os.path.exists(full):
                    report.fail(f"{doc}:{n}", f"link to {target}: no such file in the repo")
                elif anchor and full.endswith(".md"):
                    with open(full, encoding="utf-8") as f:
                        if anchor not in anchors(f.read().split("\n")):
                            report.fail(f"{doc}:{n}", f"link to {target}: {os.path.relpath(full, repo)} has no heading #{anchor}")
            for m in PATH_IN_TEXT.finditer(line):
                path = m.group(1).rstrip(".")
                if placeholder(path):
                    continue
                checked_paths += 1
                if any(ch in path for ch in "*?["):
                    if not glob.glob(os.path.join(repo, path)):
                        report.fail(f"{doc}:{n}", f"{path} matches no file of the repo")
                elif not os.path.exists(os.path.join(repo, path)) and not glob.glob(os.path.join(repo, path) + ".*"):
                    # (a module named without its extension, runtime/driver/run_plan, is its .h/.cpp)
                    report.fail(f"{doc}:{n}", f"{path} is not a file or folder of the repo")
        for b in blocks:
            path, kind = quoted_path(b.caption)
            if not path:
                continue
            quotes += 1
            full = os.path.join(repo, path)
            if not os.path.isfile(full):
                report.fail(f"{doc}:{b.line}", f"the block quotes {path}, which is not a file of the repo")
                continue
            with open(full, encoding="utf-8") as f:
                content = f.read()
            quoted = [l for _, l in b.lines]
            file_lines = content[:-1].split("\n") if content.endswith("\n") else content.split("\n")
            if kind == "full":
                if "\n".join(quoted) + "\n" != content:
                    report.fail(f"{doc}:{b.line}", f"the block says it is {path} in full, but it differs:\n"
                                + line_diff(path, file_lines, 0, doc, b, content))
                else:
                    print(f"QUOTE {doc}:{b.line}: {path}, in full, byte for byte")
            else:
                k = len(quoted)
                if not any(file_lines[i:i + k] == quoted for i in range(len(file_lines) - k + 1)):
                    best = max(range(max(1, len(file_lines) - k + 1)),
                               key=lambda i: difflib.SequenceMatcher(None, file_lines[i:i + k], quoted).ratio())
                    report.fail(f"{doc}:{b.line}", f"the block quotes lines of {path} that are not in it "
                                f"(nearest: from its line {best + 1}):\n"
                                + line_diff(path, file_lines[best:best + k], best, doc, b, None))
                else:
                    print(f"QUOTE {doc}:{b.line}: lines of {path}, as in the file")
    print(f"{checked_links} links, {checked_paths} paths and {quotes} quoted files checked in {len(doc_files(repo))} docs")
    return report.finish("files")


def line_diff(path, file_lines, first, doc, block, content):
    """Each difference as the file's lines against the doc's, both with their line numbers."""
    quoted = [l for _, l in block.lines]
    out = []
    for tag, i1, i2, j1, j2 in difflib.SequenceMatcher(None, file_lines, quoted, autojunk=False).get_opcodes():
        if tag == "equal":
            continue
        for i in range(i1, i2):
            out.append(f"      {path}:{first + i + 1}: {file_lines[i]}")
        for j in range(j1, j2):
            out.append(f"      {doc}:{block.lines[j][0]}: {quoted[j]}")
        if i1 == i2:
            out.append(f"      ({path} has no such line{'s' if j2 - j1 > 1 else ''} there)")
        if j1 == j2:
            out.append(f"      ({doc} leaves {'them' if i2 - i1 > 1 else 'it'} out)")
    if not out and content is not None and not content.endswith("\n"):
        out.append(f"      {path} does not end in a newline")
    return "\n".join(out)


def inside_link(line, pos, docdir, repo):
    """A ../ that is a link target resolving inside the repo (docs/x.md linking ../README.md) is fine."""
    for m in LINK.finditer(line):
        if m.start(1) <= pos < m.end(1):
            full = os.path.realpath(os.path.join(docdir, m.group(1).partition("#")[0]))
            return full.startswith(repo + os.sep)
    return False


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("check", choices=("commands", "python", "files"))
    ap.add_argument("--repo", required=True)
    ap.add_argument("--crex")
    ap.add_argument("--python-path")
    ap.add_argument("--work")
    ap.add_argument("--timeout", type=int, default=300, help="seconds one command may take")
    args = ap.parse_args()
    if args.check == "commands":
        return run_commands(args)
    if args.check == "python":
        return run_python(args)
    return check_files(args)


if __name__ == "__main__":
    sys.exit(main())
