"""The README's Python example runs as written (from a folder with the examples in it)."""
import os
import pathlib
import re

from conftest import EXAMPLES

README = pathlib.Path(__file__).parents[2] / "README.md"


def test_the_readmes_python_example_runs(tmp_path, monkeypatch):
    blocks = re.findall(r"```python\n(.*?)```", README.read_text(), re.S)
    assert blocks, "the README has a Python example"
    os.symlink(EXAMPLES, tmp_path / "examples")
    monkeypatch.chdir(tmp_path)
    for block in blocks:
        exec(compile(block, str(README), "exec"), {})
    assert (tmp_path / "out" / "ex1" / "particles.csv").read_bytes() == (
        tmp_path / "out" / "ex1b" / "particles.csv").read_bytes()
