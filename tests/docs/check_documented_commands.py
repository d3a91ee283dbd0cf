#!/usr/bin/env python3
"""Every lidarseg command written in the docs parses as written.

Finds the commands in README.md, docs/*.md and apps/*/README.md that call a lidarseg tool
(`lidarseg-odometry ...`, `build/release/apps/lidarseg-features ...`), inside fenced code
blocks, with their continuation lines, and runs each with the built tool and `--help`
added at the end: TCLAP then checks every flag and value (an unknown or renamed-away flag,
a value of the wrong type, a missing required argument are usage errors, exit 2) and runs
nothing. Renamed flags still read print a note: the docs must not use them.

  check_documented_commands.py SOURCE_DIR APPS_DIR
"""
import glob
import os
import re
import shlex
import subprocess
import sys

TOOL = re.compile(r"(?:^|\s|/)(lidarseg-(?:odometry|features|segment|simulate|inspect|people|batch))(?=\s|$)")


def commands(path):
    """(line number, text) of each tool command in the file's code blocks."""
    out, in_block, pending, start = [], False, "", 0
    with open(path, encoding="utf-8") as f:
        for n, line in enumerate(f, 1):
            if line.lstrip().startswith("```"):
                in_block = not in_block
                pending = ""
                continue
            if not in_block:
                continue
            text = line.rstrip("\n")
            if pending:
                pending += " " + text.strip()
            else:
                if not TOOL.search(text.split("#")[0]) or text.lstrip().startswith("#"):
                    continue
                pending, start = text.strip(), n
            if pending.endswith("\\"):
                pending = pending[:-1]
                continue
            out.append((start, pending))
            pending = ""
    return out


def main():
    source, apps = sys.argv[1], sys.argv[2]
    files = [os.path.join(source, "README.md")] + sorted(glob.glob(os.path.join(source, "docs", "*.md"))) + \
        sorted(glob.glob(os.path.join(source, "apps", "*", "README.md")))
    failures, checked = [], 0
    for path in files:
        for line, text in commands(path):
            where = "%s:%d" % (os.path.relpath(path, source), line)
            # The command alone: no comment, pipe or redirection, no "time"/"( ... )".
            cmd = re.split(r"\s[|>]|\s2>|\s&&\s|;", text.split(" #")[0])[0].strip().lstrip("(").strip()
            if cmd.startswith("time "):
                cmd = cmd[5:]
            try:
                args = shlex.split(cmd)
            except ValueError as e:
                failures.append("%s: cannot split '%s': %s" % (where, cmd, e))
                continue
            tool_index = next((i for i, a in enumerate(args) if TOOL.search(a)), None)
            if tool_index is None:
                continue
            if any(a.startswith(("[", "(")) or a.endswith("]") for a in args):
                continue  # a synopsis ("[-c FILE]"), not a command
            # Shell variables stand for values the reader supplies: a number parses anywhere.
            args = [re.sub(r"\$\{?\w+\}?", "1", a) for a in args]
            tool = TOOL.search(args[tool_index]).group(1)
            argv = [os.path.join(apps, tool)] + args[tool_index + 1:] + ["--help"]
            run = subprocess.run(argv, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                                 stderr=subprocess.PIPE, text=True, timeout=60)
            checked += 1
            if run.returncode != 0:
                failures.append("%s: exit %d: %s\n    %s" % (where, run.returncode, cmd, run.stderr.strip()))
            elif "note:" in run.stderr:
                failures.append("%s: uses an old spelling: %s\n    %s" % (where, cmd, run.stderr.strip()))
    for f in failures:
        print("FAIL " + f)
    print("%d documented commands checked, %d fail" % (checked, len(failures)))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
