#!/usr/bin/env python3
"""Docs that run: every shell command in README.md and docs/*.md is run, and must succeed.

Which blocks are commands (the fence's tag decides, nothing else):
  ```sh, ```bash, ```shell  every line is a command (or several joined by && etc.); it must exit 0.
  ```console                a terminal transcript: a line starting with "$ " is a command, the
                            lines after it up to the next "$ " line are its output (stdout and
                            stderr as a terminal shows them), which is checked (see below).
  any other tag             (text, json, ...) is not run: synopses, scene files, sample output.
  no tag                    is a failure: every fence says what it holds.
A "\" at the end of a line continues the command; "#" starting a word outside quotes starts a
comment. An HTML comment on the line just before the opening fence changes what the block's
commands expect:
  <!-- doc-test: skip (reason) -->   the block is not run; the reason is printed.
  <!-- doc-test: exit N -->          each command of the block must exit N instead of 0.

Checked output (console blocks): lines are compared with runs of spaces collapsed; a line "..."
stands for any number of lines, "..." inside a line for any text, and a time in seconds ("1.43 s")
for any time. Every other character must match.

How a command runs: the commands of one document run in order, each in `bash -c`, in one fresh
work folder for that document, so a file one command writes (`> shot.json`) is there for the
next. The folder is laid out as a clone beside the shared data: WORK/voxlux (the commands' working
directory) holds copies of the repository's grids/, ocio/ and docs/ (a command may write into
them, as `voxlux study ... -o docs/accuracy/smoke` does, without touching the repository) and
`build`, a link to the folder of the voxlux binary under test, which is also first on PATH (so
`voxlux` and `build/voxlux` are the binary under test); WORK/shared/data links to the shared data.
A `build/PROGRAM` that is not built (a benchmark, the test binary) is skipped. Three tables below
decide the rest:
  SKIPPED      commands that are never run (they build, install or run the whole suite);
  PLACEHOLDERS the doc's example file names, mapped to bundled or shared (third-party) data;
               a command that needs the shared data is skipped when it is absent, and so is a later
               command of the doc that reads a file it would have written (-o, --preview);
  REDUCTIONS   smaller images, fewer samples and frames, so the whole run stays short.
GL commands (`--backend gl`, `--backends ...gl`) are skipped with --skip-gl or VOXLUX_SKIP_GL=1.
A command is split into words as the shell does, the tables are applied to its words, and it is
joined again, quoted; a failure prints it as it ran.

Cost: about 2 minutes on 2 busy cores with the shared data, half of it the eight `voxlux study`
runs of docs/accuracy.md and docs/scans.md; about 40 s without the shared data. Temporary folders are removed.

  tests/docs/run_doc_commands.py --binary build/voxlux --source .          # run, PASS/FAIL/SKIP each
  tests/docs/run_doc_commands.py --binary build/voxlux --source . --list   # only list the commands
Exits 1 when a command fails, 0 otherwise.
"""
import argparse
import os
import re
import shlex
import shutil
import subprocess
import sys
import tempfile
import time

# Commands never run, with why. Each entry is the first words of a simple command (after any
# VAR=value words); a line with one of them, as `cmake --build build && build/voxlux_bench_sat`,
# is skipped whole, since what follows depends on it.
SKIPPED = [
    ("./setup.sh", "installs Debian packages, rebuilds the tree under test, renders the default cloud"),
    ("tests/run.sh", "the whole test suite, this test included, and a second, sanitizer build"),
    ("cmake -S", "configures a build tree: building is not this test's job"),
    ("cmake --build", "rebuilds the tree under test (the benchmarks after it are long and rewrite docs/)"),
    ("cmake --install", "installs outside the test's folder"),
]

# The docs' example file names -> real files. Keys are whole words of a command, or, ending in
# "/", the start of one. Values: ("repo", path) a bundled file (its copy in the work folder),
# ("shared", path) a file of the shared data, reached as ../shared/data/PATH, as from a clone;
# ("temp", "") the work folder. A command with a "shared" word, or naming a scene .json of the
# repository that mentions ../shared/data (docs/accuracy/*.json), is skipped when the shared data
# is absent. Outputs (smoke.exr, shot.json, stats.json) need no entry: they land in the work folder.
PLACEHOLDERS = {
    "cache.vdb": ("repo", "grids/cloud.vdb"),                                    # any .vdb cache
    "smoke.vdb": ("shared", "arnold-usd/smoke.vdb"),                             # the Houdini smoke
    "fire/fluid_data_####.vdb": ("shared", "blender/fire/fluid_data_####.vdb"),  # Blender fire sim
    "../shared/data/": ("shared", ""),
    "/tmp/": ("temp", ""),                                        # keep outputs in the work folder
}

# Size reductions, applied to the voxlux (and benchmark) invocations of a command: (the
# subcommands or programs, option, new value from the doc's value, value added when the option is
# absent or None). They change sizes and sample counts only: what a command does, and its exit code,
# stay the doc's.
MAX_RES = 64


def smaller_res(value):
    """WxH (or N) scaled down to at most MAX_RES on the long side, keeping the aspect."""
    sizes = [int(s) for s in value.split("x")] if re.fullmatch(r"\d+(x\d+)?", value) else None
    if not sizes or max(sizes) <= MAX_RES:
        return value
    return "x".join(str(max(1, s * MAX_RES // max(sizes))) for s in sizes)


def first_frames(value):
    """FIRST-LAST[xSTEP] cut to its first three frames."""
    m = re.fullmatch(r"(-?\d+)-(-?\d+)(?:x(\d+))?", value)
    step = int(m[3]) if m and m[3] else 1
    return f"{m[1]}-{min(int(m[2]), int(m[1]) + 2 * step)}" + (f"x{step}" if step > 1 else "") if m else value


REDUCTIONS = [
    (("render", "study", "view"), "--res", smaller_res, f"{MAX_RES}x{MAX_RES}"),     # 64x64 images
    (("voxlux_bench",), "--res", smaller_res, str(MAX_RES)),
    (("render", "study"), "--spp", lambda v: str(min(int(v), 4)) if v.isdigit() else v, None),
    (("render", "study"), "--frames", first_frames, None),                  # 3 frames of a sequence
    (("study",), "--spp-list", lambda v: "1,2", "1,2"),                     # 2 reference renders,
    (("study",), "--truth-spp", lambda v: "4", "4"),                        # against a 4-spp truth
    (("calibrate",), "--max-side", lambda v: "32", "32"),                   # a 32-pixel fit
    (("calibrate",), "--reference-spp", lambda v: "4", "4"),                # against a 4-spp truth
]

RUN_TAGS = {"sh", "bash", "shell"}
CONSOLE_TAG = "console"
OPERATORS = {"&&", "||", ";", "|", "&"}
TIMEOUT_S = 300          # per command


class Command:
    """One command of a doc; `output` is the console transcript's expected output (None: unchecked)."""

    def __init__(self, doc, line, text, expect_exit=0, output=None, skip=None, untagged=False):
        self.doc, self.line, self.text = doc, line, text
        self.expect_exit, self.output, self.skip, self.untagged = expect_exit, output, skip, untagged

    def where(self):
        return f"{self.doc}:{self.line}"


# ---- extraction ----------------------------------------------------------------------------

def code_part(line):
    """`line` without its comment: "#" starting a word outside quotes, as the shell reads it."""
    quote = None
    i = 0
    while i < len(line):
        c = line[i]
        if quote:
            if c == quote:
                quote = None
            elif c == "\\" and quote == '"':
                i += 1
        elif c == "\\":
            i += 1
        elif c in "'\"":
            quote = c
        elif c == "#" and (i == 0 or line[i - 1].isspace()):
            return line[:i].rstrip()
        i += 1
    return line.rstrip()


def logical_lines(lines, first_line):
    """(line number, command) for each command of `lines`, continuation lines joined."""
    out, pending, start = [], "", None
    for n, raw in enumerate(lines, first_line):
        code = code_part(raw)
        if start is None:
            if not code.strip():
                continue
            start = n
        if code.endswith("\\"):
            pending += code[:-1].strip() + " "
            continue
        out.append((start, (pending + code.strip()).strip()))
        pending, start = "", None
    if start is not None:
        out.append((start, pending.strip()))
    return out


def extract(doc, text):
    """Every command of one document; an untagged fence is a Command that fails."""
    lines = text.split("\n")
    commands = []
    i = 0
    while i < len(lines):
        fence = re.match(r"^(\s*)```\s*([\w+-]*)", lines[i])
        if not fence:
            i += 1
            continue
        indent, tag, fence_line = len(fence[1]), fence[2].lower(), i + 1
        marker = re.match(r"^\s*<!--\s*doc-test:\s*(.*?)\s*-->\s*$", lines[i - 1]) if i else None
        end = i + 1
        while end < len(lines) and not re.match(r"^\s*```\s*$", lines[end]):
            end += 1
        body = [l[indent:] if l[:indent].isspace() else l.lstrip() for l in lines[i + 1:end]]
        first = fence_line + 1          # the doc's line number of body[0]
        i = end + 1
        if not tag:
            commands.append(Command(doc, fence_line, "(untagged code block)", untagged=True))
            continue
        if tag not in RUN_TAGS and tag != CONSOLE_TAG:
            continue
        expect_exit, skip = 0, None
        if marker:
            m = re.fullmatch(r"exit (\d+)|skip \((.+)\)", marker[1])
            if not m:
                sys.exit(f"{doc}:{fence_line - 1}: unknown marker '{marker[1]}' (doc-test: skip (reason) | exit N)")
            expect_exit, skip = (int(m[1]), None) if m[1] else (0, m[2])
        if tag in RUN_TAGS:
            for n, cmd in logical_lines(body, first):
                commands.append(Command(doc, n, cmd, expect_exit, skip=skip))
            continue
        k = 0                           # console: "$ command", then its output up to the next "$ "
        while k < len(body):
            if not body[k].startswith("$ "):
                k += 1
                continue
            n, cmd_lines = first + k, [body[k][2:]]
            while code_part(cmd_lines[-1]).endswith("\\") and k + 1 < len(body):
                k += 1
                cmd_lines.append(body[k])
            k += 1
            out_start = k
            while k < len(body) and not body[k].startswith("$ "):
                k += 1
            (_, cmd), = logical_lines(cmd_lines, n)
            commands.append(Command(doc, n, cmd, expect_exit, output=body[out_start:k], skip=skip))
    return commands


def documents(source):
    docs = ["README.md"] + sorted("docs/" + f for f in os.listdir(os.path.join(source, "docs")) if f.endswith(".md"))
    return [(d, extract(d, open(os.path.join(source, d), encoding="utf-8").read())) for d in docs]


# ---- turning a doc command into the command run ----------------------------------------------

def split_simple(tokens):
    """The token lists of the simple commands between && || ; | &."""
    parts, cur = [], []
    for t in tokens:
        if t in OPERATORS:
            parts.append(cur)
            cur = []
        else:
            cur.append(t)
    return parts + [cur]


def tokenize(text):
    lex = shlex.shlex(text, posix=True, punctuation_chars=True)
    lex.whitespace_split = True
    lex.commenters = ""
    return list(lex)


def join(tokens):
    return " ".join(t if re.fullmatch(r"[;&|<>()]+", t) else shlex.quote(t) for t in tokens)


def reduce_sizes(words):
    """`words` (one simple command, redirections included) with REDUCTIONS applied."""
    # voxlux may run under a launcher (`xvfb-run -a ... build/voxlux view ...`, `env -u DISPLAY voxlux`).
    start = next((k for k, w in enumerate(words) if os.path.basename(w) == "voxlux"), 0)
    program = os.path.basename(words[start])
    key = program
    if program == "voxlux":
        key = next((w for w in words[start + 1:] if not w.startswith("-")), "")
    words = list(words)
    for keys, option, rewrite, added in REDUCTIONS:
        if key not in keys:
            continue
        if option in words[:-1]:
            k = words.index(option) + 1
            words[k] = rewrite(words[k])
        elif added is not None:
            redirect = next((k for k, w in enumerate(words) if re.fullmatch(r"\d*[<>]+", w)), len(words))
            words[redirect:redirect] = [option, added]
    return words


class Runner:
    def __init__(self, args):
        self.binary = os.path.abspath(args.binary)
        self.build = os.path.dirname(self.binary)
        self.source = os.path.abspath(args.source)
        shared = args.shared_data or os.environ.get("VOXLUX_SHARED_DATA") or os.path.join(self.source, "..", "shared", "data")
        self.shared = os.path.abspath(shared) if os.path.isdir(shared) else None
        self.skip_gl = args.skip_gl or os.environ.get("VOXLUX_SKIP_GL") == "1"

    def prepare(self, cmd):
        """(command to run, why it is skipped or None)."""
        if cmd.untagged:
            return None, "untagged"
        if cmd.skip:
            return None, f"marked in the doc: {cmd.skip}"
        tokens = tokenize(cmd.text)
        simple = split_simple(tokens)
        for words in simple:
            start = " ".join(w for w in words if not re.fullmatch(r"\w+=.*", w)) + " "
            for prefix, reason in SKIPPED:
                if start.startswith(prefix + " "):
                    return None, f"skip list: {prefix}: {reason}"
        out = []
        for words in simple:
            for k, w in enumerate(words):
                words[k] = self.placeholder(w)
                if words[k] is None:
                    return None, f"needs the shared data ({w}), absent: set VOXLUX_SHARED_DATA or put it at ../shared/data"
            if words and words[0].startswith("build/") and not os.path.exists(os.path.join(self.build, words[0][6:])):
                return None, f"{words[0]} is not built"
            if self.skip_gl and any(w == "gl" or w.endswith(",gl") or w.startswith("gl,") for w in words):
                return None, "asks for the GL backend, and GL tests are off (VOXLUX_SKIP_GL=1 or a VOXLUX_GL=OFF build)"
            out.append(reduce_sizes(words) if words else words)
        ops = [t for t in tokens if t in OPERATORS]
        run = out[0]
        for op, words in zip(ops, out[1:]):
            run = run + [op] + words
        return join(run), None

    def placeholder(self, word):
        """`word` with a PLACEHOLDERS entry applied; None when it needs absent shared data."""
        for key, (kind, path) in PLACEHOLDERS.items():
            if word == key or (key.endswith("/") and word.startswith(key)):
                rest = word[len(key):]
                if kind == "shared":
                    return "../shared/data/" + path + rest if self.shared else None
                return path + rest if kind == "repo" else rest
        if word.endswith(".json") and not self.shared:
            scene = os.path.join(self.source, word)
            if os.path.isfile(scene) and "../shared/data/" in open(scene, encoding="utf-8").read():
                return None
        return word

    def workdir(self):
        """A fresh work folder laid out as a clone beside the shared data: WORK/voxlux (returned,
        with copies of grids/, ocio/, docs/ and a link `build`) and WORK/shared/data (a link)."""
        root = tempfile.mkdtemp(prefix="voxlux-doc-")
        clone = os.path.join(root, "voxlux")
        for folder in ("grids", "ocio", "docs"):
            shutil.copytree(os.path.join(self.source, folder), os.path.join(clone, folder), symlinks=True)
        os.symlink(self.build, os.path.join(clone, "build"))
        if self.shared:
            os.mkdir(os.path.join(root, "shared"))
            os.symlink(self.shared, os.path.join(root, "shared", "data"))
        return clone

    def run(self, cmd, line, cwd):
        """(PASS|FAIL, seconds, failure detail)."""
        env = dict(os.environ, PATH=self.build + os.pathsep + os.environ.get("PATH", ""))
        merged = cmd.output is not None
        t0 = time.monotonic()
        try:
            p = subprocess.run(["bash", "-c", line], cwd=cwd, env=env, text=True, errors="replace",
                               stdout=subprocess.PIPE, stderr=subprocess.STDOUT if merged else subprocess.PIPE,
                               timeout=TIMEOUT_S)
        except subprocess.TimeoutExpired:
            return "FAIL", time.monotonic() - t0, f"timed out after {TIMEOUT_S} s"
        seconds = time.monotonic() - t0
        log = p.stdout if merged else p.stderr
        if p.returncode != cmd.expect_exit:
            tail = "\n".join(log.rstrip().split("\n")[-8:])
            return "FAIL", seconds, f"exit {p.returncode}, expected {cmd.expect_exit}\n{tail}"
        if merged:
            problem = compare_output(cmd.output, p.stdout)
            if problem:
                return "FAIL", seconds, problem
        return "PASS", seconds, ""


# ---- output check ----------------------------------------------------------------------------

def line_pattern(expected):
    """A regular expression for one expected output line (see the header)."""
    parts = re.split(r"(\.\.\.|\d+(?:\.\d+)?(?:e[+-]?\d+)? s\b)", " ".join(expected.split()))
    rx = ""
    for k, part in enumerate(parts):
        if k % 2 == 0:
            rx += re.escape(part)
        else:
            rx += ".*" if part == "..." else r"\d+(?:\.\d+)?(?:e[+-]?\d+)? s\b"
    return re.compile(rx)


def compare_output(expected, actual):
    """None when `actual` matches the doc's `expected` lines, else what differs."""
    want = [l for l in expected if l.strip()]
    got = [" ".join(l.split()) for l in actual.split("\n") if l.strip()]

    def match(w, g):
        if w == len(want):
            return g == len(got)
        if want[w].strip() == "...":
            return any(match(w + 1, k) for k in range(g, len(got) + 1))
        return g < len(got) and line_pattern(want[w]).fullmatch(got[g]) is not None and match(w + 1, g + 1)

    if match(0, 0):
        return None
    for k, w in enumerate(want):           # the first expected line the output lacks, for the report
        if w.strip() != "..." and not any(line_pattern(w).fullmatch(g) for g in got):
            return f"output differs from the doc: no line matches doc output line {k + 1}:\n  {w.strip()}"
    return "output differs from the doc: the lines match, but not in the doc's order or count"


def written_files(words):
    """The files a command names as its outputs (-o, --output, --preview)."""
    return [words[k + 1] for k, w in enumerate(words[:-1]) if w in ("-o", "--output", "--preview")]


# ---- main ------------------------------------------------------------------------------------

def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--binary", required=True, help="the voxlux binary under test")
    ap.add_argument("--source", required=True, help="the repository (README.md, docs/, grids/)")
    ap.add_argument("--shared-data", help="default: $VOXLUX_SHARED_DATA, else SOURCE/../shared/data")
    ap.add_argument("--skip-gl", action="store_true", help="skip commands that ask for the GL backend")
    ap.add_argument("--list", action="store_true", help="only print the commands found, as they would run")
    ap.add_argument("--keep", action="store_true", help="keep the temporary folders (their paths are printed)")
    args = ap.parse_args()
    runner = Runner(args)
    docs = documents(runner.source)

    if args.list:
        for doc, commands in docs:
            print(f"{doc}: {len(commands)} commands")
            for c in commands:
                line, skip = runner.prepare(c)
                print(f"  {c.where()}  {c.text}")
                print(f"      {'skip: ' + skip if skip else 'runs: ' + line}")
        return 0

    counts = {"PASS": 0, "FAIL": 0, "SKIP": 0}
    failures = []
    t_all = time.monotonic()
    for doc, commands in docs:
        cwd = None
        unwritten = {}   # file -> the command that would have written it, skipped for want of the shared data
        for c in commands:
            line, skip = runner.prepare(c)
            # A later command of the doc may read what a skipped one would have written (a scene
            # the quick form writes from the shared data): it cannot run either.
            # (tokenize cannot fail on these: prepare has split the same text.)
            if not skip and (read := next((w for w in tokenize(c.text) if w in unwritten), None)):
                line, skip = None, f"reads {read}, which {unwritten[read]} would have written (it needs the shared data)"
            if skip and skip.startswith("needs the shared data"):
                unwritten.update({w: c.where() for w in written_files(tokenize(c.text))})
            if skip == "untagged":
                status, seconds, detail = "FAIL", 0.0, ("a code block without a tag: tag it sh/bash/shell or console "
                                                        "(run) or text, json, ... (not run)")
            elif skip:
                status, seconds, detail = "SKIP", 0.0, skip
            else:
                cwd = cwd or runner.workdir()
                status, seconds, detail = runner.run(c, line, cwd)
            counts[status] += 1
            print(f"{status}  {c.where()}  {c.text}" + (f"  ({seconds:.1f} s)" if status != "SKIP" else ""), flush=True)
            if status == "SKIP":
                print(f"      {detail}")
            elif status == "FAIL":
                failures.append(c.where())
                if line and line != c.text:
                    print(f"      ran: {line}")
                print("\n".join("      | " + l for l in detail.split("\n")), flush=True)
        if cwd and args.keep:
            print(f"      ({doc}: commands ran in {cwd})")
        elif cwd:
            shutil.rmtree(os.path.dirname(cwd), ignore_errors=True)
    print(f"{counts['PASS']} passed, {counts['FAIL']} failed, {counts['SKIP']} skipped "
          f"in {time.monotonic() - t_all:.0f} s" + (": " + " ".join(failures) if failures else ""))
    return 1 if counts["FAIL"] else 0


if __name__ == "__main__":
    sys.exit(main())
