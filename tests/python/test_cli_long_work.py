"""Long work from the command line: with stderr not a terminal a campaign prints plain progress lines
(flights, rate, ETA); Ctrl-C (SIGINT) stops it, stores every finished flight, prints the exact command that
continues it, and exits 130."""
import re
import shlex
import signal
import sqlite3
import subprocess

from conftest import example

LINE = re.compile(r"^campaign (?P<name>\S+), flights: (?P<done>\d+)/(?P<total>\d+) \((?P<percent>[0-9.]+) %\), "
                  r"(?P<rate>[0-9.]+)/s, .+ elapsed, (ETA .+|done)$")


def stored_flights(db):
    with sqlite3.connect(db) as connection:
        return connection.execute("SELECT COUNT(*) FROM runs").fetchone()[0]


def test_progress_lines_then_ctrl_c_stores_and_says_how_to_resume(cli, tmp_path):
    db = tmp_path / "c.db"
    # 800 flights: a line each 5 % (40 flights, a few seconds) or 10 s; stderr is a pipe, not a terminal.
    command = [cli, "campaign", example("campaign.yaml"), "--runs", "400", "--seed", "3", "--db", str(db), "--jobs", "1"]
    child = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        first = child.stderr.readline().rstrip("\n")
        child.send_signal(signal.SIGINT)
        out, err = child.communicate(timeout=120)
    finally:
        child.kill()
    match = LINE.match(first)
    assert match, first
    assert int(match["total"]) == 800 and 0 < int(match["done"]) < 800
    assert child.returncode == 130, err
    lines = err.splitlines()
    summary = next(line for line in lines if line.startswith("uascma: campaign stopped (Ctrl-C): "))
    kept = int(summary.split(": ")[2].split()[0])
    assert stored_flights(db) == kept and int(match["done"]) <= kept < 800
    assert f"of 800 flights stored in {db}" in summary
    resume = lines[lines.index(summary) + 1].strip()
    assert shlex.split(resume) == command + ["--resume"]
    assert out == ""  # no report for a campaign stopped half-way
