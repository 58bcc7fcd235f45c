// The _madsfm extension: estimator options, the estimation entry point and its result. Input checking, cameras and
// depth sampling live in the Python package (madsfm/_inputs.py, madsfm/_api.py), which hands this module clean
// float64 arrays.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "madsfm/estimators/estimate_relpose.h"
#include "madsfm/estimators/pair_evaluation.h"
#include "bindings.h"

namespace py = pybind11;

namespace madsfm::python {
namespace {

// Every field of HybridEstimatorOptions in declaration order: X(name). Binding, repr, to_dict and the keyword
// constructor all expand this list, so a field cannot be bound without also being shown and settable.
#define MADSFM_OPTION_FIELDS(X)                                                                                   \
  X(reproj_threshold) X(epipolar_threshold) X(sampson_weight) X(solvers) X(scoring) X(estimate_shift)             \
  X(sampson_cheirality) X(cheirality_min_parallax) X(min_iterations) X(min_iterations_two_focal_points)           \
  X(min_iterations_shared_focal_points) X(max_iterations) X(confidence) X(guided_sampling_fraction)               \
  X(num_lo_steps) X(num_lo_lsq_steps)                                                                             \
  X(lo_threshold_multiplier) X(lo_inner_sample_multiplier) X(lo_lsq_sample_size) X(lo_first_fit_sample_size)      \
  X(lo_starting_iterations)                                                                                       \
  X(alt_basin_lo_margin) X(lo_skip_same_basin) X(planar_twin_min_support) X(low_parallax_sampson_factor)          \
  X(low_parallax_noise_ratio) X(low_parallax_final_reprojection_weight)                                           \
  X(mixed_refinement_depth_from_triangulation) X(lo_max_lm_iterations)                                            \
  X(lo_max_lm_iterations_two_focal) X(final_refinement) X(final_max_lm_iterations)                                \
  X(final_reprojection_weight) X(epipolar_focal_max_sigma) X(epipolar_focal_wide_sigma) X(final_cauchy_ratio)     \
  X(epipolar_check_ratio) X(retry_depth_less) X(scale_only_fallback) X(max_shift_ratio) X(final_depth_fit)        \
  X(depth_fit_regression) X(low_parallax_depth_fit_regression) X(depth_fit_regression_in_bound)                  \
  X(focal_depth_from_joint) X(max_depth_sigma) X(seed)

const char* SolverChoiceName(SolverChoice c) {
  switch (c) {
    case SolverChoice::kHybrid: return "hybrid";
    case SolverChoice::kDepthOnly: return "depth_only";
    case SolverChoice::kPointsOnly: return "points_only";
  }
  return "unknown";
}

const char* ScoringModeName(ScoringMode s) {
  switch (s) {
    case ScoringMode::kHybrid: return "hybrid";
    case ScoringMode::kReprojectionOnly: return "reprojection_only";
    case ScoringMode::kSampsonOnly: return "sampson_only";
  }
  return "unknown";
}

std::string TypeName(py::handle value) { return py::str(py::type::handle_of(value).attr("__name__")); }

[[noreturn]] void BadType(const char* field, const char* expected, py::handle value) {
  throw py::type_error(std::string("HybridEstimatorOptions.") + field + " must be " + expected + ", got " +
                       TypeName(value) + " (" + std::string(py::repr(value)) + ")");
}

bool IsBool(py::handle value) {
  // numpy.bool_ is not a Python bool subclass; accept it by name rather than importing numpy here.
  if (PyBool_Check(value.ptr())) return true;
  const std::string name = TypeName(value);
  if (name != "bool_" && name != "bool") return false;  // numpy 1.x: bool_, numpy 2: bool
  return std::string(py::str(py::type::handle_of(value).attr("__module__"))) == "numpy";
}

// Typed conversion of a Python value to an option field. Strict on purpose: 1.5 is not an int, True is not a
// number, 5 is not a bool, so that a misplaced argument fails loudly instead of being coerced.
void SetOption(const char* field, double* out, py::handle value) {
  if (IsBool(value) || !PyNumber_Check(value.ptr()) || PyComplex_Check(value.ptr())) BadType(field, "a float", value);
  try {
    *out = value.cast<double>();
  } catch (const py::cast_error&) {
    BadType(field, "a float", value);
  }
}

long long IndexValue(const char* field, const char* expected, py::handle value) {
  if (IsBool(value) || !PyIndex_Check(value.ptr())) BadType(field, expected, value);
  py::int_ index = py::reinterpret_steal<py::int_>(PyNumber_Index(value.ptr()));
  int overflow = 0;
  const long long v = PyLong_AsLongLongAndOverflow(index.ptr(), &overflow);
  if (overflow) throw py::value_error(std::string("HybridEstimatorOptions.") + field + " is out of range");
  return v;
}

void SetOption(const char* field, int* out, py::handle value) {
  const long long v = IndexValue(field, "an int", value);
  if (v < std::numeric_limits<int>::min() || v > std::numeric_limits<int>::max()) {
    throw py::value_error(std::string("HybridEstimatorOptions.") + field + " = " + std::to_string(v) +
                          " does not fit in a C int");
  }
  *out = static_cast<int>(v);
}

void SetOption(const char* field, uint64_t* out, py::handle value) {
  if (IsBool(value) || !PyIndex_Check(value.ptr())) BadType(field, "a non-negative int", value);
  py::int_ index = py::reinterpret_steal<py::int_>(PyNumber_Index(value.ptr()));
  const unsigned long long v = PyLong_AsUnsignedLongLong(index.ptr());
  if (PyErr_Occurred()) {
    PyErr_Clear();
    throw py::value_error(std::string("HybridEstimatorOptions.") + field + " = " + std::string(py::repr(value)) +
                          " is not in [0, 2**64 - 1]");
  }
  *out = v;
}

void SetOption(const char* field, bool* out, py::handle value) {
  if (!IsBool(value)) BadType(field, "a bool", value);
  *out = value.cast<bool>();
}

// Enums accept their Python enum value or its name ("points_only").
template <typename Enum>
void SetEnumOption(const char* field, Enum* out, py::handle value, const char* (*name_of)(Enum),
                   std::initializer_list<Enum> all) {
  if (py::isinstance<Enum>(value)) {
    *out = value.cast<Enum>();
    return;
  }
  if (!py::isinstance<py::str>(value)) BadType(field, "a name or enum value", value);
  const std::string name = value.cast<std::string>();
  std::string names;
  for (Enum e : all) {
    if (name == name_of(e)) {
      *out = e;
      return;
    }
    names += std::string(names.empty() ? "" : ", ") + name_of(e);
  }
  throw py::value_error(std::string("HybridEstimatorOptions.") + field + ": unknown value '" + name + "' (expected " +
                        names + ")");
}

void SetOption(const char* field, SolverChoice* out, py::handle value) {
  SetEnumOption(field, out, value, SolverChoiceName,
                {SolverChoice::kHybrid, SolverChoice::kDepthOnly, SolverChoice::kPointsOnly});
}

void SetOption(const char* field, ScoringMode* out, py::handle value) {
  SetEnumOption(field, out, value, ScoringModeName,
                {ScoringMode::kHybrid, ScoringMode::kReprojectionOnly, ScoringMode::kSampsonOnly});
}

// Python value of a field: enums as their names in to_dict (JSON-friendly), as enum objects for attribute access.
template <typename T>
py::object PlainValue(const T& v) { return py::cast(v); }
py::object PlainValue(SolverChoice v) { return py::str(SolverChoiceName(v)); }
py::object PlainValue(ScoringMode v) { return py::str(ScoringModeName(v)); }

const std::vector<std::string>& OptionNames() {
#define MADSFM_NAME(field) #field,
  static const std::vector<std::string> names = {MADSFM_OPTION_FIELDS(MADSFM_NAME)};
#undef MADSFM_NAME
  return names;
}

std::string JoinNames() {
  std::string out;
  for (const std::string& n : OptionNames()) out += (out.empty() ? "" : ", ") + n;
  return out;
}

// Sets one option by name; unknown names are a TypeError, as for any unexpected keyword argument.
void SetOptionByName(HybridEstimatorOptions* o, const std::string& name, py::handle value) {
#define MADSFM_SET(field)                     \
  if (name == #field) {                       \
    SetOption(#field, &o->field, value);      \
    return;                                   \
  }
  MADSFM_OPTION_FIELDS(MADSFM_SET)
#undef MADSFM_SET
  throw py::type_error("HybridEstimatorOptions has no option '" + name + "' (options: " + JoinNames() + ")");
}

py::dict OptionsToDict(const HybridEstimatorOptions& o) {
  py::dict d;
#define MADSFM_GET(field) d[#field] = PlainValue(o.field);
  MADSFM_OPTION_FIELDS(MADSFM_GET)
#undef MADSFM_GET
  return d;
}

std::string OptionsRepr(const HybridEstimatorOptions& o) {
  std::string out = "HybridEstimatorOptions(";
  bool first = true;
  for (auto item : OptionsToDict(o)) {
    out += std::string(first ? "" : ", ") + std::string(py::str(item.first)) + "=" + std::string(py::repr(item.second));
    first = false;
  }
  return out + ")";
}

HybridEstimatorOptions OptionsFromKwargs(const py::kwargs& kwargs) {
  HybridEstimatorOptions o;
  for (auto item : kwargs) SetOptionByName(&o, item.first.cast<std::string>(), item.second);
  return o;
}

// pybind11's pickle support alone (__getstate__ / __setstate__) aborts the interpreter with pickle protocols 0 and 1
// (copyreg cannot allocate a pybind11 instance). __reduce__ hands pickle madsfm._api._unpickle(cls, state) instead,
// which allocates with cls.__new__ and then calls __setstate__: every protocol works.
py::tuple Reduce(const py::object& self) {
  return py::make_tuple(py::module_::import("madsfm._api").attr("_unpickle"),
                        py::make_tuple(py::type::of(self), self.attr("__getstate__")()));
}

void BindOptions(py::module_& m) {
  py::enum_<SolverChoice>(m, "SolverChoice", "Which minimal solvers the RANSAC loop draws from.")
      .value("hybrid", SolverChoice::kHybrid)
      .value("depth_only", SolverChoice::kDepthOnly)
      .value("points_only", SolverChoice::kPointsOnly);
  py::enum_<ScoringMode>(m, "ScoringMode", "Which data types score hypotheses and enter the local optimisation.")
      .value("hybrid", ScoringMode::kHybrid)
      .value("reprojection_only", ScoringMode::kReprojectionOnly)
      .value("sampson_only", ScoringMode::kSampsonOnly);

  py::class_<HybridEstimatorOptions> options(
      m, "HybridEstimatorOptions",
      "Options of the hybrid LO-MSAC estimator: the fields and defaults of the C++ struct\n"
      "madsfm::HybridEstimatorOptions (src/madsfm/estimators/hybrid_estimator_options.h).\n"
      "HybridEstimatorOptions(**fields); unknown names raise TypeError, values of the wrong type TypeError.");
  options.def(py::init(&OptionsFromKwargs))
      .def_static("for_method", [](const std::string& method, const HybridEstimatorOptions* base) {
            return OptionsForMethod(method, base ? *base : HybridEstimatorOptions());
          }, py::arg("method"), py::arg("base") = nullptr,
          "The options `madsfm pair --method METHOD` runs (hybrid, points, depth_only, no_shift, sampson_score).")
      .def("check", &HybridEstimatorOptions::Check, "Raises ValueError naming the first invalid option.")
      .def("to_dict", &OptionsToDict, "All fields by name (enums as their names).")
      .def("__repr__", &OptionsRepr)
      .def("__eq__", [](const HybridEstimatorOptions& a, py::object b) -> py::object {
            if (!py::isinstance<HybridEstimatorOptions>(b)) {
              return py::reinterpret_borrow<py::object>(Py_NotImplemented);
            }
            return py::bool_(OptionsToDict(a).equal(OptionsToDict(b.cast<const HybridEstimatorOptions&>())));
          })
      .def("__copy__", [](const HybridEstimatorOptions& o) { return o; })
      .def("__deepcopy__", [](const HybridEstimatorOptions& o, py::dict) { return o; }, py::arg("memo"))
      .def(py::pickle([](const HybridEstimatorOptions& o) { return OptionsToDict(o); },
                      [](const py::dict& d) {
                        HybridEstimatorOptions o;
                        for (auto item : d) SetOptionByName(&o, item.first.cast<std::string>(), item.second);
                        return o;
                      }));
  options.def("__reduce__", [](py::object self) { return Reduce(self); });
  options.attr("__hash__") = py::none();  // mutable and compared by value
  options.attr("FIELDS") = py::tuple(py::cast(OptionNames()));
#define MADSFM_PROPERTY(field)                                                                            \
  options.def_property(                                                                                   \
      #field, [](const HybridEstimatorOptions& o) { return o.field; },                                    \
      [](HybridEstimatorOptions& o, py::handle v) { SetOption(#field, &o.field, v); });
  MADSFM_OPTION_FIELDS(MADSFM_PROPERTY)
#undef MADSFM_PROPERTY
}

// ---- the result ----

struct RelativePoseResult {
  HybridEstimate estimate;
  std::string camera_mode, method;
  std::vector<std::string> notes;
  int num_matches = 0, num_matches_with_depth = 0;
};

double ModelValue(const RelativePoseResult& r, double v) {
  return r.estimate.success ? v : std::numeric_limits<double>::quiet_NaN();
}

py::array_t<double> Rotation(const RelativePoseResult& r) {
  py::array_t<double> out({3, 3});
  auto a = out.mutable_unchecked<2>();
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) a(i, k) = ModelValue(r, r.estimate.model.R(i, k));
  return out;
}

py::array_t<double> Translation(const RelativePoseResult& r) {
  py::array_t<double> out(3);
  auto a = out.mutable_unchecked<1>();
  for (int i = 0; i < 3; ++i) a(i) = ModelValue(r, r.estimate.model.t(i));
  return out;
}

// An inlier mask over all matches; all False when the estimator stopped before computing one.
py::array_t<bool> Mask(const RelativePoseResult& r, const std::vector<char>& mask) {
  py::array_t<bool> out(r.num_matches);
  bool* p = out.mutable_data();
  for (int i = 0; i < r.num_matches; ++i) p[i] = i < static_cast<int>(mask.size()) && mask[i] != 0;
  return out;
}

// (name, getter) of every result attribute, in the order repr and to_dict show them.
using ResultGetter = py::object (*)(const RelativePoseResult&);
const std::vector<std::pair<const char*, ResultGetter>>& ResultFields() {
  using R = const RelativePoseResult&;
  static const std::vector<std::pair<const char*, ResultGetter>> fields = {
      {"success", [](R r) -> py::object { return py::bool_(r.estimate.success); }},
      {"camera_mode", [](R r) -> py::object { return py::str(r.camera_mode); }},
      {"method", [](R r) -> py::object { return py::str(r.method); }},
      {"R", [](R r) -> py::object { return Rotation(r); }},
      {"t", [](R r) -> py::object { return Translation(r); }},
      {"scale", [](R r) -> py::object { return py::float_(ModelValue(r, r.estimate.model.scale)); }},
      {"shift0", [](R r) -> py::object { return py::float_(ModelValue(r, r.estimate.model.shift0)); }},
      {"shift1", [](R r) -> py::object { return py::float_(ModelValue(r, r.estimate.model.shift1)); }},
      // Calibrated: the cameras' sqrt(fx * fy), known even when the estimate failed.
      {"f0", [](R r) -> py::object {
         return py::float_(r.camera_mode == "calibrated" ? r.estimate.model.f0 : ModelValue(r, r.estimate.model.f0));
       }},
      {"f1", [](R r) -> py::object {
         return py::float_(r.camera_mode == "calibrated" ? r.estimate.model.f1 : ModelValue(r, r.estimate.model.f1));
       }},
      {"num_matches", [](R r) -> py::object { return py::int_(r.num_matches); }},
      {"num_matches_with_depth", [](R r) -> py::object { return py::int_(r.num_matches_with_depth); }},
      {"inliers_reproj0", [](R r) -> py::object { return Mask(r, r.estimate.inliers_reproj0); }},
      {"inliers_reproj1", [](R r) -> py::object { return Mask(r, r.estimate.inliers_reproj1); }},
      {"inliers_sampson", [](R r) -> py::object { return Mask(r, r.estimate.inliers_sampson); }},
      {"num_inliers_reproj0", [](R r) -> py::object { return py::int_(r.estimate.num_inliers_reproj0); }},
      {"num_inliers_reproj1", [](R r) -> py::object { return py::int_(r.estimate.num_inliers_reproj1); }},
      {"num_inliers_sampson", [](R r) -> py::object { return py::int_(r.estimate.num_inliers_sampson); }},
      {"score", [](R r) -> py::object { return py::float_(r.estimate.score); }},
      {"iterations", [](R r) -> py::object { return py::int_(r.estimate.iterations); }},
      {"num_lo", [](R r) -> py::object { return py::int_(r.estimate.num_lo); }},
      {"num_depth_samples", [](R r) -> py::object { return py::int_(r.estimate.num_depth_samples); }},
      {"num_point_samples", [](R r) -> py::object { return py::int_(r.estimate.num_point_samples); }},
      {"epipolar_check_switched", [](R r) -> py::object { return py::bool_(r.estimate.epipolar_check_switched); }},
      {"depth_observable", [](R r) -> py::object { return py::bool_(r.estimate.depth_observable); }},
      {"sigma_scale", [](R r) -> py::object { return py::float_(r.estimate.sigma_scale); }},
      {"sigma_shift0", [](R r) -> py::object { return py::float_(r.estimate.sigma_shift0); }},
      {"sigma_shift1", [](R r) -> py::object { return py::float_(r.estimate.sigma_shift1); }},
      {"shifts_dropped", [](R r) -> py::object { return py::bool_(r.estimate.shifts_dropped); }},
      {"scale_reset", [](R r) -> py::object { return py::bool_(r.estimate.scale_reset); }},
      {"low_parallax_weighting", [](R r) -> py::object { return py::bool_(r.estimate.low_parallax_weighting); }},
      {"sigma_focal0", [](R r) -> py::object { return py::float_(r.estimate.sigma_focal0); }},
      {"sigma_focal1", [](R r) -> py::object { return py::float_(r.estimate.sigma_focal1); }},
      {"runtime_ms", [](R r) -> py::object { return py::float_(r.estimate.runtime_ms); }},
      {"notes", [](R r) -> py::object { return py::cast(r.notes); }},
  };
  return fields;
}

std::string ResultRepr(const RelativePoseResult& r) {
  const HybridEstimate& e = r.estimate;
  std::string out = "RelativePoseResult(success=" + std::string(e.success ? "True" : "False") + ", camera_mode='" +
                    r.camera_mode + "', method='" + r.method + "'";
  char buf[512];
  if (e.success) {
    const Eigen::Vector3d& t = e.model.t;
    std::snprintf(buf, sizeof(buf), ", t=[%.6g, %.6g, %.6g], scale=%.6g, shift0=%.6g, shift1=%.6g, f0=%.6g, f1=%.6g",
                  t.x(), t.y(), t.z(), e.model.scale, e.model.shift0, e.model.shift1, e.model.f0, e.model.f1);
    out += buf;
  }
  std::snprintf(buf, sizeof(buf),
                ", inliers reproj0/reproj1/sampson=%d/%d/%d of %d matches (%d with depth), iterations=%d, "
                "runtime_ms=%.3g",
                e.num_inliers_reproj0, e.num_inliers_reproj1, e.num_inliers_sampson, r.num_matches,
                r.num_matches_with_depth, e.iterations, e.runtime_ms);
  out += buf;
  if (!r.notes.empty()) out += ", notes=" + std::string(py::repr(py::cast(r.notes)));
  return out + ")";
}

// Pickling: every member of the result as it is stored (the model also when the estimate failed, the masks as bytes),
// so that a round trip gives back the same object bit for bit.
py::bytes MaskBytes(const std::vector<char>& mask) { return py::bytes(mask.data(), mask.size()); }

std::vector<char> MaskFromBytes(const py::handle& b) {
  const std::string s = b.cast<std::string>();
  return std::vector<char>(s.begin(), s.end());
}

py::dict ResultState(const RelativePoseResult& r) {
  const HybridEstimate& e = r.estimate;
  py::dict d;
  d["version"] = 1;
  d["camera_mode"] = r.camera_mode;
  d["method"] = r.method;
  d["notes"] = r.notes;
  d["num_matches"] = r.num_matches;
  d["num_matches_with_depth"] = r.num_matches_with_depth;
  d["success"] = e.success;
  d["R"] = std::vector<double>(e.model.R.data(), e.model.R.data() + 9);  // column-major
  d["t"] = std::vector<double>(e.model.t.data(), e.model.t.data() + 3);
  d["scale"] = e.model.scale;
  d["shift0"] = e.model.shift0;
  d["shift1"] = e.model.shift1;
  d["f0"] = e.model.f0;
  d["f1"] = e.model.f1;
  d["inliers_reproj0"] = MaskBytes(e.inliers_reproj0);
  d["inliers_reproj1"] = MaskBytes(e.inliers_reproj1);
  d["inliers_sampson"] = MaskBytes(e.inliers_sampson);
  d["num_inliers_reproj0"] = e.num_inliers_reproj0;
  d["num_inliers_reproj1"] = e.num_inliers_reproj1;
  d["num_inliers_sampson"] = e.num_inliers_sampson;
  d["score"] = e.score;
  d["iterations"] = e.iterations;
  d["num_lo"] = e.num_lo;
  d["num_depth_samples"] = e.num_depth_samples;
  d["num_point_samples"] = e.num_point_samples;
  d["epipolar_check_switched"] = e.epipolar_check_switched;
  d["depth_observable"] = e.depth_observable;
  d["sigma_scale"] = e.sigma_scale;
  d["sigma_shift0"] = e.sigma_shift0;
  d["sigma_shift1"] = e.sigma_shift1;
  d["shifts_dropped"] = e.shifts_dropped;
  d["scale_reset"] = e.scale_reset;
  d["low_parallax_weighting"] = e.low_parallax_weighting;
  d["sigma_focal0"] = e.sigma_focal0;
  d["sigma_focal1"] = e.sigma_focal1;
  d["runtime_ms"] = e.runtime_ms;
  return d;
}

RelativePoseResult ResultFromState(const py::dict& d) {
  auto get = [&](const char* key) -> py::handle {
    if (!d.contains(key)) throw py::value_error(std::string("RelativePoseResult state has no '") + key + "'");
    return d[key];
  };
  if (get("version").cast<int>() != 1) {
    throw py::value_error("RelativePoseResult state version " + std::string(py::str(get("version"))) +
                          " is not 1 (pickled by another madsfm version)");
  }
  RelativePoseResult r;
  HybridEstimate& e = r.estimate;
  r.camera_mode = get("camera_mode").cast<std::string>();
  r.method = get("method").cast<std::string>();
  r.notes = get("notes").cast<std::vector<std::string>>();
  r.num_matches = get("num_matches").cast<int>();
  r.num_matches_with_depth = get("num_matches_with_depth").cast<int>();
  e.success = get("success").cast<bool>();
  const auto R = get("R").cast<std::vector<double>>();
  const auto t = get("t").cast<std::vector<double>>();
  if (R.size() != 9 || t.size() != 3) throw py::value_error("RelativePoseResult state: R needs 9 values, t 3");
  std::copy(R.begin(), R.end(), e.model.R.data());
  std::copy(t.begin(), t.end(), e.model.t.data());
  e.model.scale = get("scale").cast<double>();
  e.model.shift0 = get("shift0").cast<double>();
  e.model.shift1 = get("shift1").cast<double>();
  e.model.f0 = get("f0").cast<double>();
  e.model.f1 = get("f1").cast<double>();
  e.inliers_reproj0 = MaskFromBytes(get("inliers_reproj0"));
  e.inliers_reproj1 = MaskFromBytes(get("inliers_reproj1"));
  e.inliers_sampson = MaskFromBytes(get("inliers_sampson"));
  e.num_inliers_reproj0 = get("num_inliers_reproj0").cast<int>();
  e.num_inliers_reproj1 = get("num_inliers_reproj1").cast<int>();
  e.num_inliers_sampson = get("num_inliers_sampson").cast<int>();
  e.score = get("score").cast<double>();
  e.iterations = get("iterations").cast<int>();
  e.num_lo = get("num_lo").cast<int>();
  e.num_depth_samples = get("num_depth_samples").cast<int>();
  e.num_point_samples = get("num_point_samples").cast<int>();
  e.epipolar_check_switched = get("epipolar_check_switched").cast<bool>();
  // Added after the first version-1 pickles: absent there (unknown, i.e. not observable).
  if (d.contains("depth_observable")) {
    e.depth_observable = get("depth_observable").cast<bool>();
    e.sigma_scale = get("sigma_scale").cast<double>();
    e.sigma_shift0 = get("sigma_shift0").cast<double>();
    e.sigma_shift1 = get("sigma_shift1").cast<double>();
  }
  // Added later still (absent: unknown).
  if (d.contains("sigma_focal0")) {
    e.sigma_focal0 = get("sigma_focal0").cast<double>();
    e.sigma_focal1 = get("sigma_focal1").cast<double>();
  }
  if (d.contains("shifts_dropped")) e.shifts_dropped = get("shifts_dropped").cast<bool>();
  if (d.contains("scale_reset")) e.scale_reset = get("scale_reset").cast<bool>();
  if (d.contains("low_parallax_weighting")) e.low_parallax_weighting = get("low_parallax_weighting").cast<bool>();
  e.runtime_ms = get("runtime_ms").cast<double>();
  return r;
}

void BindResult(py::module_& m) {
  py::class_<RelativePoseResult> result(
      m, "RelativePoseResult",
      "Result of madsfm.estimate_*relative_pose: X1 = R X0 + t with t in units of view 0's corrected depth,\n"
      "corrected depths d0 + shift0 and scale * (d1 + shift1), focal lengths f0, f1 in pixels, inlier masks per\n"
      "data type and statistics. Model attributes are NaN when success is False.");
  for (const auto& [name, getter] : ResultFields()) {
    result.def_property_readonly(name, [g = getter](const RelativePoseResult& r) { return g(r); });
  }
  result.def("to_dict", [](const RelativePoseResult& r) {
          py::dict d;
          for (const auto& [name, getter] : ResultFields()) d[name] = getter(r);
          return d;
        }, "All attributes by name (numpy arrays for R, t and the masks).")
      .def("__repr__", &ResultRepr)
      .def(py::pickle(&ResultState, &ResultFromState))
      .def("__reduce__", [](py::object self) { return Reduce(self); });
}

// ---- estimation ----

std::vector<Eigen::Vector2d> Points(const py::array_t<double, py::array::c_style | py::array::forcecast>& a,
                                    const char* name) {
  if (a.ndim() != 2 || a.shape(1) != 2) throw py::value_error(std::string(name) + " must be an N x 2 array");
  std::vector<Eigen::Vector2d> out(a.shape(0));
  const double* p = a.data();
  for (size_t i = 0; i < out.size(); ++i) out[i] = Eigen::Vector2d(p[2 * i], p[2 * i + 1]);
  return out;
}

std::vector<double> Values(const py::array_t<double, py::array::c_style | py::array::forcecast>& a, size_t n,
                           const char* name) {
  if (a.ndim() != 1 || static_cast<size_t>(a.shape(0)) != n) {
    throw py::value_error(std::string(name) + " must have one value per match");
  }
  return std::vector<double>(a.data(), a.data() + n);
}

// The estimation step of `madsfm pair` on prepared inputs: pixel coordinates and pinhole cameras (fx, fy, cx, cy)
// exactly as EvaluatePair passes them to EstimateRelativePose. Inputs are copied before the GIL is released.
RelativePoseResult Estimate(const std::string& camera_mode, const std::string& method,
                            const py::array_t<double, py::array::c_style | py::array::forcecast>& kpts0,
                            const py::array_t<double, py::array::c_style | py::array::forcecast>& kpts1,
                            const py::array_t<double, py::array::c_style | py::array::forcecast>& depth0,
                            const py::array_t<double, py::array::c_style | py::array::forcecast>& depth1,
                            const std::array<double, 4>& camera0, const std::array<double, 4>& camera1,
                            const HybridEstimatorOptions& base_options, bool point_fallback, double max_image_dim,
                            std::vector<std::string> notes) {
  RelativePoseResult r;
  r.camera_mode = camera_mode;
  r.method = method;
  r.notes = std::move(notes);
  const CameraMode mode = ParseCameraMode(camera_mode);
  HybridEstimatorOptions options = OptionsForMethod(method, base_options);
  if (point_fallback) options = PointOnlyOptions(base_options);
  options.Check();
  const std::vector<Eigen::Vector2d> p0 = Points(kpts0, "kpts0"), p1 = Points(kpts1, "kpts1");
  if (p1.size() != p0.size()) throw py::value_error("kpts0 and kpts1 must have the same number of rows");
  const std::vector<double> d0 = Values(depth0, p0.size(), "depth0"), d1 = Values(depth1, p0.size(), "depth1");
  r.num_matches = static_cast<int>(p0.size());
  for (size_t i = 0; i < d0.size(); ++i) r.num_matches_with_depth += (d0[i] > 0.0 && d1[i] > 0.0);
  const PinholeCamera cam0{camera0[0], camera0[1], camera0[2], camera0[3]};
  const PinholeCamera cam1{camera1[0], camera1[1], camera1[2], camera1[3]};
  {
    py::gil_scoped_release release;
    r.estimate = EstimateRelativePose(mode, p0, p1, d0, d1, cam0, cam1, options, max_image_dim);
  }
  AppendEstimateNotes(r.estimate, &r.notes);  // as EvaluatePair does for `madsfm pair`
  return r;
}

}  // namespace

void BindEstimation(py::module_& m) {
  BindOptions(m);
  BindResult(m);
  m.def("_estimate", &Estimate, py::arg("camera_mode"), py::arg("method"), py::arg("kpts0"), py::arg("kpts1"),
        py::arg("depth0"), py::arg("depth1"), py::arg("camera0"), py::arg("camera1"), py::arg("options"),
        py::arg("point_fallback"), py::arg("max_image_dim"), py::arg("notes"));
  m.attr("METHODS") = py::tuple(py::cast(MethodNames()));
}

}  // namespace madsfm::python

PYBIND11_MODULE(_madsfm, m) {
  m.doc() = "madsfm C++ core: relative pose with affine-corrected monocular depth priors (use the madsfm package).";
  m.attr("__version__") = MADSFM_VERSION;
  madsfm::python::BindEstimation(m);
  madsfm::python::BindIo(m);
}
