"""The module as Python users expect it: Ctrl-C stops long calls, progress reaches a callback, tqdm or
plain lines, the mission importer's notes are Python warnings, `import uascma` loads neither pandas nor NumPy,
and the package carries its types (py.typed, a stub that is Python and names everything the module has)."""
import ast
import os
import signal
import sqlite3
import subprocess
import sys
import time
import types
import warnings

import pytest

import uascma
from conftest import SOURCE_DIR, example, run_cli

MISSION = os.path.join(SOURCE_DIR, "tests", "data", "missions", "delivery_loiter.plan")
STOP_WITHIN_S = 1.0  # s, from SIGINT to the KeyboardInterrupt of run_campaign (its docstring)


def stored_flights(db):
    with sqlite3.connect(db) as connection:
        return connection.execute("SELECT COUNT(*) FROM runs").fetchone()[0]


def test_ctrl_c_stops_a_campaign_and_keeps_its_flights(tmp_path):
    # A child interpreter runs a campaign far longer than the test; SIGINT (what Ctrl-C sends) once flights are
    # stored must end it with a KeyboardInterrupt that counts the flights kept, well before the campaign ends.
    db = tmp_path / "c.db"
    script = (
        "import sys, uascma\n"
        "def progress(done, total):\n"
        "    if done >= 4: print('FLYING', flush=True)\n"
        "try:\n"
        "    uascma.run_campaign(sys.argv[1], sys.argv[2], runs=5000, jobs=1, progress=progress)\n"
        "except KeyboardInterrupt as stop:\n"
        "    print('STOPPED', stop, flush=True)\n"
        "    sys.exit(0)\n"
        "print('FINISHED', flush=True)\n")
    child = subprocess.Popen([sys.executable, "-c", script, example("campaign.yaml"), str(db)],
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        assert child.stdout.readline().startswith("FLYING")
        signalled = time.monotonic()
        child.send_signal(signal.SIGINT)
        line = child.stdout.readline()
        while line.startswith("FLYING"):  # progress reported before the signal was seen
            line = child.stdout.readline()
        stopped_after_s = time.monotonic() - signalled
        out, err = child.communicate(timeout=120)
    finally:
        child.kill()
    assert child.returncode == 0, err
    assert line.startswith("STOPPED"), out + err
    # The documented bound (run_campaign's docstring): the call returns within a second of Ctrl-C, the flights in
    # flight (jobs=1: 4 runs, each by 2 policies) finished and stored.
    assert stopped_after_s < STOP_WITHIN_S, f"stopped {stopped_after_s:.2f} s after SIGINT"
    # "STOPPED <kept> of 10000 flights stored in <db> (...); continue with the same arguments and resume=True"
    kept = int(line.split()[1])
    assert f"of 10000 flights stored in {db}" in line and "resume=True" in line
    assert 4 <= kept < 10000
    assert stored_flights(db) == kept


def test_progress_callback_counts_every_flight(tmp_path):
    calls = []
    outcome = uascma.run_campaign(example("campaign.yaml"), tmp_path / "c.db", runs=3, jobs=1,
                                  progress=lambda done, total: calls.append((done, total)))
    assert calls, "the callback was never called"
    assert all(total == outcome["flights_total"] for _, total in calls)
    done = [d for d, _ in calls]
    assert done == sorted(done) and done[-1] == outcome["flights_total"] == stored_flights(tmp_path / "c.db")


def test_progress_uses_tqdm_when_installed(tmp_path, monkeypatch):
    bars = []

    class FakeTqdm:  # the part of tqdm's API the reporter uses: total, n, update, close
        def __init__(self, total, desc, unit):
            self.total, self.desc, self.unit, self.n, self.closed = total, desc, unit, 0, False
            bars.append(self)

        def update(self, count):
            self.n += count

        def close(self):
            self.closed = True

    package, auto = types.ModuleType("tqdm"), types.ModuleType("tqdm.auto")
    auto.tqdm = FakeTqdm
    package.auto = auto
    monkeypatch.setitem(sys.modules, "tqdm", package)
    monkeypatch.setitem(sys.modules, "tqdm.auto", auto)
    outcome = uascma.run_campaign(example("campaign.yaml"), tmp_path / "c.db", runs=2, jobs=1)
    assert len(bars) == 1 and bars[0].closed and bars[0].unit == "flight"
    assert bars[0].n == bars[0].total == outcome["flights_total"]


def test_progress_lines_every_ten_seconds_or_five_percent(monkeypatch, capsys):
    from uascma import _progress

    clock = [0.0]
    monkeypatch.setattr(_progress.time, "monotonic", lambda: clock[0])
    monkeypatch.setattr(_progress, "make_reporter", _progress.make_reporter)
    lines = _progress._Lines(sys.stdout)

    def at(t, done):
        clock[0] = t
        lines("campaign x, flights", done, 1000, t)
        return capsys.readouterr().out

    assert at(0.0, 0) == ""
    assert at(0.5, 60) == ""          # 6 % but under a second since the last line
    assert "60/1000" in at(1.0, 60)    # 6 %, a second on: a line
    assert at(5.0, 100) == ""         # 4 % more, 4 s on: nothing yet
    assert "105/1000 (10.5 %)" in at(11.0, 105)  # 10 s on: a line whatever the step
    assert "ETA" in _progress.progress_line("x", 105, 1000, 11.0)
    clock[0] = 12.0
    lines("campaign x, flights", 110, 1000, 12.0)
    lines.close()                     # where it ended, for a reader of the log
    assert "110/1000" in capsys.readouterr().out


def test_bad_progress_is_an_input_error(tmp_path):
    with pytest.raises(uascma.InputError, match="progress"):
        uascma.run_campaign(example("campaign.yaml"), tmp_path / "c.db", runs=1, progress="yes")


def test_mission_notes_are_python_warnings_as_the_cli_prints_them(cli, tmp_path):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        uascma.load_scenario(example("nominal.yaml"), mission=MISSION)
    notes = [str(w.message) for w in caught if issubclass(w.category, uascma.MissionWarning)]
    assert issubclass(uascma.MissionWarning, UserWarning)
    result = run_cli("simulate", example("nominal.yaml"), "--mission", MISSION)
    printed = [line[len("warning: "):] for line in result.stderr.splitlines() if line.startswith("warning: ")]
    assert notes and notes == printed


def test_import_loads_neither_pandas_nor_numpy():
    code = "import sys, uascma; print('pandas' in sys.modules, 'numpy' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout.split()
    assert out == ["False", "False"]
    # The lazy names resolve (and then load what they need).
    code = "import sys, uascma; uascma.read_campaign; uascma.Environment; print('pandas' in sys.modules)"
    assert subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout.strip() == "True"


def test_the_package_carries_its_types():
    package = os.path.dirname(uascma.__file__)
    assert os.path.isfile(os.path.join(package, "py.typed"))
    with open(os.path.join(package, "_uascma.pyi")) as f:
        stub = ast.parse(f.read())
    defined = {node.name for node in stub.body if isinstance(node, (ast.ClassDef, ast.FunctionDef))}
    defined |= {node.target.id for node in stub.body if isinstance(node, ast.AnnAssign)}
    public = {name for name in vars(uascma._uascma) if not name.startswith("_")}
    assert public - defined == set()
    # Every method of a class is in the class's stub.
    classes = {node.name: node for node in stub.body if isinstance(node, ast.ClassDef)}
    for name, node in classes.items():
        members = {n.name for n in node.body if isinstance(n, ast.FunctionDef)}
        members |= {n.target.id for n in node.body if isinstance(n, ast.AnnAssign)}
        cls = getattr(uascma._uascma, name)
        expected = {m for m, v in vars(cls).items() if not m.startswith("_") and (callable(v) or isinstance(v, property))}
        if issubclass(cls, BaseException):
            continue
        assert expected - members == set(), name


def test_examples_ship_inside_the_package():
    assert "jam-motor-3.yaml" in uascma.example_files()
    assert uascma.load_scenario(uascma.example_file("jam-motor-3.yaml")).name == uascma.load_scenario(
        example("jam-motor-3.yaml")).name
    with pytest.raises(uascma.InputError, match="jam-motor-3.yaml"):
        uascma.example_file("no-such.yaml")
