"""The simulated vehicle as a MAVLink v2 endpoint, from a notebook or a script (docs/mavlink.md).

``start_sitl`` starts ``uascma sitl`` (the command-line tool of this build) on a scenario and returns a handle with
the UDP port it listens on; point a ground station, an SDK (pymavlink, MAVSDK, node-mavlink) or your own code at
``udp:127.0.0.1:<port>``::

    from uascma import example_file
    from uascma.mavlink import start_sitl
    with start_sitl(example_file("scenario-1.yaml"), speed=20, wait_for_start=True) as sitl:
        print(sitl.address)      # "udp:127.0.0.1:40123": send a frame there to become a peer
        print(sitl.wait())       # the summary line once the flight and the linger are over

``start_companion`` starts ``uascma companion`` (the CMA as an onboard companion, reading the vehicle's telemetry and
acting through MAVLink) listening on loopback; give it to ``start_sitl`` and the vehicle sends to it and obeys it::

    with start_companion(example_file("scenario-2.yaml"), log="decisions.csv") as cma, \
         start_sitl(example_file("scenario-2.yaml"), speed=20, companion=cma) as sitl:
        print(sitl.wait())       # the vehicle's summary: landed at the site the companion chose
        print(cma.wait())        # the companion's: epochs decided, commands sent, decision time
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
    """A running ``uascma sitl`` (or ``uascma companion``): ``port`` and ``address`` (where it listens), ``process``
    (the Popen), ``wait()`` (its output once it ended), ``stop()``. A context manager: leaving the block stops it."""

    def __init__(self, process, host, port, command="sitl"):
        self.command = command
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

            raise InputError(f"uascma {self.command}: exited {self.process.returncode}: {err.strip()}")
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
               policy=None, timeout_s=30.0, companion=None, wait_for_mission=False):
    """Starts ``uascma sitl SCENARIO --mavlink udp:HOST:PORT`` and returns a :class:`Sitl` once it listens.

    ``port`` 0 lets the system choose (``Sitl.port`` says which). ``speed``: simulated seconds per wall second;
    ``wait_for_start``: stay on the ground until ARM and MISSION_START; ``wait_for_mission``: the same, then fly the
    mission a ground station uploaded instead of the scenario's plan; ``linger_s``: how long the link is served
    after the flight; ``companion``: a :func:`start_companion` handle: the vehicle sends to it too and the CMA is the
    companion's (``--cma external``). InputError when the tool refuses an argument or does not listen within
    ``timeout_s``."""
    args = [_cli(), "sitl", os.fspath(scenario), "--mavlink", f"udp:{host}:{int(port)}", "--speed", str(float(speed)),
            "--system-id", str(int(system_id)), "--linger", str(float(linger_s))]
    if wait_for_start and wait_for_mission:
        from ._uascma import InputError

        raise InputError("start_sitl: wait_for_start, wait_for_mission: one of them (both wait on the ground)")
    if wait_for_start:
        args.append("--wait-for-start")
    if wait_for_mission:
        args.append("--wait-for-mission")
    if policy is not None:
        args += ["--policy", os.fspath(policy)]
    if companion is not None:
        args += ["--cma", "external", "--mavlink", f"udpout:{companion.host}:{companion.port}"]
    return _start(args, "sitl", host, timeout_s)


def start_companion(scenario, policy=None, host="127.0.0.1", port=0, log=None, allow_termination=False,
                    timeout_s=30.0, map_files=(), sites=None):
    """Starts ``uascma companion --mavlink udp:HOST:PORT --scenario SCENARIO`` and returns a handle once it listens.

    ``policy``: the CMA policy (``uascma simulate --policy``'s names; default the scenario's); ``log``: the decision
    log CSV written when it ends (``uascma plot companion LOG`` draws it); ``allow_termination``: send
    DO_FLIGHTTERMINATION when Terminate is taken; ``map_files``, ``sites``: the companion's own building files and
    landing-site CSV in place of the scenario's. It plans on the vehicle's mission, downloaded. It ends when the vehicle
    has landed or been silent for 5 s (docs/mavlink.md#the-cma-as-a-companion)."""
    args = [_cli(), "companion", "--mavlink", f"udp:{host}:{int(port)}", "--scenario", os.fspath(scenario)]
    if policy is not None:
        args += ["--policy", os.fspath(policy)]
    if log is not None:
        args += ["--log", os.fspath(log)]
    if allow_termination:
        args.append("--allow-termination")
    for path in map_files:
        args += ["--map", os.fspath(path)]
    if sites is not None:
        args += ["--sites", os.fspath(sites)]
    return _start(args, "companion", host, timeout_s)


def _start(args, command, host, timeout_s):
    process = subprocess.Popen(args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + timeout_s
    prefix = f"listening on udp:{host}:"
    while time.monotonic() < deadline:
        line = process.stdout.readline()
        if line.startswith(prefix):
            return Sitl(process, host, int(line[len(prefix):]), command)
        if not line and process.poll() is not None:
            break
    process.kill()
    _, err = process.communicate()
    from ._uascma import InputError

    raise InputError(f"start_{command}: uascma {command} did not listen: {err.strip() or 'no output'}")
