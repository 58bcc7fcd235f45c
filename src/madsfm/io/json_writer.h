// The one writer of numbers meant for machines (JSON, CSV): every double as the shortest decimal string that
// parses back to exactly the same double (std::to_chars), so that outputs are the same text whoever reads them
// back (Python's repr, strtod, nlohmann::json::parse) and equal outputs mean equal numbers.
#pragma once

#include <nlohmann/json_fwd.hpp>
#include <string>

namespace madsfm {

// Shortest round-trip decimal form of v ("0.1", "-0.007081597240052685", "1e+20", "3"); "nan", "inf", "-inf" for
// non-finite values (CSV cells; strtod and Python's float() read them back).
std::string FormatDouble(double v);

// v as a JSON number: FormatDouble, with ".0" appended when the text would read back as an integer ("3.0"), and
// null for non-finite values (JSON has no NaN / infinity; nlohmann::json writes null too).
std::string FormatJsonNumber(double v);

// j as nlohmann::json::dump(indent) lays it out (indent < 0: one line without spaces; keys in the json's order,
// sorted for objects; strings escaped by nlohmann), with every floating-point number written by FormatJsonNumber
// instead of nlohmann's Grisu2, which sometimes prints 17 digits where 16 suffice.
std::string DumpJson(const nlohmann::json& j, int indent = -1);

}  // namespace madsfm
