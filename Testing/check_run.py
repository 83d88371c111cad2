"""Runs a test command and passes only when it exits with the expected code AND its output
(stdout and stderr together) matches every expected pattern.

ctest's PASS_REGULAR_EXPRESSION ignores the exit code (a run that prints the right line and then
crashes or fails still passes), and WILL_FAIL passes on any non-zero exit (a program that cannot
start, exit 127, passes as "refused the bad input"); this checks both at once.

Usage: check_run.py [--exit-code N] [--output REGEX]... -- <command> [arguments...]
"""
import argparse
import re
import subprocess
import sys

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--exit-code", type=int, default=0, help="the code the command must exit with")
parser.add_argument("--output", action="append", default=[], metavar="REGEX",
                    help="a pattern (Python re, searched) the output must contain; repeatable")
parser.add_argument("command", nargs=argparse.REMAINDER)
args = parser.parse_args()
command = args.command[1:] if args.command[:1] == ["--"] else args.command
if not command:
    parser.error("no command")

run = subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                     errors="replace")
sys.stdout.write(run.stdout)
failures = []
if run.returncode != args.exit_code:
    failures.append(f"expected exit code {args.exit_code}, got {run.returncode}")
for pattern in args.output:
    if not re.search(pattern, run.stdout):
        failures.append(f"expected output matching {pattern!r}, found none")
for failure in failures:
    print("check_run: FAILED:", failure, flush=True)
sys.exit(1 if failures else 0)
