"""madsfm.read_depth (the C++ readers) and madsfm.sample_depth (the C++ sampler of `madsfm pair`)."""

import numpy as np
import pytest

import madsfm
from conftest import EXAMPLE_PAIRS


@pytest.fixture
def depth():
    rng = np.random.default_rng(1)
    return rng.uniform(0.5, 10.0, (30, 40)).astype(np.float32)


@pytest.mark.parametrize("dtype", [np.float16, np.float32, np.float64])
def test_read_npy_as_numpy_wrote_it(tmp_path, depth, dtype):
    stored = depth.astype(dtype)
    np.save(tmp_path / "d.npy", stored)
    read = madsfm.read_depth(tmp_path / "d.npy")
    assert read.dtype == np.float32 and read.shape == (30, 40)
    np.testing.assert_array_equal(read, stored.astype(np.float32))


def test_read_npy_layouts_and_invalid_values(tmp_path, depth):
    depth[0, 0], depth[1, 2], depth[2, 3], depth[3, 4] = np.nan, -1.0, 0.0, np.inf  # kept as stored
    np.save(tmp_path / "fortran.npy", np.asfortranarray(depth))
    np.save(tmp_path / "chw.npy", depth[None])
    np.save(tmp_path / "hwc.npy", depth[:, :, None])
    for name in ("fortran.npy", "chw.npy", "hwc.npy"):
        np.testing.assert_array_equal(madsfm.read_depth(str(tmp_path / name)), depth)


def test_read_pfm_rows_bottom_to_top(tmp_path, depth):
    # Grayscale PFM, negative scale = little-endian, rows stored bottom to top.
    with open(tmp_path / "d.pfm", "wb") as f:
        f.write(b"Pf\n40 30\n-1.0\n")
        f.write(depth[::-1].astype("<f4").tobytes())
    np.testing.assert_array_equal(madsfm.read_depth(tmp_path / "d.pfm"), depth)


def test_read_colmap_bin(tmp_path, depth):
    with open(tmp_path / "d.jpg.geometric.bin", "wb") as f:
        f.write(b"40&30&1&")
        f.write(depth.astype("<f4").tobytes())
    np.testing.assert_array_equal(madsfm.read_depth(tmp_path / "d.jpg.geometric.bin"), depth)


def test_read_example_pair_depth():
    path = EXAMPLE_PAIRS / "1_eth3d" / "da-met_depth_0.npy"
    np.testing.assert_array_equal(madsfm.read_depth(path), np.load(path).astype(np.float32))


def bilinear(depth_map, x, y, width, height):
    """Independent reference of the documented sampling (interior points, all neighbours valid)."""
    h, w = depth_map.shape
    u = (x + 0.5) * w / width - 0.5
    v = (y + 0.5) * h / height - 0.5
    u0, v0 = int(np.floor(u)), int(np.floor(v))
    fu, fv = u - u0, v - v0
    m = depth_map.astype(np.float64)
    return ((1 - fv) * ((1 - fu) * m[v0, u0] + fu * m[v0, u0 + 1]) +
            fv * ((1 - fu) * m[v0 + 1, u0] + fu * m[v0 + 1, u0 + 1]))


@pytest.mark.parametrize("image_size", [(40, 30), (80, 60), (400, 300)])
def test_sample_depth_is_bilinear(depth, image_size):
    rng = np.random.default_rng(2)
    width, height = image_size
    kpts = rng.uniform([width * 0.05, height * 0.05], [width * 0.95, height * 0.95], (200, 2))
    sampled = madsfm.sample_depth(depth, kpts, image_size)
    assert sampled.dtype == np.float64 and sampled.shape == (200,)
    expected = [bilinear(depth, x, y, width, height) for x, y in kpts]
    np.testing.assert_allclose(sampled, expected, rtol=1e-12)


def test_sample_depth_at_pixel_centres_returns_the_map(depth):
    ys, xs = np.mgrid[0:30, 0:40]
    kpts = np.stack([xs.ravel(), ys.ravel()], axis=1)
    np.testing.assert_array_equal(madsfm.sample_depth(depth, kpts, (40, 30)), depth.ravel().astype(np.float64))


def test_sample_depth_invalid_is_nan(depth):
    depth[10, 10] = np.nan
    depth[20, 20] = -2.0
    kpts = np.array([[10.0, 10.0], [10.5, 9.5], [20.0, 20.0], [-0.6, 5.0], [5.0, 29.6], [39.5, 29.5], [5.0, 5.0]])
    sampled = madsfm.sample_depth(depth, kpts, (40, 30))
    assert np.isnan(sampled[:5]).all()  # invalid pixel, neighbour of one, negative pixel, outside twice
    assert sampled[5] == depth[29, 39] and sampled[6] == depth[5, 5]  # the corner clamps; interior


def test_sample_depth_accepts_float64_maps_as_float32(depth):
    kpts = np.array([[3.3, 4.7], [20.2, 11.9]])
    np.testing.assert_array_equal(madsfm.sample_depth(depth.astype(np.float64), kpts, (40, 30)),
                                  madsfm.sample_depth(depth, kpts, [40, 30]))
