"""Shared fixtures of the Python module's tests: where the iaa command and the scenes are, and
running the command to set its outputs against the module's.

Run from the repository (ctest runs it as the test `python`):
    PYTHONPATH=build/python /usr/bin/python3 -m pytest tools/python/tests
IAA_BIN_DIR (default build/bin) names the directory of the iaa command.
"""

import json
import os
import pathlib
import subprocess

import pytest

SOURCE = pathlib.Path(os.environ.get("IAA_SOURCE_DIR", pathlib.Path(__file__).parents[3]))
BIN = pathlib.Path(os.environ.get("IAA_BIN_DIR", SOURCE / "build" / "bin"))


@pytest.fixture(scope="session")
def teardrop():
    return str(SOURCE / "data" / "scenes" / "teardrop.toml")


@pytest.fixture(scope="session")
def chubs():
    return str(SOURCE / "data" / "scenes" / "chubs.toml")


def run_cli(*args):
    """Runs `iaa ARGS...`; returns the completed process (stdout, stderr as text)."""
    return subprocess.run([str(BIN / "iaa"), *map(str, args)], capture_output=True, text=True)


def cli_ok(*args):
    """Runs `iaa ARGS...`, which must succeed; returns its stdout."""
    p = run_cli(*args)
    assert p.returncode == 0, p.stderr
    return p.stdout


def cli_error(*args):
    """The message of a failing `iaa COMMAND ...`, without its 'iaa COMMAND: error: ' prefix."""
    p = run_cli(*args)
    assert p.returncode == 1, (p.returncode, p.stdout, p.stderr)
    prefix = "iaa " + str(args[0]) + ": error: "
    line = p.stderr.strip()
    assert line.startswith(prefix), line
    return line[len(prefix):]


def assert_same_error(cli_args, call):
    """call() raises ValueError with the message of the failing `iaa CLI_ARGS...`."""
    expected = cli_error(*cli_args)
    with pytest.raises(ValueError) as e:
        call()
    assert str(e.value) == expected


def load_json(path):
    with open(path) as f:
        return json.load(f)


def without_times(report):
    """A report without what differs from run to run: wall times."""
    if isinstance(report, dict):
        return {k: without_times(v) for k, v in report.items()
                if not (k.startswith("seconds") or k == "time_s")}
    if isinstance(report, list):
        return [without_times(v) for v in report]
    return report
