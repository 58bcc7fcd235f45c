// Bindings of the C++ readers and helpers the Python package builds on: depth maps (read, sample), pair directories,
// COLMAP camera models (undistortion) and the pose-error metrics of `madsfm pair`.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <stdexcept>
#include <string>
#include <vector>

#include "bindings.h"
#include "colmap_ext/camera/camera_models.h"
#include "madsfm/geometry/pose_error.h"
#include "madsfm/io/depth_map_io.h"
#include "madsfm/io/depth_sampling.h"
#include "madsfm/io/pair_directory.h"

namespace py = pybind11;

namespace madsfm::python {
namespace {

using DoubleArray = py::array_t<double, py::array::c_style | py::array::forcecast>;
using FloatArray = py::array_t<float, py::array::c_style | py::array::forcecast>;

py::array_t<float> MapToArray(const DepthMap& map) {
  py::array_t<float> out({map.height, map.width});
  std::copy(map.data.begin(), map.data.end(), out.mutable_data());
  return out;
}

DepthMap ArrayToMap(const FloatArray& a) {
  if (a.ndim() != 2) throw py::value_error("depth map must be a 2-D array");
  DepthMap map;
  map.height = static_cast<int>(a.shape(0));
  map.width = static_cast<int>(a.shape(1));
  map.data.assign(a.data(), a.data() + a.size());
  return map;
}

std::vector<Eigen::Vector2d> ArrayToPoints(const DoubleArray& a, const std::string& name) {
  if (a.ndim() != 2 || a.shape(1) != 2) throw py::value_error(name + " must be an N x 2 array");
  std::vector<Eigen::Vector2d> points(a.shape(0));
  for (size_t i = 0; i < points.size(); ++i) points[i] = Eigen::Vector2d(a.data()[2 * i], a.data()[2 * i + 1]);
  return points;
}

py::array_t<double> PointsToArray(const std::vector<Eigen::Vector2d>& points) {
  py::array_t<double> out({static_cast<py::ssize_t>(points.size()), py::ssize_t{2}});
  auto a = out.mutable_unchecked<2>();
  for (size_t i = 0; i < points.size(); ++i) {
    a(i, 0) = points[i].x();
    a(i, 1) = points[i].y();
  }
  return out;
}

py::array_t<double> MatrixToArray(const Eigen::MatrixXd& m) {
  py::array_t<double> out({m.rows(), m.cols()});
  auto a = out.mutable_unchecked<2>();
  for (int i = 0; i < m.rows(); ++i)
    for (int k = 0; k < m.cols(); ++k) a(i, k) = m(i, k);
  return out;
}

// Every C++ reader error is about the file's content (a missing file is caught before, in Python).
DepthMap ReadDepth(const std::string& path) {
  try {
    return ReadDepthMap(path);
  } catch (const std::runtime_error& e) {
    throw py::value_error(e.what());
  }
}

// Samples `depth_map` at `kpts` (pixel centres at integers) of a width x height image; the map must have the
// image's aspect ratio (within 1%, as for pair directories). `name` prefixes errors (the caller's argument name).
py::array_t<double> SampleDepthMap(const FloatArray& depth_map, const DoubleArray& kpts, int width, int height,
                                   const std::string& name) {
  const DepthMap map = ArrayToMap(depth_map);
  const std::vector<Eigen::Vector2d> points = ArrayToPoints(kpts, "kpts");
  try {
    CheckAspectRatio(map, width, height, name);
  } catch (const std::runtime_error& e) {
    // The C++ message reads "depth file '<name>': <problem>"; here there is no file, only an argument.
    std::string what = e.what();
    const std::string prefix = "depth file '" + name + "': ";
    if (what.compare(0, prefix.size(), prefix) == 0) what = name + ": " + what.substr(prefix.size());
    throw py::value_error(what);
  }
  std::vector<double> depths;
  {
    py::gil_scoped_release release;
    depths = SampleDepths(map, points, width, height);
  }
  py::array_t<double> out(static_cast<py::ssize_t>(depths.size()));
  std::copy(depths.begin(), depths.end(), out.mutable_data());
  return out;
}

py::dict ReadPair(const std::string& path, bool allow_missing_depth) {
  PairReadOptions options;
  options.allow_missing_depth = allow_missing_depth;
  const PairData pair = ReadPairDirectory(path, options);
  py::dict d;
  d["path"] = pair.path;
  d["K0"] = MatrixToArray(pair.K0);
  d["K1"] = MatrixToArray(pair.K1);
  d["T_0to1"] = pair.T_0to1 ? py::object(MatrixToArray(*pair.T_0to1)) : py::none();
  d["kpts0"] = PointsToArray(pair.p0);
  d["kpts1"] = PointsToArray(pair.p1);
  d["depth0"] = pair.depth0 ? py::object(MapToArray(*pair.depth0)) : py::none();
  d["depth1"] = pair.depth1 ? py::object(MapToArray(*pair.depth1)) : py::none();
  d["image_size0"] = py::make_tuple(pair.width0, pair.height0);
  d["image_size1"] = py::make_tuple(pair.width1, pair.height1);
  d["warnings"] = pair.warnings;
  return d;
}

// COLMAP models ImageToCamera handles, by name, with their ids and numbers of parameters.
py::dict SupportedCameraModels() {
  py::dict d;
  for (int id = 0; id < 32; ++id) {
    if (colmap::IsSupportedCameraModel(id)) {
      d[py::str(colmap::CameraModelName(id))] = py::make_tuple(id, colmap::CameraModelNumParams(id));
    }
  }
  return d;
}

colmap::CameraIntrinsics Intrinsics(const std::string& model, int width, int height,
                                    const std::vector<double>& params) {
  colmap::CameraIntrinsics camera;
  camera.model_id = colmap::CameraModelId(model);
  camera.width = width;
  camera.height = height;
  camera.params = params;
  return camera;
}

// (fx, fy, cx, cy) of a COLMAP camera, in COLMAP's convention (pixel centres at +0.5).
py::tuple PinholeParams(const std::string& model, const std::vector<double>& params) {
  try {
    const colmap::CameraIntrinsics c = Intrinsics(model, 0, 0, params);
    return py::make_tuple(c.FocalX(), c.FocalY(), c.PrincipalX(), c.PrincipalY());
  } catch (const std::invalid_argument& e) {
    throw py::value_error(e.what());
  }
}

// Undistorts image points (COLMAP convention: pixel centres at +0.5) to normalised camera coordinates.
py::array_t<double> ImageToCamera(const std::string& model, int width, int height, const std::vector<double>& params,
                                  const DoubleArray& points) {
  const colmap::CameraIntrinsics camera = Intrinsics(model, width, height, params);
  std::vector<Eigen::Vector2d> xs = ArrayToPoints(points, "points");
  try {
    py::gil_scoped_release release;
    for (Eigen::Vector2d& x : xs) x = colmap::ImageToCamera(camera, x);
  } catch (const std::invalid_argument& e) {
    throw py::value_error(e.what());
  }
  return PointsToArray(xs);
}

Eigen::Matrix3d ToRotation(const DoubleArray& a, const char* name) {
  if (a.ndim() != 2 || a.shape(0) != 3 || a.shape(1) != 3) throw py::value_error(std::string(name) + " must be 3 x 3");
  Eigen::Matrix3d m;
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) m(i, k) = a.data()[3 * i + k];
  return m;
}

Eigen::Vector3d ToVector3(const DoubleArray& a, const char* name) {
  if (a.size() != 3 || a.ndim() > 2) throw py::value_error(std::string(name) + " must have 3 elements");
  return Eigen::Vector3d(a.data()[0], a.data()[1], a.data()[2]);
}

}  // namespace

void BindIo(py::module_& m) {
  m.def("_read_depth", [](const std::string& path) { return MapToArray(ReadDepth(path)); }, py::arg("path"));
  m.def("_sample_depth", &SampleDepthMap, py::arg("depth_map"), py::arg("kpts"), py::arg("width"), py::arg("height"),
        py::arg("name"));
  m.def("_read_pair_directory", &ReadPair, py::arg("path"), py::arg("allow_missing_depth") = true);
  m.def("_camera_models", &SupportedCameraModels);
  m.def("_camera_pinhole_params", &PinholeParams, py::arg("model"), py::arg("params"));
  m.def("_image_to_camera", &ImageToCamera, py::arg("model"), py::arg("width"), py::arg("height"), py::arg("params"),
        py::arg("points"));
  m.def(
      "rotation_error_deg",
      [](const DoubleArray& R_est, const DoubleArray& R_gt) {
        return RotationErrorDeg(ToRotation(R_est, "R_est"), ToRotation(R_gt, "R_gt"));
      },
      py::arg("R_est"), py::arg("R_gt"), "Angle of R_est R_gt^T in degrees (the metric of `madsfm pair`).");
  m.def(
      "translation_error_deg",
      [](const DoubleArray& t_est, const DoubleArray& t_gt) {
        return TranslationErrorDeg(ToVector3(t_est, "t_est"), ToVector3(t_gt, "t_gt"));
      },
      py::arg("t_est"), py::arg("t_gt"),
      "Angle between the translation directions in degrees, min(theta, 180 - theta); 180 for a zero or non-finite "
      "vector (the metric of `madsfm pair`).");
}

}  // namespace madsfm::python
