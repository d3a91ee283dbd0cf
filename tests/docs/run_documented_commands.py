#!/usr/bin/env python3
"""Every command written in the docs runs as written, from a fresh copy of the clone.

Reads the shell code blocks of README.md, docs/*.md and apps/*/README.md, and runs their
commands in order, one document at a time, as a reader following that document would:

- in a scratch folder laid out like CI's: SCRATCH/clone/ is a fresh copy of the source tree
  (its tracked and untracked, not ignored, files: the docs may write docs/images/... there,
  never into the real tree), the working directory of every command; SCRATCH/shared is
  `../shared` beside it (the shared data folder, when it is beside the source tree);
- the doc's `/tmp/` is SCRATCH/tmp/ (so parallel runs and other users of /tmp do not
  collide, and everything is removed at the end); TMPDIR too;
- a lidarseg tool (`lidarseg-odometry`, `build/release/apps/lidarseg-features`, ...) is the
  built one (APPS_DIR), `build/release/apps` (a `--bin` value) is APPS_DIR and
  `build/release/tests/benchmarks/` is BUILD_DIR/tests/benchmarks/;
- `NAME=value` lines set NAME for the document's later commands (`$L`);
- each command gets a time budget: one still running at its budget, without an error so far,
  is stopped and reported "started" (heavy commands, such as batches of many seeds and
  benchmarks, get a shorter budget: they are only checked to start); a command whose
  output a later command of the same document reads gets a longer one.

Per command: ok / started / FAILED (exit code, first error line) / skipped (with why: an
input absent such as ../shared, a program not installed, a template with placeholders, a
synopsis, `./run.sh` commands that build and run for minutes). A command repeated word
for word whose inputs all come from the clone is run once: a later copy gets the first
one's outputs (reported "ok (same as FILE:LINE)"). A failure whose input was written by an
earlier command stopped at its budget is reported skipped, not failed (the machine was
slow, the doc is not wrong); a command killed by a signal is run once more (headless
Chromium sometimes aborts on a loaded machine; a crash that repeats fails). Exit 0 when no
command failed.

  run_documented_commands.py SOURCE_DIR APPS_DIR BUILD_DIR [--work DIR] [--shared DIR]
      [--budget S] [--heavy-budget S] [--producer-budget S] [--only PATTERN] [--keep]
"""
import argparse
import glob
import os
import re
import shlex
import shutil
import signal
import subprocess
import sys
import tempfile
import time

TOOLS = "odometry|features|segment|simulate|inspect|people|batch"
# A lidarseg tool as a whole word, with any leading path (build/release/apps/lidarseg-x).
TOOL_TOKEN = re.compile(r"(?<![^\s(|&;\"'=])(?:[\w./-]*/)?(lidarseg-(?:%s))(?=[\s)|&;\"']|$)" % TOOLS)
SHELL_LANGS = {"sh", "bash", "shell", "console", "shell-session"}
BUILTINS = {"cd", "time", "export", "set", "true", "false", "echo", "test", "[", "source", "."}
# Commands only checked to start: many runs, benchmarks, whole evaluations.
HEAVY = [
    (re.compile(r"lidarseg-batch\s+run\b"), "a batch of many seeds"),
    (re.compile(r"\bparallel\b"), "a batch of many seeds"),
    (re.compile(r"tests/benchmarks/[\w.]+\.py\b"), "a whole evaluation"),
    (re.compile(r"tests/benchmarks/bench_\w+"), "a benchmark"),
]
# `./run.sh` commands: each builds (minutes) and runs for minutes; `test` is this suite.
RUN_SH = re.compile(r"^\./run\.sh\b")
ASSIGN = re.compile(r"^([A-Za-z_]\w*)=(\S*)$")
VAR = re.compile(r"\$\{?([A-Za-z_]\w*)\}?")
SHELL_VARS = {"OLDPWD", "PWD", "HOME"}


def strip_comment(line):
    """The line without its shell comment (a # at the start of a word, outside quotes)."""
    quote, prev = None, " "
    for i, c in enumerate(line):
        if quote:
            if c == quote:
                quote = None
        elif c in "'\"":
            quote = c
        elif c == "#" and prev.isspace():
            return line[:i].rstrip()
        prev = c
    return line.rstrip()


def blocks(path):
    """(language, [(line number, text)]) of each fenced code block of a Markdown file."""
    out, current, lang = [], None, ""
    with open(path, encoding="utf-8") as f:
        for n, line in enumerate(f, 1):
            stripped = line.strip()
            if stripped.startswith("```"):
                if current is None:
                    current, lang = [], stripped[3:].strip().lower()
                else:
                    out.append((lang, current))
                    current = None
                continue
            if current is not None:
                current.append((n, line.rstrip("\n")))
    return out


def commands(path):
    """(line, text) of each command of the file's code blocks, continuation lines joined,
    comments removed. Shell blocks: every command; other blocks: lidarseg tool lines only
    (the others hold program output, diagrams, synopses)."""
    out = []
    for lang, lines in blocks(path):
        pending, start = "", 0
        for n, raw in lines:
            text = strip_comment(raw)
            if not pending:
                if not text.strip():
                    continue
                if lang not in SHELL_LANGS and not TOOL_TOKEN.search(text):
                    continue
                start = n
            pending = (pending + " " + text.strip()) if pending else text.strip()
            if pending.endswith("\\"):
                pending = pending[:-1].rstrip()
                continue
            out.append((start, pending))
            pending = ""
        if pending:
            out.append((start, pending))
    return out


def programs(text):
    """The programs a command line starts (first word of each pipeline/list element; quotes
    respected, `time` and NAME=value prefixes and redirection targets left out)."""
    lexer = shlex.shlex(text, posix=True, punctuation_chars=True)
    lexer.whitespace_split = True
    try:
        tokens = list(lexer)
    except ValueError:
        tokens = text.split()
    progs, expect, target = [], True, False
    for t in tokens:
        if target:
            target = False
            continue
        if t and all(c in "|&;()<>" for c in t):
            if set(t) <= set("<>&") and t not in ("&", "&&"):
                target = True  # the file of a redirection
            else:
                expect = True
            continue
        if expect and not (t == "time" or re.match(r"^[A-Za-z_]\w*=", t)):
            progs.append(t)
            expect = False
    return progs


class Step:
    def __init__(self, doc, line, text):
        self.doc, self.line, self.text = doc, line, text
        self.where = "%s:%d" % (doc, line)
        self.status, self.detail, self.seconds = None, "", 0.0
        self.outputs = []  # paths (relative to the scratch root) the command wrote


class Runner:
    def __init__(self, args):
        self.source = os.path.abspath(args.source)
        self.apps = os.path.abspath(args.apps)
        self.build = os.path.abspath(args.build)
        # Short by default (the system's temporary folder): the commands' TMPDIR is in it, and
        # a UNIX socket path there (Chromium's) must stay under 108 characters.
        self.work = os.path.abspath(args.work) if args.work else None
        shared = args.shared if args.shared is not None else os.path.join(self.source, "..", "shared")
        self.shared = os.path.realpath(shared) if shared and os.path.isdir(shared) else None
        self.args = args
        self.cache = {}  # command text -> (first step, cache folder)
        self.child = None
        self.clone_files = self.source_files()

    # -- the scratch copy of the clone --------------------------------------------------
    def source_files(self):
        try:
            out = subprocess.run(["git", "-C", self.source, "ls-files", "-z", "--cached", "--others",
                                  "--exclude-standard"], capture_output=True, check=True).stdout
            files = [f for f in out.decode().split("\0") if f]
        except (OSError, subprocess.CalledProcessError):
            files = []
            for root, dirs, names in os.walk(self.source):
                dirs[:] = [d for d in dirs if d not in (".git", "build") and not d.startswith("build")]
                files += [os.path.relpath(os.path.join(root, n), self.source) for n in names]
        return sorted(f for f in files if os.path.isfile(os.path.join(self.source, f)))

    def make_scratch(self, name):
        root = os.path.join(self.work, name)
        clone = os.path.join(root, "clone")
        for f in self.clone_files:
            dst = os.path.join(clone, f)
            os.makedirs(os.path.dirname(dst), exist_ok=True)
            shutil.copy2(os.path.join(self.source, f), dst)
        for d in ("tmp", "home/.config", "home/.cache"):
            os.makedirs(os.path.join(root, d), exist_ok=True)
        if self.shared:
            os.symlink(self.shared, os.path.join(root, "shared"))
        return root

    # -- text substitutions --------------------------------------------------------------
    def substitute(self, text, root):
        # The docs' /tmp/ first: the build tree itself may live under /tmp (a CI clone), and
        # its paths, put in below, must not be moved into the scratch folder.
        text = re.sub(r"(?<![\w.-])/tmp/", os.path.join(root, "tmp") + "/", text)
        text = TOOL_TOKEN.sub(lambda m: os.path.join(self.apps, m.group(1)), text)
        text = re.sub(r"(?<!\S)build/release/apps(?=/?(?:\s|$))", self.apps, text)
        text = re.sub(r"(?<![\w.-])build/release/tests/benchmarks/",
                      os.path.join(self.build, "tests", "benchmarks") + "/", text)
        return text

    # -- why a command is not run --------------------------------------------------------
    def skip_reason(self, step, env, root):
        text = step.text
        if RUN_SH.match(text):
            what = text.split()[1] if len(text.split()) > 1 else ""
            return ("./run.sh %s builds and runs for minutes (CI runs ./run.sh test, which holds "
                    "this check)" % what) if what != "test" else "./run.sh test is the suite this check is part of"
        try:
            words = shlex.split(text)
        except ValueError as e:
            return "cannot be split as shell words (%s)" % e
        prog_seen = False
        for i, w in enumerate(words):
            if not prog_seen:
                prog_seen = not (w == "time" or re.match(r"^[A-Za-z_]\w*=", w))
                continue
            if w.startswith("[") or w.endswith("]") or (w.startswith("(") and "|" in text):
                return "a synopsis, not a command"
        placeholders = []
        for w in words:
            if w in ("<", ">", "<<", ">>", "2>", "&>"):
                continue
            if re.search(r"<[\w -]+>", w):
                placeholders.append(w)
                continue
            for name in VAR.findall(w):
                if name not in env and name not in SHELL_VARS:
                    placeholders.append("$" + name)
            if w.startswith("-") and "=" not in w:
                continue
            value = w.split("=", 1)[1] if w.startswith("-") else w
            for part in re.split(r"[/,]", value):
                stem = part.split(".")[0]
                if re.fullmatch(r"[A-Z][A-Z0-9_]*", stem) and stem not in env:
                    placeholders.append(w)
                    break
        if placeholders:
            return "a template: %s stand%s for what the reader supplies" % (
                ", ".join(sorted(set(placeholders))), "s" if len(set(placeholders)) == 1 else "")
        for prog in programs(text):
            if prog in BUILTINS:
                continue
            sub = self.substitute(prog, root)
            if "/" in sub:
                path = sub if os.path.isabs(sub) else os.path.join(root, "clone", sub)
                if not os.access(path, os.X_OK):
                    if "/tests/benchmarks/" in sub:
                        return "%s not built (LIDARSEG_BUILD_BENCHMARKS=OFF)" % prog
                    return "%s not found" % prog
            elif shutil.which(prog) is None:
                return "%s is not installed" % prog
        # Inputs outside the clone: ../shared and absolute paths (after the doc's variables).
        expanded = VAR.sub(lambda m: env.get(m.group(1), m.group(0)), text)
        try:
            words = shlex.split(expanded)
        except ValueError:
            words = expanded.split()
        for w in words:
            value = w.split("=", 1)[1] if w.startswith("-") and "=" in w else w
            if value.startswith("../shared"):
                if not self.shared:
                    return "input absent: %s (no shared data folder beside the source tree)" % value
                if not os.path.exists(os.path.join(root, "clone", value)):
                    return "input absent: %s" % value
            elif value.startswith("/") and not value.startswith("/tmp/") and value not in ("/dev/null",):
                if not os.path.exists(value):
                    return "input absent: %s" % value
        return None

    # -- running -------------------------------------------------------------------------
    def snapshot(self, root):
        state = {}
        for top in ("clone", "tmp"):
            for dirpath, dirs, names in os.walk(os.path.join(root, top)):
                for n in names:
                    p = os.path.join(dirpath, n)
                    try:
                        st = os.lstat(p)
                    except OSError:
                        continue
                    state[os.path.relpath(p, root)] = (st.st_mtime_ns, st.st_size)
        return state

    def session_pids(self, sid):
        pids = []
        for d in os.listdir("/proc"):
            if not d.isdigit():
                continue
            try:
                with open("/proc/%s/stat" % d) as f:
                    fields = f.read().rsplit(")", 1)[1].split()
                if int(fields[3]) == sid:  # fields after the name: state ppid pgrp session
                    pids.append(int(d))
            except (OSError, IndexError, ValueError):
                continue
        return pids

    def stop(self, proc):
        """Stop the command and everything it started (its own session), by process id."""
        for sig, wait in ((signal.SIGTERM, 5.0), (signal.SIGKILL, 5.0)):
            pids = self.session_pids(proc.pid)
            if proc.poll() is None and proc.pid not in pids:
                pids.append(proc.pid)
            if not pids:
                break
            for pid in pids:
                try:
                    os.kill(pid, sig)
                except ProcessLookupError:
                    pass
            deadline = time.monotonic() + wait
            while time.monotonic() < deadline:
                if proc.poll() is not None and not self.session_pids(proc.pid):
                    return
                time.sleep(0.1)
        proc.poll()

    def run(self, step, command, env_vars, root, budget, log):
        env = dict(os.environ)
        env.update(env_vars)
        env["TMPDIR"] = os.path.join(root, "tmp")
        env["XDG_CONFIG_HOME"] = os.path.join(root, "home", ".config")
        env["XDG_CACHE_HOME"] = os.path.join(root, "home", ".cache")
        with open(log, "wb") as out:
            self.child = proc = subprocess.Popen(["bash", "-c", command], cwd=os.path.join(root, "clone"),
                                                 stdin=subprocess.DEVNULL, stdout=out, stderr=subprocess.STDOUT,
                                                 env=env, start_new_session=True)
            start = time.monotonic()
            try:
                code = proc.wait(timeout=budget)
                stopped = False
            except subprocess.TimeoutExpired:
                stopped, code = True, None
            step.seconds = time.monotonic() - start
            self.stop(proc)  # the command's leftovers (an X server, a browser) too
            self.child = None
        return code, stopped

    @staticmethod
    def first_error(log):
        try:
            with open(log, encoding="utf-8", errors="replace") as f:
                lines = [l.strip() for l in f if l.strip()]
        except OSError:
            return ""
        for l in lines:
            if re.search(r"\bFATAL\b|AddressSanitizer|runtime error", l):
                return l[:300]
        for l in lines:
            if re.search(r"error|fail|cannot|can't|no such|not found|usage|invalid|unknown|exception|abort",
                         l, re.I):
                return l[:300]
        return (lines[-1] if lines else "(no output)")[:300]

    def budget_of(self, step, later):
        for pattern, why in HEAVY:
            if pattern.search(step.text):
                return self.args.heavy_budget, "heavy (%s): run for %d s only" % (why, self.args.heavy_budget)
        if later:
            return self.args.producer_budget, None
        return self.args.budget, None

    def run_doc(self, doc, steps):
        root = self.make_scratch(re.sub(r"[^\w.-]", "_", doc))
        env = {}
        written = set()        # paths (relative to root) an earlier command wrote
        stopped_outputs = []   # (step, path tokens) of commands stopped at their budget
        for i, step in enumerate(steps):
            m = ASSIGN.match(step.text)
            if m and len(step.text.split()) == 1:
                env[m.group(1)] = m.group(2)
                step.status, step.detail = "set", "%s=%s" % m.groups()
                continue
            reason = self.skip_reason(step, env, root)
            if reason:
                step.status, step.detail = "skipped", reason
                continue
            command = self.substitute(step.text, root)
            # Does a later command read what this one writes? (a path token of a later
            # command starting with one of this command's paths that do not exist yet)
            own = [t for t in self.path_tokens(command, root) if not os.path.exists(self.resolve(t, root))]
            later = any(t2.startswith(t) for t in own for s in steps[i + 1:]
                        for t2 in self.path_tokens(self.substitute(s.text, root), root) if t2 != t)
            # The same command, with inputs from the clone only, already ran: reuse its outputs.
            reads_written = any(os.path.relpath(self.resolve(t, root), root) in written or
                                any(w.startswith(os.path.relpath(self.resolve(t, root), root) + "/")
                                    for w in written)
                                for t in self.path_tokens(command, root) if os.path.exists(self.resolve(t, root)))
            key = (step.text, tuple(sorted(env.items())))
            if not reads_written and key in self.cache:
                first, store = self.cache[key]
                for rel in first.outputs:
                    dst = os.path.join(root, rel)
                    os.makedirs(os.path.dirname(dst), exist_ok=True)
                    shutil.copy2(os.path.join(store, rel), dst)
                    written.add(rel)
                step.status = "ok"
                step.detail = "same command as %s: its outputs copied, not run again" % first.where
                continue
            budget, heavy = self.budget_of(step, later)
            log = os.path.join(root, "log_%d.txt" % step.line)
            before = self.snapshot(root)
            print("[%s] %s" % (step.where, step.text), flush=True)
            code, stopped = self.run(step, command, env, root, budget, log)
            retried = ""
            if not stopped and (code < 0 or code > 128):
                # Killed by a signal (headless Chromium now and then aborts in its crash
                # handler on a loaded machine): once more; a crash that repeats still fails.
                retried = "second try (the first died of signal %d: %s)" % (
                    -code if code < 0 else code - 128, self.first_error(log))
                print("    " + retried, flush=True)
                code, stopped = self.run(step, command, env, root, budget, log)
            after = self.snapshot(root)
            step.outputs = sorted(p for p, s in after.items() if before.get(p) != s)
            written.update(step.outputs)
            if stopped:
                step.status = "started"
                step.detail = (heavy + ", then stopped") if heavy else \
                    "still running at its budget of %d s, stopped" % budget
                stopped_outputs.append((step, own))
            elif code == 0:
                step.status, step.detail = "ok", retried
                if not reads_written:
                    store = os.path.join(self.work, "cache", "%d" % len(self.cache))
                    for rel in step.outputs:
                        dst = os.path.join(store, rel)
                        os.makedirs(os.path.dirname(dst), exist_ok=True)
                        shutil.copy2(os.path.join(root, rel), dst)
                    self.cache[key] = (step, store)
            else:
                tokens = self.path_tokens(command, root)
                cause = next((s for s, outs in stopped_outputs
                              if any(t.startswith(o) for o in outs for t in tokens)), None)
                if cause:
                    step.status = "skipped"
                    step.detail = ("reads what %s writes, which was stopped at its budget (exit %d: %s)"
                                   % (cause.where, code, self.first_error(log)))
                else:
                    step.status = "FAILED"
                    step.detail = "exit %d: %s" % (code, self.first_error(log)) + \
                        (" (%s)" % retried if retried else "")
            print("    %s %.1f s %s" % (step.status, step.seconds, step.detail), flush=True)

    @staticmethod
    def resolve(token, root):
        return token if os.path.isabs(token) else os.path.join(root, "clone", token)

    @staticmethod
    def path_tokens(command, root):
        """Words of a command that look like paths (a flag's value after = included)."""
        try:
            words = shlex.split(command)
        except ValueError:
            words = command.split()
        out = []
        for w in words:
            if w.startswith("-") and "=" in w:
                w = w.split("=", 1)[1]
            elif w.startswith("-"):
                continue
            if w.startswith("file://"):
                w = w[len("file://"):]
            if "/" in w or re.search(r"\.\w+$", w):
                out.append(w.rstrip(")"))
        return out

    def main(self):
        files = [os.path.join(self.source, "README.md")] + \
            sorted(glob.glob(os.path.join(self.source, "docs", "*.md"))) + \
            sorted(glob.glob(os.path.join(self.source, "apps", "*", "README.md")))
        if self.args.only:
            files = [f for f in files if re.search(self.args.only, os.path.relpath(f, self.source))]
        if self.work is None:
            self.work = tempfile.mkdtemp(prefix="lidarseg-docs-")
        elif os.path.exists(self.work):
            shutil.rmtree(self.work)
        os.makedirs(self.work, exist_ok=True)
        print("scratch %s: clone/ (a copy of the %d source files, the working folder), tmp/ "
              "(the docs' /tmp/), shared -> %s" % (self.work, len(self.clone_files), self.shared or "(absent)"))
        print("budget per command %d s (%d s when a later command reads its output; heavy: %d s)"
              % (self.args.budget, self.args.producer_budget, self.args.heavy_budget), flush=True)
        all_steps = []
        try:
            for path in files:
                doc = os.path.relpath(path, self.source)
                steps = [Step(doc, n, t) for n, t in commands(path)]
                if not steps:
                    continue
                all_steps += steps
                self.run_doc(doc, steps)
        finally:
            if self.child is not None and self.child.poll() is None:
                self.stop(self.child)
            if not self.args.keep:
                shutil.rmtree(self.work, ignore_errors=True)
        counted = [s for s in all_steps if s.status != "set"]
        print()
        for s in counted:
            shown = s.text if len(s.text) <= 140 else s.text[:137] + "..."
            timing = " %.0f s" % s.seconds if s.status in ("ok", "started", "FAILED") and s.seconds else ""
            print("%-8s %s%s  %s\n         %s" % (s.status, s.where, timing, shown, s.detail) if s.detail
                  else "%-8s %s%s  %s" % (s.status, s.where, timing, shown))
        n = {k: sum(1 for s in counted if s.status == k) for k in ("ok", "started", "FAILED", "skipped")}
        print("\n%d documented commands: %d ran ok, %d started (stopped at their budget), %d failed, "
              "%d skipped" % (len(counted), n["ok"], n["started"], n["FAILED"], n["skipped"]))
        return 1 if n["FAILED"] else 0


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("source")
    p.add_argument("apps")
    p.add_argument("build")
    p.add_argument("--work", help="scratch folder, emptied first (default: a new one in the system's "
                   "temporary folder; keep its path short, see Runner.__init__)")
    p.add_argument("--shared", help="the shared data folder (default SOURCE/../shared; '' for none)")
    p.add_argument("--budget", type=int, default=30)
    p.add_argument("--heavy-budget", type=int, default=10)
    p.add_argument("--producer-budget", type=int, default=300)
    p.add_argument("--only", help="regular expression: only the docs whose path matches")
    p.add_argument("--keep", action="store_true", help="keep the scratch folder")
    args = p.parse_args()
    runner = Runner(args)

    def on_signal(signum, frame):
        raise KeyboardInterrupt

    signal.signal(signal.SIGTERM, on_signal)
    try:
        return runner.main()
    except KeyboardInterrupt:
        print("interrupted: commands stopped, scratch removed", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
