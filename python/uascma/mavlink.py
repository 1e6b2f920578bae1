"""The simulated vehicle as a MAVLink v2 endpoint, from a notebook or a script (docs/mavlink.md).

``start_sitl`` starts ``uascma sitl`` (the command-line tool of this build) on a scenario and returns a handle with
the UDP port it listens on; point a ground station, an SDK (pymavlink, MAVSDK, node-mavlink) or your own code at
``udp:127.0.0.1:<port>``::

    from uascma import example_file
    from uascma.mavlink import start_sitl
    with start_sitl(example_file("scenario-1.yaml"), speed=20, wait_for_start=True) as sitl:
        print(sitl.address)      # "udp:127.0.0.1:40123": send a frame there to become a peer
        print(sitl.wait())       # the summary line once the flight and the linger are over

The companion side (the CMA reading an autopilot's telemetry) is not built yet.
"""
import os
import shutil
import subprocess
import time


def _cli():
    path = os.environ.get("UASCMA_CLI")
    if path and os.path.isfile(path):
        return path
    here = os.path.dirname(os.path.abspath(__file__))
    built = os.path.normpath(os.path.join(here, "..", "..", "uascma"))  # build/python/uascma -> build/uascma
    if os.path.isfile(built):
        return built
    found = shutil.which("uascma")
    if found:
        return found
    from ._uascma import InputError

    raise InputError("start_sitl: cli: the uascma command-line tool (set UASCMA_CLI, or build it: make build)")


class Sitl:
    """A running ``uascma sitl``: ``port`` and ``address`` (where it listens), ``process`` (the Popen), ``wait()``
    (its output once it ended), ``stop()``. A context manager: leaving the block stops it."""

    def __init__(self, process, host, port):
        self.process = process
        self.host = host
        self.port = port
        self.address = f"udp:{host}:{port}"
        self._lines = []

    def wait(self, timeout=None):
        """Waits for the run to end; returns its last output line (the summary). InputError when it failed."""
        out, err = self.process.communicate(timeout=timeout)
        self._lines += out.splitlines()
        if self.process.returncode != 0:
            from ._uascma import InputError

            raise InputError(f"uascma sitl: exited {self.process.returncode}: {err.strip()}")
        return self._lines[-1] if self._lines else ""

    def stop(self):
        """Stops the run (SIGTERM, then SIGKILL after 5 s) if it is still going."""
        if self.process.poll() is None:
            self.process.terminate()
            try:
                self.process.wait(timeout=5)
            except subprocess.TimeoutExpired:
                self.process.kill()
                self.process.wait()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.stop()
        for stream in (self.process.stdout, self.process.stderr):
            if stream:
                stream.close()


def start_sitl(scenario, speed=1.0, host="127.0.0.1", port=0, system_id=1, wait_for_start=False, linger_s=2.0,
               policy=None, timeout_s=30.0):
    """Starts ``uascma sitl SCENARIO --mavlink udp:HOST:PORT`` and returns a :class:`Sitl` once it listens.

    ``port`` 0 lets the system choose (``Sitl.port`` says which). ``speed``: simulated seconds per wall second;
    ``wait_for_start``: stay on the ground until ARM and MISSION_START; ``linger_s``: how long the link is served
    after the flight. InputError when the tool refuses an argument or does not listen within ``timeout_s``."""
    args = [_cli(), "sitl", os.fspath(scenario), "--mavlink", f"udp:{host}:{int(port)}", "--speed", str(float(speed)),
            "--system-id", str(int(system_id)), "--linger", str(float(linger_s))]
    if wait_for_start:
        args.append("--wait-for-start")
    if policy is not None:
        args += ["--policy", os.fspath(policy)]
    process = subprocess.Popen(args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + timeout_s
    prefix = f"listening on udp:{host}:"
    while time.monotonic() < deadline:
        line = process.stdout.readline()
        if line.startswith(prefix):
            return Sitl(process, host, int(line[len(prefix):]))
        if not line and process.poll() is not None:
            break
    process.kill()
    _, err = process.communicate()
    from ._uascma import InputError

    raise InputError(f"start_sitl: uascma sitl did not listen: {err.strip() or 'no output'}")
