"""The README's Python example runs and returns what the text says it returns."""

import re
from pathlib import Path

README = Path(__file__).resolve().parents[1] / "README.md"


def test_the_python_example_runs():
    blocks = re.findall(r"```python\n(.*?)```", README.read_text(), flags=re.S)
    assert blocks, "the README has no Python example"
    scope: dict = {}
    for block in blocks:
        exec(compile(block, str(README), "exec"), scope)
    scores = scope["scores"]
    assert len(scores) == 1 and set(scores[0]) == {"ckf", "fkf", "lkf"}
    assert all(v.shape == (20, 30) for v in scores[0].values())
