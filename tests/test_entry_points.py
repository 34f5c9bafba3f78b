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
    assert set(SCRIPTS) == {"dynnav-train", "dynnav-eval", "dynnav-record", "dynnav-sweep", "dynnav-report"}


@pytest.mark.parametrize("name", sorted(SCRIPTS))
def test_entry_point_answers_help(name):
    script = Path(sys.executable).parent / name
    assert script.is_file(), f"{script} is missing: install the project (pip install -e .) to get {name}"
    done = subprocess.run([str(script), "--help"], cwd=ROOT, capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    assert "usage:" in done.stdout and "--" in done.stdout, done.stdout
    assert "Traceback" not in done.stderr
