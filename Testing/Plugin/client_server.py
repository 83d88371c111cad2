"""Runs a pvpython client script against a pvserver started for it, each process on an X server
of its own, within a time limit; the server (1 process, or N under mpirun) is stopped in every
case. Like mpi_private_displays.py, a run is tried again only when X refused a connection.

Usage: client_server.py <server ranks> <seconds> <pvserver> <client> [args...]
The client gets "--port <port>" after its arguments, or the port in place of "{port}" where an
argument holds it (e.g. paraview --server-url=cs://localhost:{port}).
"""
import os
import queue
import signal
import socket
import subprocess
import sys
import threading
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from mpi_private_displays import (ATTEMPTS, REFUSALS, mpirun_with_displays,  # noqa: E402
                                  start_server, stop_server)


def free_port():
    with socket.socket() as probe:
        probe.bind(("localhost", 0))
        return probe.getsockname()[1]


def attempt(ranks, seconds, pvserver, client):
    """(client's return code, or None when the server did not start or a process hung; output)."""
    displays = [start_server() for _ in range(ranks + 1)]
    deadline = time.monotonic() + seconds
    server = None
    output = []
    try:
        port = free_port()
        command = [pvserver, f"--server-port={port}"]
        if ranks > 1:
            argv, env = mpirun_with_displays(ranks, command, [name for _, name in displays[1:]])
        else:
            argv, env = command, dict(os.environ, DISPLAY=displays[1][1])
        server = subprocess.Popen(argv, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                  text=True, errors="replace", start_new_session=True)
        lines = queue.Queue()
        threading.Thread(target=lambda: [lines.put(line) for line in server.stdout], daemon=True).start()
        while True:  # until it listens
            try:
                line = lines.get(timeout=max(0.1, deadline - time.monotonic()))
            except queue.Empty:
                return None, "client_server: pvserver did not start listening in time\n" + "".join(output)
            output.append("[server] " + line)
            if "Accepting connection" in line:
                break
            if time.monotonic() > deadline:
                return None, "".join(output)
        if any("{port}" in argument for argument in client):
            command = [argument.replace("{port}", str(port)) for argument in client]
        else:
            command = client + ["--port", str(port)]
        run = subprocess.run(command, env=dict(os.environ, DISPLAY=displays[0][1]),
                             stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                             errors="replace", timeout=max(1.0, deadline - time.monotonic()))
        output.append(run.stdout)
        return run.returncode, "".join(output)
    except subprocess.TimeoutExpired as timeout:
        hung = timeout.output or ""
        output.append(hung.decode(errors="replace") if isinstance(hung, bytes) else hung)
        return None, "".join(output) + f"\nclient_server: the client hung for {seconds:g} s\n"
    finally:
        if server is not None:
            try:
                os.killpg(server.pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
            server.wait()
            while True:  # the server's last words
                try:
                    output.append("[server] " + lines.get_nowait())
                except (queue.Empty, NameError):
                    break
        for process, _ in displays:
            stop_server(process)


def main():
    ranks, seconds = int(sys.argv[1]), float(sys.argv[2])
    pvserver, client = sys.argv[3], sys.argv[4:]
    for number in range(1, ATTEMPTS + 1):
        code, output = attempt(ranks, seconds, pvserver, client)
        print(output, flush=True)
        if not any(text in output for text in REFUSALS):
            sys.exit(1 if code is None else code)
        print(f"client_server: attempt {number} of {ATTEMPTS} refused by X", flush=True)
        time.sleep(1)
    sys.exit(1)


if __name__ == "__main__":
    main()
