"""What the Python API's tests share: the CLI beside the module, the shipped examples."""
import os
import pathlib
import subprocess

import pytest

EXAMPLES = pathlib.Path(os.environ.get("AGGPACK_EXAMPLES", pathlib.Path(__file__).parents[2] / "examples"))
AGGPACK_EXE = os.environ.get("AGGPACK_EXE", str(pathlib.Path(__file__).parents[2] / "build" / "aggpack"))


def cli(*args, check=True):
    """Runs the aggpack command; returns (exit code, what it printed)."""
    done = subprocess.run([AGGPACK_EXE, *map(str, args)], capture_output=True, text=True)
    if check and done.returncode != 0:
        raise AssertionError(f"aggpack {' '.join(map(str, args))} exited {done.returncode}:\n{done.stdout}{done.stderr}")
    return done.returncode, done.stdout + done.stderr


@pytest.fixture
def examples():
    return EXAMPLES
