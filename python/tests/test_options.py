"""madsfm.HybridEstimatorOptions mirrors the C++ struct: same fields, order and defaults; strict typed setters."""

import copy
import pickle
import re
import subprocess

import numpy as np
import pytest

import madsfm
from conftest import REPO

HEADER = REPO / "src" / "madsfm" / "estimators" / "hybrid_estimator_options.h"


def cpp_fields():
    """(name, default) of every HybridEstimatorOptions field, parsed from the C++ header."""
    text = HEADER.read_text()
    body = text[text.index("struct HybridEstimatorOptions {"):]
    body = body[:body.index("\n};")]
    fields = []
    for type_name, name, value in re.findall(r"^\s+(\w+) (\w+) = ([^;]+);", body, flags=re.M):
        if type_name in ("SolverChoice", "ScoringMode"):
            # kPointsOnly -> points_only
            value = re.sub(r"(?<!^)([A-Z])", r"_\1", value.split("::k")[1]).lower()
        elif type_name == "bool":
            value = value == "true"
        elif type_name == "double":
            value = float(value)
        else:
            value = int(value)
        fields.append((name, value))
    assert len(fields) >= 10, "parsing the header went wrong"
    return fields


def test_fields_and_defaults_mirror_the_cpp_header():
    fields = cpp_fields()
    assert madsfm.HybridEstimatorOptions.FIELDS == tuple(name for name, _ in fields)
    assert list(madsfm.HybridEstimatorOptions().to_dict().items()) == fields


def test_defaults_match_the_cli_help(cli):
    help_text = subprocess.run([cli, "pair", "--help"], capture_output=True, text=True, check=True).stdout
    defaults = dict(re.findall(r"--(\w+) (?:NUM|INT)  \(default: ([^)]+)\)", help_text))
    defaults.pop("seed")
    assert len(defaults) >= 8
    options = madsfm.HybridEstimatorOptions()
    for name, value in defaults.items():
        assert getattr(options, name) == float(value), name
    methods = re.search(r"--method TEXT.*\n\s+(.*)\.", help_text).group(1)
    assert madsfm.METHODS == tuple(methods.split(" | "))


def test_repr_shows_every_field_and_round_trips():
    options = madsfm.HybridEstimatorOptions(seed=42, solvers="depth_only", scoring=madsfm.ScoringMode.reprojection_only,
                                            reproj_threshold=16.0, final_refinement=False)
    text = repr(options)
    for name in madsfm.HybridEstimatorOptions.FIELDS:
        assert f"{name}=" in text
    assert "seed=42" in text and "solvers='depth_only'" in text and "final_refinement=False" in text
    assert eval(text, {"HybridEstimatorOptions": madsfm.HybridEstimatorOptions}) == options
    assert options != madsfm.HybridEstimatorOptions()


def test_attributes_are_settable_with_their_types():
    o = madsfm.HybridEstimatorOptions()
    o.reproj_threshold = 12
    o.epipolar_threshold = np.float32(1.5)
    o.min_iterations = np.int64(7)
    o.estimate_shift = np.bool_(False)
    o.seed = 2**64 - 1
    o.solvers = "points_only"
    o.scoring = madsfm.ScoringMode.sampson_only
    assert (o.reproj_threshold, o.epipolar_threshold, o.min_iterations, o.estimate_shift, o.seed) == (
        12.0, 1.5, 7, False, 2**64 - 1)
    assert o.solvers == madsfm.SolverChoice.points_only and o.scoring == madsfm.ScoringMode.sampson_only
    assert o.to_dict()["solvers"] == "points_only"


@pytest.mark.parametrize("name, value, error, message", [
    ("min_iterations", 1.5, TypeError, "HybridEstimatorOptions.min_iterations must be an int, got float (1.5)"),
    ("min_iterations", True, TypeError, "HybridEstimatorOptions.min_iterations must be an int, got bool (True)"),
    ("max_iterations", 2**40, ValueError,
     "HybridEstimatorOptions.max_iterations = 1099511627776 does not fit in a C int"),
    ("reproj_threshold", "8", TypeError, "HybridEstimatorOptions.reproj_threshold must be a float, got str ('8')"),
    ("confidence", 1j, TypeError, "HybridEstimatorOptions.confidence must be a float, got complex (1j)"),
    ("estimate_shift", 1, TypeError, "HybridEstimatorOptions.estimate_shift must be a bool, got int (1)"),
    ("seed", -1, ValueError, "HybridEstimatorOptions.seed = -1 is not in [0, 2**64 - 1]"),
    ("seed", 2**64, ValueError, "HybridEstimatorOptions.seed = 18446744073709551616 is not in [0, 2**64 - 1]"),
    ("seed", 3.0, TypeError, "HybridEstimatorOptions.seed must be a non-negative int, got float (3.0)"),
    ("solvers", "magic", ValueError,
     "HybridEstimatorOptions.solvers: unknown value 'magic' (expected hybrid, depth_only, points_only)"),
    ("scoring", madsfm.SolverChoice.hybrid, TypeError, "HybridEstimatorOptions.scoring must be a name or enum value"),
])
def test_bad_values(name, value, error, message):
    o = madsfm.HybridEstimatorOptions()
    with pytest.raises(error, match=re.escape(message)):
        setattr(o, name, value)
    with pytest.raises(error, match=re.escape(message)):
        madsfm.HybridEstimatorOptions(**{name: value})
    assert o == madsfm.HybridEstimatorOptions(), "a rejected value must leave the options unchanged"


def test_unknown_names():
    with pytest.raises(TypeError, match=re.escape("HybridEstimatorOptions has no option 'max_iteration' (options: "
                                                  "reproj_threshold, epipolar_threshold")):
        madsfm.HybridEstimatorOptions(max_iteration=5)
    o = madsfm.HybridEstimatorOptions()
    with pytest.raises(AttributeError, match="max_iteration"):
        o.max_iteration = 5
    with pytest.raises(TypeError):
        madsfm.HybridEstimatorOptions(8.0)  # fields are keyword-only


def test_check_names_the_invalid_option():
    madsfm.HybridEstimatorOptions().check()
    with pytest.raises(ValueError, match=re.escape("invalid estimator option: num_lo_steps must be >= 0")):
        madsfm.HybridEstimatorOptions(num_lo_steps=-1).check()
    with pytest.raises(ValueError, match="the depth-only solver needs depth residuals"):
        madsfm.HybridEstimatorOptions(solvers="depth_only", scoring="sampson_only").check()


def test_for_method_mirrors_the_cli_methods():
    base = madsfm.HybridEstimatorOptions(seed=9, reproj_threshold=16.0)
    assert madsfm.HybridEstimatorOptions.for_method("hybrid", base) == base
    points = madsfm.HybridEstimatorOptions.for_method("points", base)
    assert (points.solvers, points.scoring, points.seed) == (madsfm.SolverChoice.points_only,
                                                             madsfm.ScoringMode.sampson_only, 9)
    depth = madsfm.HybridEstimatorOptions.for_method("depth_only")
    assert (depth.solvers, depth.scoring) == (madsfm.SolverChoice.depth_only, madsfm.ScoringMode.reprojection_only)
    assert madsfm.HybridEstimatorOptions.for_method("no_shift").estimate_shift is False
    assert madsfm.HybridEstimatorOptions.for_method("sampson_score").scoring == madsfm.ScoringMode.sampson_only
    with pytest.raises(ValueError, match="unknown method 'fast'"):
        madsfm.HybridEstimatorOptions.for_method("fast")


def test_copy_pickle_and_equality():
    o = madsfm.HybridEstimatorOptions(seed=5, scoring="sampson_only", confidence=0.99)
    pickles = [pickle.loads(pickle.dumps(o, protocol=p)) for p in range(pickle.HIGHEST_PROTOCOL + 1)]
    for clone in (copy.copy(o), copy.deepcopy(o), *pickles):
        assert clone == o and clone is not o
    clone = copy.copy(o)
    clone.seed = 6
    assert o.seed == 5 and clone != o
    assert (o == "options") is False
    with pytest.raises(TypeError):
        hash(o)
