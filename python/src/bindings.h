// Shared declarations of the two binding translation units of the _madsfm extension.
#pragma once

#include <pybind11/pybind11.h>

namespace madsfm::python {

// Options, result and the estimation entry point (module.cc).
void BindEstimation(pybind11::module_& m);

// Depth-map reading and sampling, pair directories, COLMAP camera undistortion, pose-error metrics (io_bindings.cc).
void BindIo(pybind11::module_& m);

}  // namespace madsfm::python
