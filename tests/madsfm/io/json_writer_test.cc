#include "madsfm/io/json_writer.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <nlohmann/json.hpp>
#include <random>
#include <string>

namespace madsfm {
namespace {

uint64_t Bits(double v) {
  uint64_t b;
  std::memcpy(&b, &v, sizeof(b));
  return b;
}

double Parse(const std::string& s) {
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  EXPECT_EQ(*end, '\0') << s;
  return v;
}

// The fewest significant digits (%.Ng) that read back as exactly v: what a shortest representation needs.
int FewestDigits(double v) {
  char buf[64];
  for (int p = 1; p <= 17; ++p) {
    std::snprintf(buf, sizeof(buf), "%.*g", p, v);
    if (Bits(std::strtod(buf, nullptr)) == Bits(v)) return p;
  }
  return 17;
}

int SignificantDigits(const std::string& s) {
  std::string mantissa = s.substr(0, s.find('e'));
  std::string digits;
  for (char c : mantissa) if (c >= '0' && c <= '9') digits += c;
  const size_t first = digits.find_first_not_of('0');
  if (first == std::string::npos) return 1;
  digits = digits.substr(first);
  // Trailing zeros of an integer part ("1200") are not significant either.
  while (digits.size() > 1 && digits.back() == '0') digits.pop_back();
  return static_cast<int>(digits.size());
}

TEST(JsonWriter, TheIssue13NumberIsWrittenWith16Digits) {
  // nlohmann's dump printed -0.0070815972400526846; Python's repr prints the shortest form.
  const double v = Parse("-0.0070815972400526846");
  EXPECT_EQ(FormatDouble(v), "-0.007081597240052685");
  EXPECT_EQ(Bits(Parse(FormatDouble(v))), Bits(v));
}

TEST(JsonWriter, RandomDoublesRoundTripExactlyWithTheFewestDigits) {
  std::mt19937_64 rng(13);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::uniform_int_distribution<int> exponent(-300, 300);
  for (int i = 0; i < 20000; ++i) {
    double v;
    if (i % 2 == 0) {
      v = std::ldexp(unit(rng), exponent(rng) / 3);
    } else {  // any bit pattern that is a finite double
      const uint64_t b = rng();
      std::memcpy(&v, &b, sizeof(v));
      if (!std::isfinite(v)) continue;
    }
    const std::string s = FormatDouble(v);
    ASSERT_EQ(Bits(Parse(s)), Bits(v)) << s;
    // Shortest: no more significant digits than the fewest that round-trip, except that an integer written out in
    // full ("300246684313106176") may be longer in digits while shorter than its scientific form.
    const int fewest = FewestDigits(v);
    if (s.find_first_of(".e") == std::string::npos) {
      char sci[64];
      ASSERT_LE(s.size(), static_cast<size_t>(std::snprintf(sci, sizeof(sci), "%.*e", fewest - 1, v))) << s;
    } else {
      ASSERT_LE(SignificantDigits(s), fewest) << s;
    }
  }
}

TEST(JsonWriter, NonFiniteValues) {
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_EQ(FormatDouble(inf), "inf");
  EXPECT_EQ(FormatDouble(-inf), "-inf");
  EXPECT_EQ(FormatDouble(std::nan("")), "nan");
  EXPECT_EQ(FormatJsonNumber(inf), "null");
  EXPECT_EQ(FormatJsonNumber(std::nan("")), "null");
  EXPECT_EQ(DumpJson(nlohmann::json{{"a", -inf}}), "{\"a\":null}");
}

TEST(JsonWriter, IntegralDoublesStayFloatsInJson) {
  EXPECT_EQ(FormatDouble(3.0), "3");
  EXPECT_EQ(FormatJsonNumber(3.0), "3.0");
  EXPECT_EQ(FormatJsonNumber(-0.0), "-0.0");
  const nlohmann::json back = nlohmann::json::parse(DumpJson(nlohmann::json{{"f", 1e20}, {"g", 2.0}}));
  EXPECT_TRUE(back.at("f").is_number_float());
  EXPECT_TRUE(back.at("g").is_number_float());
  EXPECT_EQ(back.at("f").get<double>(), 1e20);
  EXPECT_EQ(back.at("g").get<double>(), 2.0);
}

TEST(JsonWriter, LayoutIsNlohmannsWhenThereAreNoFloats) {
  const nlohmann::json j = nlohmann::json::parse(
      R"({"b": [1, -2, {"x": "q\"uote\n"}, [], {}], "a": {"n": null, "t": true, "f": false, "u": 18446744073709551615},
          "e": [], "s": "ünïcode", "z": [[1], [2, 3]]})");
  for (int indent : {-1, 0, 2, 4}) EXPECT_EQ(DumpJson(j, indent), j.dump(indent)) << indent;
}

TEST(JsonWriter, FloatsReadBackAsTheSameNumbers) {
  std::mt19937_64 rng(7);
  std::normal_distribution<double> normal;
  nlohmann::json j;
  for (int i = 0; i < 200; ++i) j["values"].push_back(normal(rng) * std::pow(10.0, i % 40 - 20));
  j["nested"]["R"] = {0.1, 0.2, 0.30000000000000004, 1.0 / 3.0};
  for (int indent : {-1, 2}) {
    const nlohmann::json back = nlohmann::json::parse(DumpJson(j, indent));
    ASSERT_EQ(back, j) << indent;  // nlohmann compares the numbers as doubles
    for (size_t i = 0; i < j["values"].size(); ++i) {
      EXPECT_EQ(Bits(back["values"][i].get<double>()), Bits(j["values"][i].get<double>()));
    }
  }
  // Same layout as nlohmann's apart from the digits: the lines agree once the numbers are parsed.
  const std::string ours = DumpJson(j, 2), theirs = j.dump(2);
  EXPECT_EQ(std::count(ours.begin(), ours.end(), '\n'), std::count(theirs.begin(), theirs.end(), '\n'));
}

}  // namespace
}  // namespace madsfm
