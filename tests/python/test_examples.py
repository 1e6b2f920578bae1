"""The Python examples (examples/python) run to the end and write what they say they write."""
import os
import shutil
import subprocess
import sys

import pytest

from conftest import SOURCE_DIR

EXAMPLES = os.path.join(SOURCE_DIR, "examples", "python")


def run_example(name, *args, cwd):
    """Runs the example as a user who copied examples/python alone would: from a copy of that folder, with the
    current folder elsewhere (the examples find the scenarios they fly with uascma.example_file)."""
    copy = os.path.join(str(cwd), "copied-examples")
    if not os.path.isdir(copy):
        shutil.copytree(EXAMPLES, copy)
    elsewhere = os.path.join(str(cwd), "elsewhere")
    os.makedirs(elsewhere, exist_ok=True)
    result = subprocess.run([sys.executable, os.path.join(copy, name), *map(str, args)], cwd=elsewhere,
                            capture_output=True, text=True, timeout=600)
    assert result.returncode == 0, result.stderr
    return result.stdout


def test_fly_and_plot(tmp_path):
    out = run_example("fly_and_plot.py", "--out", tmp_path / "flight.png", cwd=tmp_path)
    assert "jam-motor-3" in out
    assert os.path.getsize(tmp_path / "flight.png") > 0


def test_compare_campaign(tmp_path):
    out = run_example("compare_campaign.py", "--db", tmp_path / "c.db", "--runs", 3, cwd=tmp_path)
    assert "failure rate by battery health" in out and "paired runs" in out


def test_solve_with_weights(tmp_path):
    out = run_example("solve_with_weights.py", "--out", tmp_path / "tuned.json", cwd=tmp_path)
    assert "quadrant cells change action" in out
    assert (tmp_path / "tuned.json").is_file()


@pytest.mark.parametrize("scenario", ["jam-motor-3.yaml", "poor-battery-long.yaml"])
def test_python_policy(tmp_path, scenario):
    out = run_example("python_policy.py", os.path.join(SOURCE_DIR, "examples", scenario), cwd=tmp_path)
    assert out.count("\n") == 3 and "cautious (Python)" in out
