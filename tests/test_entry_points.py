"""The command-line entry points of pyproject.toml ([project.scripts]): each is installed next to
the Python that runs the tests, and each answers ``--help``."""

import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
SCRIPTS = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["scripts"]


def test_the_documented_commands_are_declared():
    assert {"dynnav-train", "dynnav-eval", "dynnav-record", "dynnav-sweep", "dynnav-report"} <= set(SCRIPTS)


@pytest.fixture(scope="module")
def helps() -> dict:
    """``<script> --help`` of every installed entry point, run side by side: name -> (exit code,
    stdout, stderr); None for a script that is not installed."""
    started = {}
    for name in SCRIPTS:
        script = Path(sys.executable).parent / name
        if script.is_file():
            started[name] = subprocess.Popen([str(script), "--help"], cwd=ROOT, stdout=subprocess.PIPE,
                                             stderr=subprocess.PIPE, text=True)
    out = dict.fromkeys(SCRIPTS)
    for name, process in started.items():
        stdout, stderr = process.communicate(timeout=300)
        out[name] = (process.returncode, stdout, stderr)
    return out


@pytest.mark.parametrize("name", sorted(SCRIPTS))
def test_entry_point_answers_help(helps, name):
    assert helps[name] is not None, (f"{Path(sys.executable).parent / name} is missing: install the project "
                                     f"again (make setup, or pip install -e .) to get {name}")
    code, out, err = helps[name]
    assert code == 0, err
    assert "usage:" in out and "--" in out, out
    assert "Traceback" not in err
