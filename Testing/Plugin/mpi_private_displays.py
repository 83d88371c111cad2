"""Runs a ParaView command under `mpirun -np N`, each rank on an X server of its own, within a time
limit.

ParaView 5.11 deadlocks under MPI when its ranks disagree on remote rendering: rank 0 waits in
IceT's communicator set-up (vtkIceTCompositePass::Render -> icetCreateMPICommunicator ->
MPI_Comm_dup) while rank 1 waits in ProcessRMIs' barrier, both spinning forever
(../shared/notes/environment.md; seen here with this plugin and with ParaView's own Surface and
Volume). It follows a rank's X connection being refused, and Xvfb refuses connections made at
the same moment, as two ranks on one server make them. So each rank gets its own Xvfb, the run
has a hard time limit (a run that exceeds it is killed and fails), and only a run that X refused
a connection is run again (at most ATTEMPTS times, each said); any other failure, a hang
included, is reported at once.

Usage: mpi_private_displays.py <ranks> <seconds per attempt> <command> [arguments...]
"""
import os
import random
import signal
import subprocess
import sys
import time

ATTEMPTS = 5
REFUSALS = ("bad X server connection", "unable to open display", "cannot connect to X server")
# The X servers run without the sanitizer runtimes the sanitizer build preloads into every test
# (CMakeLists.txt TETDSR_SANITIZE): they are for ParaView and the plugin, not for Xvfb (in that
# build a rank's fresh server refused its connection on all of 3 attempts once, never in the
# release build).
SERVER_ENVIRONMENT = {key: value for key, value in os.environ.items()
                      if key not in ("LD_PRELOAD", "ASAN_OPTIONS", "UBSAN_OPTIONS")}


def start_server(screen="1280x1024x24"):
    """An Xvfb on a display of its own: a random number in [100, 900) without a lock file (not
    the lowest free one, which every other -displayfd user on the machine picks too: two servers
    racing for a stale lock of :0 were seen to leave a rank's connection refused on every
    attempt), ready when it writes its number back through -displayfd; another number if that
    one fails to start. -noreset: without it Xvfb resets when its last client disconnects and
    refuses connections meanwhile (a rank's ParaView opens and closes a display to probe OpenGL
    before it opens its window); measured here (400 open/close cycles on a fresh server: 5 and
    400 refused without it, 0 of 800 with it)."""
    for _ in range(20):
        number = random.randrange(100, 900)
        if os.path.exists(f"/tmp/.X{number}-lock"):
            continue
        read, write = os.pipe()
        server = subprocess.Popen(
            ["Xvfb", f":{number}", "-displayfd", str(write), "-screen", "0", screen,
             "-nolisten", "tcp", "-noreset"],
            pass_fds=(write,), stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=SERVER_ENVIRONMENT)
        os.close(write)
        written = b""
        while not written.endswith(b"\n"):
            chunk = os.read(read, 16)
            if not chunk:
                break
            written += chunk
        os.close(read)
        if written.strip():
            return server, ":" + written.decode().strip()
        stop_server(server)
    raise RuntimeError("mpi_private_displays: Xvfb did not start on 20 displays")


def stop_server(server):
    """Terminates an Xvfb so that it removes its lock file and socket (SIGKILL leaves them for the
    next server to race over); killed if it has not exited within 5 s."""
    server.terminate()
    try:
        server.wait(timeout=5)
    except subprocess.TimeoutExpired:
        server.kill()
        server.wait()


def mpirun_with_displays(ranks, command, displays):
    """The mpirun command line and environment that run `command` on `ranks` ranks, each with
    DISPLAY set to its own of `displays`."""
    # Each rank picks its display by its rank (Open MPI's OMPI_COMM_WORLD_RANK).
    env = dict(os.environ, TETDSR_RANK_DISPLAYS=" ".join(displays))
    # sh -c '...' takes the command as $0 and its arguments as "$@".
    launcher = ["sh", "-c", 'DISPLAY=$(echo $TETDSR_RANK_DISPLAYS | cut -d" " '
                '-f$((OMPI_COMM_WORLD_RANK + 1))); export DISPLAY; exec "$0" "$@"']
    mpirun = ["mpirun", "--allow-run-as-root", "--oversubscribe", "-np", str(ranks)]
    return mpirun + launcher + list(command), env


def attempt(ranks, seconds, command):
    """(return code or None on a hang, output)."""
    servers = [start_server() for _ in range(ranks)]
    try:
        argv, env = mpirun_with_displays(ranks, command, [name for _, name in servers])
        run = subprocess.Popen(argv, env=env,
                               stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                               errors="replace", start_new_session=True)
        try:
            output, _ = run.communicate(timeout=seconds)
            return run.returncode, output
        except subprocess.TimeoutExpired:
            os.killpg(run.pid, signal.SIGKILL)
            output, _ = run.communicate()
            return None, output
    finally:
        for server, _ in servers:
            stop_server(server)


def run(ranks, seconds, command, log=sys.stdout):
    """Runs `command` under mpirun until an attempt is not refused by X (at most ATTEMPTS):
    (exit code, [(outcome, seconds) per attempt]) with outcome "passed", "failed", "hung" or
    "refused by X". A hang is a failure, not retried, unless X refused a connection first."""
    attempts = []
    for number in range(1, ATTEMPTS + 1):
        start = time.monotonic()
        code, output = attempt(ranks, seconds, command)
        elapsed = time.monotonic() - start
        log.write(output)
        log.flush()
        refused = code != 0 and any(text in output for text in REFUSALS)
        if not refused:
            outcome = "passed" if code == 0 else "hung" if code is None else "failed"
            attempts.append((outcome, elapsed))
            if code is None:
                print(f"mpi_private_displays: hung for {seconds:g} s, killed (not retried: no X "
                      f"connection was refused)", file=log, flush=True)
            return (1 if code is None else code), attempts
        attempts.append(("refused by X", elapsed))
        print(f"mpi_private_displays: attempt {number} of {ATTEMPTS} refused by X", file=log,
              flush=True)
        time.sleep(1)
    return 1, attempts


def main():
    ranks, seconds, command = int(sys.argv[1]), float(sys.argv[2]), sys.argv[3:]
    code, _ = run(ranks, seconds, command)
    sys.exit(code)


if __name__ == "__main__":
    main()
