#!/usr/bin/env python3
"""Runs the README's command lines as a user would copy them, from the repository root.

  check_readme_commands.py REPO_ROOT AGGPACK_EXE

Every line of a ```sh block that starts with ./build/aggpack is taken. `analyze`, `grading`
and `check` run as written; a `run` line is checked as `aggpack check` with the same scenario
and --set overrides (a run takes seconds to hours; the tests run the examples elsewhere);
`reproduce`, `sweep`, `calibrate`, `whole-grading` and `test` lines (minutes of simulation), `specimen` lines (they
need a run's folder; tests/cli/test_cli_specimen.cpp runs the command), and lines with a placeholder in capitals (SCENARIO, DIR),
are listed as skipped. Exits 1 if a command fails.
"""
import pathlib
import re
import shlex
import subprocess
import sys


def commands(readme):
    in_sh = False
    for number, line in enumerate(readme.splitlines(), start=1):
        if line.startswith("```"):
            in_sh = line.strip() == "```sh"
            continue
        if in_sh and line.startswith("./build/aggpack"):
            yield number, shlex.split(line, comments=True)


def as_check(args):
    """`run SCENARIO [options]` -> `check SCENARIO [--set ...]`."""
    out, k = ["check", args[1]], 2
    while k < len(args):
        if args[k] == "--set":
            out += args[k:k + 2]
            k += 2
        elif args[k] in ("--out", "--seed", "--threads", "--stop-after"):
            k += 2
        else:
            k += 1
    return out


def main(root, exe):
    root = pathlib.Path(root)
    failed = ran = 0
    for number, words in commands((root / "README.md").read_text()):
        args = words[1:]
        if any(re.fullmatch(r"[A-Z_]+", a) for a in args) or args[0] in ("reproduce", "sweep", "calibrate", "whole-grading", "specimen", "test"):
            print(f"README.md:{number}: skipped: {' '.join(words)}")
            continue
        if args[0] == "run":
            args = as_check(args)
        result = subprocess.run([exe, *args], cwd=root, capture_output=True, text=True, timeout=300)
        ran += 1
        if result.returncode != 0:
            failed += 1
            print(f"README.md:{number}: exit {result.returncode}: {' '.join(words)}\n{result.stdout}{result.stderr}")
        else:
            print(f"README.md:{number}: ok: aggpack {' '.join(args)}")
    print(f"{ran - failed} passed, {failed} failed")
    return 1 if failed or ran == 0 else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1], sys.argv[2]))
