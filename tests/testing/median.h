// The median the tests report and assert on.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

namespace madsfm {
namespace testing {

// Upper median (the element at index size / 2 of the sorted values); NaN for no values.
inline double Median(std::vector<double> values) {
  if (values.empty()) return std::nan("");
  std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
  return values[values.size() / 2];
}

}  // namespace testing
}  // namespace madsfm
