"""What the fuzzers share (fuzz_filter, fuzz_mapper, fuzz_representation, fuzz_wheel):

- Case, the record of one case's random choices, made from (seed, case index) alone: one random
  stream per named knob or step, so that switching a knob off (--without) leaves every other
  choice as it was, and the notes a replay prints;
- the worker processes that run many cases each (fuzz_filter, fuzz_wheel): serve() is a worker's
  loop, run_tasks() the parent's, which gives each case a time limit and reports a crash or a
  hang as that case's result (a crash or a hang costs one restart);
- the texts by which a run tells an X server's refusal or a sanitizer report.

numpy and the standard library only: the wheel's fuzzer runs it with pip's packages, the
representation's cases in pvpython.
"""
import json
import os
import re
import select
import signal
import subprocess
import sys
import tempfile
import time
import zlib

import numpy as np

# An X client that could not connect (Xvfb refuses some connections under load): not a failure of
# the case, which runs again.
X_REFUSALS = ("bad X server connection", "unable to open display", "cannot connect to X server")
SANITIZER = re.compile(r"ERROR: (AddressSanitizer|LeakSanitizer): ([\w -]+?)(?: on | 0x|$)|"
                       r"runtime error: (.*)")


def pick(rng, choices):
    return choices[int(rng.integers(len(choices)))]


class Case:
    """The random choices of one case. A fuzzer's subclass names its knobs and their
    probabilities in KNOBS, and may keep a knob off in some cases (allows)."""

    KNOBS = {}

    def __init__(self, seed, index, without=()):
        self.seed, self.index, self.without = seed, index, set(without)
        self.active, self.log = [], []

    def rng(self, name):
        """The random stream of the knob or step `name` (the same in every run of the case)."""
        return np.random.default_rng([self.seed, self.index, zlib.crc32(name.encode())])

    def allows(self, name):
        return True

    def knob(self, name):
        """The knob's random stream if it is on in this case, else None. The stream's first
        number decides, whether or not the knob is allowed or switched off."""
        rng = self.rng(name)
        on = rng.random() < self.KNOBS[name] and self.allows(name)
        if not on or name in self.without:
            return None
        self.active.append(name)
        return rng

    def note(self, text):
        self.log.append(text)

    @classmethod
    def active_knobs(cls, seed, index, without=()):
        """The knobs a case would switch on (computed without building it)."""
        case = cls(seed, index, without)
        for name in cls.KNOBS:
            case.knob(name)
        return case.active


# ---------------------------------------------------------------------------------------------
# Worker processes

def serve(setup, run):
    """A worker's loop: setup() (imports, once), then for each line on stdin the answer
    "R <json of run(line)>" on the original stdout, after "READY". Whatever the cases print goes
    to stderr, each case's part after a "=== case <first field>" line; the worker dies with its
    parent, and SIGUSR1 prints its Python stack (the parent asks before killing a hung case)."""
    import ctypes
    import faulthandler
    faulthandler.enable()
    faulthandler.register(signal.SIGUSR1)
    ctypes.CDLL(None).prctl(1, signal.SIGKILL)  # PR_SET_PDEATHSIG: die with the parent
    if os.getppid() == 1:
        return
    answer = os.fdopen(os.dup(1), "w", buffering=1)
    os.dup2(2, 1)  # anything VTK prints goes to stderr
    np.seterr(all="ignore")
    setup()
    answer.write("READY\n")
    for line in sys.stdin:
        line = line.rstrip("\n")
        print("=== case %s" % line.split("\t")[0], file=sys.stderr, flush=True)
        answer.write("R " + json.dumps(run(line), default=str) + "\n")


def case_output(text):
    """A worker's stderr from its last case's "=== case" line on (what that case printed)."""
    lines = text.splitlines()
    start = max([k + 1 for k, line in enumerate(lines) if line.startswith("=== case")] or [0])
    return lines[start:]


class Worker:
    """A worker process (`command`, which calls serve()) and the case it runs."""

    def __init__(self, command, startup):
        self.stderr = tempfile.TemporaryFile()
        self.proc = subprocess.Popen(command, stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                     stderr=self.stderr, start_new_session=True)
        self.buffer, self.task, self.ready = b"", None, False
        self.deadline = time.time() + startup

    def send(self, task, line, timeout):
        self.stderr.seek(0)
        self.stderr.truncate()
        self.task, self.deadline = task, time.time() + timeout
        self.proc.stdin.write((line + "\n").encode())
        self.proc.stdin.flush()

    def lines(self):
        """Complete lines read so far; None at end of file."""
        data = os.read(self.proc.stdout.fileno(), 1 << 16)
        if not data:
            return None
        self.buffer += data
        *complete, self.buffer = self.buffer.split(b"\n")
        return [line.decode(errors="replace") for line in complete]

    def stderr_text(self):
        self.stderr.seek(0)
        return self.stderr.read().decode(errors="replace")

    def kill(self):
        try:
            os.kill(self.proc.pid, signal.SIGUSR1)  # where it hangs, into its stderr
            time.sleep(1.0)
            os.killpg(self.proc.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
        self.proc.wait()


def run_tasks(tasks, jobs, timeout, on_result, stop_at=None, *, command, encode, startup,
              crashed, hung, answered=lambda worker, result: result):
    """Runs `tasks` on `jobs` workers (each started as `command`, given `startup` seconds to say
    READY), one at a time per worker as the line encode(task), each within `timeout` seconds,
    until the tasks run out or the clock passes stop_at; calls on_result(task, result) with the
    worker's answer as answered(worker, result) makes it, or crashed(worker) when the worker died
    during the task, or hung(worker) when it ran out of time (the worker is killed first). A
    worker that dies or stays silent before its first task stops the run (exit status 2): the
    fuzzer itself cannot run."""
    tasks = iter(tasks)
    workers, exhausted = [], False
    while True:
        while len(workers) < jobs and not exhausted:
            workers.append(Worker(command, startup))
        for w in workers:
            if w.ready and w.task is None and not exhausted:
                task = None if stop_at and time.time() > stop_at else next(tasks, None)
                if task is None:
                    exhausted = True
                    break
                w.send(task, encode(task), timeout)
        if exhausted and not any(w.task is not None for w in workers):
            break
        busy = [w for w in workers if w.task is not None or not w.ready]
        if not busy:
            continue
        wait = max(0.0, min(w.deadline for w in busy) - time.time())
        readable, _, _ = select.select([w.proc.stdout for w in busy], [], [], wait)
        for w in list(busy):
            if w.proc.stdout in readable:
                lines = w.lines()
                if lines is None:  # the worker died
                    w.proc.wait()
                    if w.task is None:
                        print("worker failed to start:\n" + w.stderr_text()[-3000:], file=sys.stderr)
                        sys.exit(2)
                    on_result(w.task, crashed(w))
                    workers.remove(w)
                    continue
                for line in lines:
                    if line == "READY":
                        w.ready = True
                    elif line.startswith("R "):
                        task, w.task = w.task, None
                        on_result(task, answered(w, json.loads(line[2:])))
            elif time.time() > w.deadline:
                if w.task is None:
                    print("worker did not start in %.0f s" % startup, file=sys.stderr)
                    sys.exit(2)
                w.kill()
                on_result(w.task, hung(w))
                workers.remove(w)
    for w in workers:
        w.proc.stdin.close()
        w.proc.wait()


def counter(start):
    """start, start + 1, ... (the case indices of a run by time)."""
    while True:
        yield start
        start += 1
