"""What the tests of the Python package share: the repository's examples, and the `dynarole`
command they compare the package with (``DYNAROLE``, or the debug build)."""

import json
import os
import pathlib
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
ATRON = ROOT / "robots" / "atron" / "examples"


def command() -> pathlib.Path:
    path = pathlib.Path(os.environ.get("DYNAROLE", ROOT / "target" / "debug" / "dynarole"))
    if not path.exists():
        pytest.fail(f"no dynarole command at {path}: build it (cargo build -p dynarole-cli) or set DYNAROLE")
    return path


def cli(*args, ok=True):
    """Runs ``dynarole ARGS``; its completed process (exit 0 required unless ``ok`` is False)."""
    done = subprocess.run([str(command()), *map(str, args)], capture_output=True, text=True)
    if ok:
        assert done.returncode == 0, done.stderr
    return done


def json_lines(text):
    return [json.loads(line) for line in text.splitlines() if line.strip()]


@pytest.fixture
def eight2car():
    """The paper's eight-to-car sequence, its start and its goal."""
    return ATRON / "eight2car.dr", ATRON / "eight.json", ATRON / "car.json"
