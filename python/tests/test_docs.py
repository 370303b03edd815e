"""docs/python.md's examples run as written (the MCU words' block asserts its own); the
scoreboard finds the planted mismatch."""

import contextlib
import io
import re

from conftest import ROOT


def test_the_scoreboard_example_runs_as_written():
    text = (ROOT / "docs" / "python.md").read_text()
    blocks = re.findall(r"```python\n(.*?)```", text, flags=re.S)
    assert len(blocks) == 3, (
        "docs/python.md should hold the scoreboard, the force example and the MCU words"
    )
    printed = []
    for block in blocks:
        out = io.StringIO()
        with contextlib.redirect_stdout(out):
            exec(compile(block, "docs/python.md", "exec"), {"__name__": "docs_example"})
        printed.append(out.getvalue())
    assert printed[0].startswith("(5000, 'position', "), printed[0]
    assert printed[1].startswith("13000 samples, 263 ticks and commands"), printed[1]
    assert printed[2] == "", "the MCU example asserts what it shows"
