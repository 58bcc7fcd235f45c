// Whether the test binary is built with AddressSanitizer (MADSFM_SANITIZE, scripts/test.sh's second stage). Rate tests
// over hundreds of estimator runs skip themselves there: they take 20x their Release time and check accuracy, which
// the Release stage already checks; the sanitizer stage still runs every code path through the smaller tests.
#pragma once

namespace madsfm::testing {

#if defined(__SANITIZE_ADDRESS__)
inline constexpr bool kUnderSanitizer = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
inline constexpr bool kUnderSanitizer = true;
#else
inline constexpr bool kUnderSanitizer = false;
#endif
#else
inline constexpr bool kUnderSanitizer = false;
#endif

}  // namespace madsfm::testing
