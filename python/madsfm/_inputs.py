"""Checks and conversions of the Python API's inputs.

Every error names the offending argument: TypeError for a wrong kind of object or dtype, ValueError for a wrong
shape, length or value. Keypoints use pixel coordinates with pixel centres at integers (the upper-left pixel's
centre is (0, 0)), as the pair directories, hloc and OpenCV do; COLMAP camera dicts keep COLMAP's convention for
their principal point (centres at +0.5) and are converted here.
"""

import functools
import math
import numbers
from typing import NamedTuple, Optional, Tuple

import numpy as np

from . import _madsfm

# Models without distortion: their keypoints go to the estimator as given.
_PINHOLE_MODELS = ("SIMPLE_PINHOLE", "PINHOLE")


def real_array(value, name: str) -> np.ndarray:
    """`value` as a numpy array of a real numeric dtype (ints and floats; not bool, complex, str or object)."""
    if isinstance(value, (str, bytes)):
        raise TypeError(f"{name} must be a numeric array, got {type(value).__name__}")
    try:
        array = np.asarray(value)
    except (ValueError, TypeError) as e:  # ragged nested lists
        raise ValueError(f"{name} could not be converted to a numeric array: {e}") from None
    if array.dtype.kind not in "fiu":
        raise TypeError(f"{name} must be a real-valued numeric array, got dtype {array.dtype}")
    return array


def keypoints(value, name: str) -> np.ndarray:
    """An N x 2 float64 C-contiguous array of finite pixel coordinates."""
    array = real_array(value, name)
    if array.ndim != 2 or array.shape[1] != 2:
        raise ValueError(f"{name} must be an N x 2 array of pixel coordinates, got shape {array.shape}")
    array = np.ascontiguousarray(array, dtype=np.float64)
    bad = np.flatnonzero(~np.isfinite(array).all(axis=1))
    if bad.size:
        raise ValueError(f"{name} has {bad.size} rows with non-finite coordinates (first: row {bad[0]})")
    return array


def image_size(value, name: str) -> Optional[Tuple[int, int]]:
    """(width, height) as positive ints, or None."""
    if value is None:
        return None
    if isinstance(value, (str, bytes)) or not hasattr(value, "__len__") or len(value) != 2:
        raise ValueError(f"{name} must be (width, height), got {value!r}")
    return positive_int(value[0], f"{name}[0] (width)"), positive_int(value[1], f"{name}[1] (height)")


def positive_int(value, name: str) -> int:
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Integral):
        raise TypeError(f"{name} must be a positive integer, got {type(value).__name__} ({value!r})")
    if value <= 0:
        raise ValueError(f"{name} must be a positive integer, got {value}")
    return int(value)


def depth_map(value, name: str) -> np.ndarray:
    """A 2-D float32 C-contiguous depth map; a singleton channel axis, (1, H, W) or (H, W, 1), is squeezed (as the
    C++ reader does). Invalid pixels (non-finite or <= 0) are allowed: the sampler skips them."""
    array = real_array(value, name)
    if array.ndim == 3 and 1 in (array.shape[0], array.shape[2]):
        array = array.reshape(array.shape[1:] if array.shape[0] == 1 else array.shape[:2])
    if array.ndim != 2 or array.size == 0:
        raise ValueError(f"{name} must be a non-empty 2-D depth map (H, W), got shape {array.shape}")
    return np.ascontiguousarray(array, dtype=np.float32)


def keypoint_depths(value, name: str, kpts: np.ndarray, size: Optional[Tuple[int, int]], size_hint: str) -> np.ndarray:
    """Per-keypoint depth priors, float64 of length N (NaN: no prior).

    None: no priors. A 1-D array: one depth per keypoint (NaN, 0 or negative: none; +-inf is an error because it
    usually means a division by zero upstream). A 2-D array: a depth map covering the image, bilinearly sampled at
    the keypoints like `madsfm pair` does (needs the image size).
    """
    n = kpts.shape[0]
    if value is None:
        return np.full(n, np.nan)
    array = real_array(value, name)
    if array.ndim == 1:
        if array.shape[0] != n:
            raise ValueError(f"{name} has {array.shape[0]} values but there are {n} keypoints")
        array = np.ascontiguousarray(array, dtype=np.float64)
        infinite = np.flatnonzero(np.isinf(array))
        if infinite.size:
            raise ValueError(f"{name} has {infinite.size} infinite values (first: index {infinite[0]}); "
                             "use NaN for keypoints without depth")
        return array
    if array.ndim == 2 and n > 1 and array.shape in ((n, 1), (1, n)):
        raise ValueError(f"{name} has shape {array.shape}: give per-keypoint depths as a 1-D array of length {n}, "
                         "or a depth map as (H, W)")
    if array.ndim not in (2, 3):
        raise ValueError(f"{name} must be per-keypoint depths (N,) or a depth map (H, W), got shape {array.shape}")
    array = depth_map(array, name)
    if size is None:
        raise ValueError(f"{name} is a depth map, so the image size is needed to sample it: {size_hint}")
    return _madsfm._sample_depth(array, kpts, size[0], size[1], name)


class Camera(NamedTuple):
    """A camera reduced to what the estimator needs; fx, fy, cx, cy in the keypoints' convention (centres at
    integers)."""
    fx: float
    fy: float
    cx: float
    cy: float
    size: Optional[Tuple[int, int]]
    model: str = "PINHOLE"
    colmap_params: tuple = ()  # the COLMAP params of a distorted model (for undistortion)

    @property
    def distorted(self) -> bool:
        return self.model not in _PINHOLE_MODELS

    def estimator_inputs(self, kpts: np.ndarray, calibrated: bool):
        """(pixel coordinates, (fx, fy, cx, cy)) as madsfm's EstimateRelativePose takes them.

        Undistorted models pass the keypoints unchanged (bit-identical to `madsfm pair` for the same K). Distorted
        ones are undistorted with COLMAP's model (as `madsfm two_view_estimator` does) and re-projected with the
        pinhole part: fx, fy when calibrated, sqrt(fx * fy) in the focal modes. The focal modes see focal 1: only
        the principal point may inform them.
        """
        if self.distorted:
            normalized = _madsfm._image_to_camera(self.model, self.size[0], self.size[1], list(self.colmap_params),
                                                  kpts + 0.5)
            if calibrated:
                kpts = normalized * np.array([self.fx, self.fy]) + np.array([self.cx, self.cy])
            else:
                kpts = normalized * math.sqrt(self.fx * self.fy) + np.array([self.cx, self.cy])
            kpts = np.ascontiguousarray(kpts)
        if calibrated:
            return kpts, (self.fx, self.fy, self.cx, self.cy)
        return kpts, (1.0, 1.0, self.cx, self.cy)


@functools.lru_cache(maxsize=None)
def _camera_models() -> dict:
    """{model name: (COLMAP id, number of params)} of the models the C++ undistortion supports."""
    return _madsfm._camera_models()


def _field(camera, key: str, name: str):
    if isinstance(camera, dict):
        if key not in camera:
            raise ValueError(f"{name} is missing '{key}' (a camera dict needs model, width, height and params)")
        return camera[key]
    return getattr(camera, key)


def _model_name(model, name: str) -> str:
    models = _camera_models()
    if hasattr(model, "name") and not isinstance(model, str):  # pycolmap.CameraModelId
        model = model.name
    if isinstance(model, numbers.Integral) and not isinstance(model, bool):
        by_id = {model_id: model_name for model_name, (model_id, _) in models.items()}
        if model not in by_id:
            raise ValueError(f"{name}: unsupported camera model id {model} (supported: "
                             f"{', '.join(f'{n} ({i})' for n, (i, _) in models.items())})")
        return by_id[model]
    if not isinstance(model, str):
        raise TypeError(f"{name}: 'model' must be a COLMAP model name or id, got {type(model).__name__}")
    if model.upper() not in models:
        raise ValueError(f"{name}: unsupported camera model '{model}' (supported: {', '.join(models)})")
    return model.upper()


def _colmap_camera(value, name: str, size: Optional[Tuple[int, int]], size_name: str) -> Camera:
    model = _model_name(_field(value, "model", name), name)
    width = positive_int(_field(value, "width", name), f"{name}['width']")
    height = positive_int(_field(value, "height", name), f"{name}['height']")
    if size is not None and size != (width, height):
        raise ValueError(f"{size_name} = {size} differs from {name}'s width and height ({width}, {height})")
    params = real_array(_field(value, "params", name), f"{name}['params']")
    num_params = _camera_models()[model][1]
    if params.ndim != 1 or params.shape[0] != num_params:
        raise ValueError(f"{name}: a {model} camera has {num_params} params, got shape {params.shape}")
    if not np.isfinite(params).all():
        raise ValueError(f"{name}['params'] has non-finite values: {params.tolist()}")
    params = tuple(float(p) for p in params)
    fx, fy, cx, cy = _madsfm._camera_pinhole_params(model, list(params))
    if not (fx > 0 and fy > 0):
        raise ValueError(f"{name}: focal lengths must be positive, got fx = {fx}, fy = {fy}")
    # COLMAP puts the upper-left pixel's centre at (0.5, 0.5), the keypoints at (0, 0).
    return Camera(fx, fy, cx - 0.5, cy - 0.5, (width, height), model, params)


def _matrix_camera(value, name: str, size: Optional[Tuple[int, int]]) -> Camera:
    K = real_array(value, name)
    if K.shape != (3, 3):
        raise ValueError(f"{name} must be a camera dict (model, width, height, params) or a 3 x 3 matrix K, "
                         f"got shape {K.shape}")
    K = K.astype(np.float64)
    if not np.isfinite(K).all():
        raise ValueError(f"{name} has non-finite entries: {K.tolist()}")
    if K[2, 0] != 0 or K[2, 1] != 0 or K[2, 2] != 1 or K[1, 0] != 0:
        raise ValueError(f"{name} must look like [[fx, 0, cx], [0, fy, cy], [0, 0, 1]], got {K.tolist()}")
    if K[0, 1] != 0:
        raise ValueError(f"{name} has skew K[0, 1] = {K[0, 1]}, which madsfm does not model")
    if not (K[0, 0] > 0 and K[1, 1] > 0):
        raise ValueError(f"{name}: focal lengths must be positive, got fx = {K[0, 0]}, fy = {K[1, 1]}")
    return Camera(float(K[0, 0]), float(K[1, 1]), float(K[0, 2]), float(K[1, 2]), size)


def camera(value, name: str, size_value, size_name: str) -> Camera:
    """A COLMAP-style camera dict ({"model", "width", "height", "params"}; also a pycolmap.Camera), or a 3 x 3 K in
    the keypoints' convention with the image size from `size_value` (optional)."""
    size = image_size(size_value, size_name)
    if isinstance(value, dict) or all(hasattr(value, k) for k in ("model", "width", "height", "params")):
        return _colmap_camera(value, name, size, size_name)
    if isinstance(value, (np.ndarray, list, tuple)):
        return _matrix_camera(value, name, size)
    raise TypeError(f"{name} must be a camera dict (model, width, height, params) or a 3 x 3 matrix K, "
                    f"got {type(value).__name__}")


def options(value) -> "_madsfm.HybridEstimatorOptions":
    if value is None:
        return _madsfm.HybridEstimatorOptions()
    if isinstance(value, _madsfm.HybridEstimatorOptions):
        return value
    if isinstance(value, dict):
        return _madsfm.HybridEstimatorOptions(**value)
    raise TypeError(f"options must be a madsfm.HybridEstimatorOptions or a dict of its fields, "
                    f"got {type(value).__name__}")
