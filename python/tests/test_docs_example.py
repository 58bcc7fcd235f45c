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
    # Numbers compared as numbers (the doc shows them rounded as the example prints them), the rest as text.
    assert split_numbers(proc.stdout) == split_numbers(shown), \
        "the estimator's output changed: paste the new output into docs/python.md"


NUMBER = re.compile(r"[-+]?\d+(?:\.\d*)?(?:[eE][-+]?\d+)?")


def split_numbers(text):
    """(text with every number replaced by '#', the numbers as floats)."""
    return NUMBER.sub("#", text), [float(x) for x in NUMBER.findall(text)]


def test_split_numbers_compares_values_not_spelling():
    assert split_numbers("scale 1.50, 3/4 inliers") == split_numbers("scale 1.5, 3/4 inliers")
    assert split_numbers("scale 1.5") != split_numbers("scale 1.6")
    assert split_numbers("scale 1.5") != split_numbers("shift 1.5")
