"""MPI runs back to back, to show that none hangs: the distributed comparison (test_mpi.py:
opaque and translucent Direct Surfaces and the filter, 2 ranks) run N times through
mpi_private_displays.py (each rank on an X server of its own, a hard time limit per attempt,
only X refusals retried), with a table of what each run did and how long it took.

Usage (after Scripts/setup.sh; the serial reference is made first):
  python3 Testing/Plugin/mpi_stress.py [--runs 30] [--seconds 120] [--work DIR]
Exit status 1 if any run failed or hung.
"""
import argparse
import glob
import io
import os
import statistics
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, HERE)
import mpi_private_displays  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=30)
    parser.add_argument("--seconds", type=float, default=120.0)
    parser.add_argument("--work", default=os.path.join(ROOT, "build", "Testing", "Temporary", "mpi-stress"))
    args = parser.parse_args()
    plugins = glob.glob(os.path.join(ROOT, "build", "**", "TetDSR.so"), recursive=True)
    if not plugins:
        sys.exit("mpi_stress: no build/**/TetDSR.so: run Scripts/setup.sh first")
    os.environ.setdefault("OMPI_ALLOW_RUN_AS_ROOT", "1")
    os.environ.setdefault("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
    test = [os.path.join(HERE, "test_mpi.py"), plugins[0], os.path.join(ROOT, "Data"), args.work]
    reference = subprocess.run(
        ["xvfb-run", "-a", "-s", "-screen 0 1280x1024x24 -noreset", "pvbatch"] + test + ["reference"],
        stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=300)
    if reference.returncode != 0:
        print(reference.stdout)
        sys.exit("mpi_stress: the serial reference failed")

    rows, failures = [], 0
    for number in range(1, args.runs + 1):
        log = io.StringIO()
        start = time.monotonic()
        code, attempts = mpi_private_displays.run(2, args.seconds, ["pvbatch"] + test + ["compare"], log)
        total = time.monotonic() - start
        outcomes = [outcome for outcome, _ in attempts]
        rows.append((number, code, outcomes, total))
        failures += code != 0
        print(f"run {number:2d}: exit {code}, attempts: {', '.join(outcomes)}; {total:.1f} s", flush=True)
        if code != 0:
            print(log.getvalue()[-4000:])
    hung = sum(outcomes.count("hung") for _, _, outcomes, _ in rows)
    refused = sum(outcomes.count("refused by X") for _, _, outcomes, _ in rows)
    durations = [total for _, _, _, total in rows]
    print()
    print("| runs | passed | failed | hung (killed at the limit) | attempts refused by X (retried) | "
          "s per run min / median / max |")
    print("|---|---|---|---|---|---|")
    print(f"| {len(rows)} | {len(rows) - failures} | {failures - hung} | {hung} | {refused} | "
          f"{min(durations):.1f} / {statistics.median(durations):.1f} / {max(durations):.1f} |")
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
