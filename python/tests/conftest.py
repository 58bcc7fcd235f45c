"""Shared fixtures of the madsfm Python tests.

Run by ctest (tests/CMakeLists.txt: python/...) through python/tests/run_pytest.py, which sets PYTHONPATH to the
build's python/ directory and MADSFM_CLI to the `madsfm` binary of the same build. By hand:
    PYTHONPATH=build/python MADSFM_CLI=build/madsfm /usr/bin/python3 -m pytest -q python/tests
"""

import json
import os
import pathlib
import struct
import subprocess

import numpy as np
import pytest

import madsfm

REPO = pathlib.Path(__file__).resolve().parents[2]
EXAMPLE_PAIRS = pathlib.Path(os.environ.get("MADSFM_EXAMPLE_PAIRS", REPO / "tests" / "data" / "example_pairs"))
# The pairs with depth maps (0_scannet names depth files it does not ship: the point-method fallback).
DEPTH_PAIRS = ("1_eth3d", "2_2d3ds")
MODES = ("calibrated", "shared_focal", "two_focal")
ESTIMATORS = {
    "calibrated": madsfm.estimate_relative_pose,
    "shared_focal": madsfm.estimate_shared_focal_relative_pose,
    "two_focal": madsfm.estimate_two_focal_relative_pose,
}


def png_size(path):
    """(width, height) from a PNG's IHDR chunk."""
    with open(path, "rb") as f:
        header = f.read(24)
    assert header[:8] == b"\x89PNG\r\n\x1a\n", path
    return struct.unpack(">II", header[16:24])


def load_pair_numpy(name):
    """A pair directory read with numpy and json only (not the C++ reader): the inputs a Python user would pass."""
    d = EXAMPLE_PAIRS / name
    info = json.loads((d / "info.json").read_text())
    pair = {"K0": np.array(info["K0"]), "K1": np.array(info["K1"]),
            "kpts0": np.load(d / info["matches_0_file"]), "kpts1": np.load(d / info["matches_1_file"]),
            "image_size0": png_size(d / "image0.png"), "image_size1": png_size(d / "image1.png"),
            "T_0to1": np.array(info["T_0to1"]) if "T_0to1" in info else None}
    for i in (0, 1):
        depth_file = d / info.get(f"depth_{i}_file", "-")
        pair[f"depth{i}"] = np.load(depth_file) if depth_file.is_file() else None
    return pair


@pytest.fixture(scope="session")
def cli():
    path = os.environ.get("MADSFM_CLI", str(REPO / "build" / "madsfm"))
    if not os.access(path, os.X_OK):
        pytest.skip(f"the madsfm command is not at {path} (set MADSFM_CLI)")
    return path


def run_cli_pair(cli_path, pair_dir, *args):
    """`madsfm pair` as a subprocess: (exit code, parsed JSON or None, stderr)."""
    proc = subprocess.run([cli_path, "pair", "--pair_path", str(pair_dir), *args], capture_output=True, text=True,
                          timeout=300)
    return proc.returncode, json.loads(proc.stdout) if proc.stdout.strip() else None, proc.stderr


def _times_transpose(X, M):
    """X @ M.T for N x 3 X and 3 x 3 M, as separate elementwise products and sums (no BLAS, no FMA)."""
    return np.stack([(X[:, 0] * M[r, 0] + X[:, 1] * M[r, 1]) + X[:, 2] * M[r, 2] for r in range(3)], axis=1)


def small_scene(n=30, seed=0, noise=0.0, half_width=1.0):
    """A small exact two-view scene (pixels, depths, K, R, t) for fast repeated calls; points in
    [-half_width, half_width]^2 x [3, 6] in camera 0."""
    rng = np.random.default_rng(seed)
    X0 = rng.uniform([-half_width, -half_width, 3.0], [half_width, half_width, 6.0], (n, 3))
    # The same bits on every CPU: numpy's vectorised cos / sin and its BLAS matrix products (FMA kernels chosen by
    # CPU) differ from one x86-64 machine to the next in the last bits, and an exact scene sits on the knife edge of
    # comparisons between round-off-sized scores. So cos(0.1) / sin(0.1) are the correctly rounded constants, and
    # the products are written out as separate multiplications and additions.
    c, s = float.fromhex("0x1.fd712f9a817c1p-1"), float.fromhex("0x1.98eaecb8bcb2cp-4")  # cos / sin of 0.1 rad
    R = np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])
    t = np.array([0.5, 0.05, 0.1])
    X1 = _times_transpose(X0, R) + t
    K = np.array([[500.0, 0.0, 320.0], [0.0, 500.0, 240.0], [0.0, 0.0, 1.0]])
    k0 = _times_transpose(X0, K)
    k1 = _times_transpose(X1, K)
    kpts0 = k0[:, :2] / k0[:, 2:] + noise * rng.standard_normal((n, 2))
    kpts1 = k1[:, :2] / k1[:, 2:] + noise * rng.standard_normal((n, 2))
    return {"kpts0": kpts0, "kpts1": kpts1, "depth0": X0[:, 2].copy(), "depth1": X1[:, 2] / 2.0, "K": K, "R": R,
            "t": t}


def fast_options(**overrides):
    """Few iterations, no refinement: tens of microseconds per call on small_scene."""
    fields = dict(min_iterations=1, max_iterations=5, num_lo_steps=0, final_refinement=False)
    fields.update(overrides)
    return madsfm.HybridEstimatorOptions(**fields)
