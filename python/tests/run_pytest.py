"""Runs madsfm's pytest files for ctest (tests/CMakeLists.txt registers one test per file).

    python3 run_pytest.py BUILD_PYTHON_DIR [pytest arguments...]

Exits 77 (ctest's SKIP_RETURN_CODE) with the reason when numpy, pytest or the module of this build is missing,
e.g. in a sanitizer build, where the module is not built.
"""

import os
import sys

SKIP = 77


def main(argv):
    if len(argv) < 2:
        print(__doc__)
        return 2
    build_python = os.path.realpath(argv[1])
    sys.path.insert(0, build_python)
    try:
        import numpy  # noqa: F401
        import pytest
    except ImportError as e:
        print(f"SKIP: {e} (Debian: apt-get install python3-numpy python3-pytest; run with /usr/bin/python3)")
        return SKIP
    try:
        import madsfm
    except ImportError as e:
        print(f"SKIP: the madsfm module is not built in {build_python} ({e}); see docs/python.md")
        return SKIP
    if not os.path.realpath(madsfm.__file__).startswith(build_python + os.sep):
        print(f"SKIP: the madsfm module is not built in {build_python} (found {madsfm.__file__} instead)")
        return SKIP
    # The tests' subprocesses (python3 -m madsfm.pair) must import the same module.
    os.environ["PYTHONPATH"] = os.pathsep.join(p for p in (build_python, os.environ.get("PYTHONPATH")) if p)
    sys.dont_write_bytecode = True  # keep the source tree clean
    return pytest.main(["-q", "-p", "no:cacheprovider", "--rootdir", os.path.dirname(__file__), *argv[2:]])


if __name__ == "__main__":
    sys.exit(main(sys.argv))
