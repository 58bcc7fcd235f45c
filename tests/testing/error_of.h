// The message of the std::exception a callable throws, for tests that check error texts.
#pragma once

#include <exception>
#include <string>

namespace madsfm::testing {

// e.what() of the std::exception thrown by f, or "no error" when it returns normally.
template <typename F>
std::string ErrorOf(F&& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "no error";
}

}  // namespace madsfm::testing
