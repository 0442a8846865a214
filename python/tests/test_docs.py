"""The Python examples of docs/api.md run as written."""
import pathlib
import re

import pytest

API = pathlib.Path(__file__).resolve().parents[2] / "docs" / "api.md"
BLOCKS = re.findall(r"```python\n(.*?)```", API.read_text(), flags=re.S)


def test_api_md_has_examples():
    assert len(BLOCKS) >= 2


@pytest.mark.parametrize("index", range(len(BLOCKS)))
def test_an_api_md_example_runs_as_written(index, capsys):
    exec(compile(BLOCKS[index], f"docs/api.md example {index + 1}", "exec"), {})
    assert capsys.readouterr().out.strip()
