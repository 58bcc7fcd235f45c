#include "madsfm/io/json_writer.h"

#include <charconv>
#include <cmath>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <system_error>

namespace madsfm {
namespace {

void Dump(const nlohmann::json& j, int indent, int depth, std::string* out) {
  using value_t = nlohmann::json::value_t;
  const bool pretty = indent >= 0;
  auto newline = [&](int level) {
    if (!pretty) return;
    out->push_back('\n');
    out->append(static_cast<size_t>(indent) * static_cast<size_t>(level), ' ');
  };
  switch (j.type()) {
    case value_t::object: {
      if (j.empty()) {
        out->append("{}");
        return;
      }
      out->push_back('{');
      bool first = true;
      for (auto it = j.begin(); it != j.end(); ++it) {
        if (!first) out->push_back(',');
        first = false;
        newline(depth + 1);
        out->append(nlohmann::json(it.key()).dump());
        out->append(pretty ? ": " : ":");
        Dump(it.value(), indent, depth + 1, out);
      }
      newline(depth);
      out->push_back('}');
      return;
    }
    case value_t::array: {
      if (j.empty()) {
        out->append("[]");
        return;
      }
      out->push_back('[');
      bool first = true;
      for (const nlohmann::json& v : j) {
        if (!first) out->push_back(',');
        first = false;
        newline(depth + 1);
        Dump(v, indent, depth + 1, out);
      }
      newline(depth);
      out->push_back(']');
      return;
    }
    case value_t::number_float:
      out->append(FormatJsonNumber(j.get<double>()));
      return;
    default:  // null, booleans, integers, strings (escaped by nlohmann), binary
      out->append(j.dump());
      return;
  }
}

}  // namespace

std::string FormatDouble(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char buf[64];
  const std::to_chars_result r = std::to_chars(buf, buf + sizeof(buf), v);
  if (r.ec != std::errc()) throw std::logic_error("FormatDouble: std::to_chars failed");
  return std::string(buf, r.ptr);
}

std::string FormatJsonNumber(double v) {
  if (!std::isfinite(v)) return "null";
  std::string s = FormatDouble(v);
  if (s.find_first_of(".e") == std::string::npos) s += ".0";
  return s;
}

std::string DumpJson(const nlohmann::json& j, int indent) {
  std::string out;
  Dump(j, indent, 0, &out);
  return out;
}

}  // namespace madsfm
