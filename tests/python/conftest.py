"""Shared fixtures of the Python tests (run by `make test` through CTest, python/CMakeLists.txt).

CTest sets PYTHONPATH to build/python, UASCMA_CLI to the command-line tool of the same build and
UASCMA_SOURCE_DIR to the source tree, so the tests compare the module with the CLI built from the same code.
"""
import json
import os
import subprocess

import pytest

SOURCE_DIR = os.environ.get("UASCMA_SOURCE_DIR", os.path.abspath(os.path.join(os.path.dirname(__file__), "..", "..")))
CLI = os.environ.get("UASCMA_CLI", os.path.join(SOURCE_DIR, "build", "uascma"))


def example(name):
    return os.path.join(SOURCE_DIR, "examples", name)


def run_cli(*args, check=True):
    """Runs the uascma CLI; returns the CompletedProcess (text)."""
    result = subprocess.run([CLI, *map(str, args)], capture_output=True, text=True, timeout=600)
    if check and result.returncode != 0:
        raise AssertionError(f"uascma {' '.join(map(str, args))} exited {result.returncode}: {result.stderr}")
    return result


def cli_json(*args):
    return json.loads(run_cli(*args, "--json").stdout)


@pytest.fixture(scope="session")
def cli():
    if not os.path.isfile(CLI):
        pytest.fail(f"the uascma CLI is missing at {CLI} (build it: make build)")
    return CLI
