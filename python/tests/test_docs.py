"""docs/python.md's scoreboard example runs as written and finds the planted mismatch."""

import contextlib
import io
import re

from conftest import ROOT


def test_the_scoreboard_example_runs_as_written():
    text = (ROOT / "docs" / "python.md").read_text()
    blocks = re.findall(r"```python\n(.*?)```", text, flags=re.S)
    assert len(blocks) == 1, "docs/python.md should hold one python example"
    printed = io.StringIO()
    with contextlib.redirect_stdout(printed):
        exec(compile(blocks[0], "docs/python.md", "exec"), {"__name__": "docs_example"})
    assert printed.getvalue().startswith("(5000, 'position', "), printed.getvalue()
