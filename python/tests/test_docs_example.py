"""docs/python.md shows python/examples/eth3d_pair.py and its real output."""

import re
import subprocess
import sys

from conftest import REPO

DOC = REPO / "docs" / "python.md"
EXAMPLE = REPO / "python" / "examples" / "eth3d_pair.py"


def doc_blocks():
    text = DOC.read_text()
    example = text[text.index("## Example"):]
    return re.findall(r"```(\w*)\n(.*?)```", example, flags=re.S)


def test_doc_shows_the_example_file():
    language, code = doc_blocks()[0]
    assert language == "python"
    assert code == EXAMPLE.read_text()


def test_example_prints_what_the_doc_shows():
    proc = subprocess.run([sys.executable, str(EXAMPLE)], cwd=REPO, capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    language, shown = doc_blocks()[1]
    assert language == ""
    assert proc.stdout == shown, "the estimator's output changed: paste the new output into docs/python.md"
