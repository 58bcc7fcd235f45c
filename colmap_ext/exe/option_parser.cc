#include "colmap_ext/exe/option_parser.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

namespace madsfm {
namespace {

std::string Trimmed(double v) {
  std::ostringstream os;
  os << v;
  return os.str();
}

}  // namespace

OptionParser::OptionParser(std::string command, std::string description)
    : command_(std::move(command)), description_(std::move(description)) {}

void OptionParser::AddRequired(const std::string& name, std::string* value, const std::string& help) {
  options_.push_back({name, help, "", "TEXT", true, false, false, [value](const std::string& s) {
                        *value = s;
                        return true;
                      }});
}

void OptionParser::AddDefault(const std::string& name, std::string* value, const std::string& help) {
  options_.push_back({name, help, *value, "TEXT", false, false, false, [value](const std::string& s) {
                        *value = s;
                        return true;
                      }});
}

void OptionParser::AddDefault(const std::string& name, int* value, const std::string& help) {
  options_.push_back({name, help, std::to_string(*value), "INT", false, false, false, [value](const std::string& s) {
                        char* end = nullptr;
                        errno = 0;
                        const long v = std::strtol(s.c_str(), &end, 10);
                        if (s.empty() || *end != '\0' || errno != 0 || v < -2147483647L || v > 2147483647L) return false;
                        *value = static_cast<int>(v);
                        return true;
                      }});
}

void OptionParser::AddDefault(const std::string& name, double* value, const std::string& help) {
  options_.push_back({name, help, Trimmed(*value), "NUM", false, false, false, [value](const std::string& s) {
                        char* end = nullptr;
                        const double v = std::strtod(s.c_str(), &end);
                        if (s.empty() || *end != '\0' || !std::isfinite(v)) return false;
                        *value = v;
                        return true;
                      }});
}

void OptionParser::AddDefault(const std::string& name, bool* value, const std::string& help) {
  options_.push_back({name, help, *value ? "1" : "0", "0|1", false, false, false, [value](const std::string& s) {
                        if (s == "1" || s == "true") *value = true;
                        else if (s == "0" || s == "false") *value = false;
                        else return false;
                        return true;
                      }});
}

void OptionParser::AddMulti(const std::string& name, std::vector<std::string>* values, bool required,
                            const std::string& help) {
  options_.push_back({name, help, "", "TEXT...", required, true, false, [values](const std::string& s) {
                        values->push_back(s);
                        return true;
                      }});
}

void OptionParser::AddPositional(const std::string& name, std::vector<std::string>* values, bool required,
                                 const std::string& help) {
  positional_ = values;
  positional_name_ = name;
  positional_help_ = help;
  positional_required_ = required;
}

OptionParser::Option* OptionParser::Find(const std::string& name) {
  for (auto& o : options_)
    if (o.name == name) return &o;
  return nullptr;
}

std::string OptionParser::Help() const {
  std::ostringstream os;
  os << "Usage: madsfm " << command_ << " [options]";
  if (positional_) os << " " << positional_name_ << "...";
  os << "\n\n" << description_ << "\n\n";
  if (positional_) os << "Arguments:\n  " << positional_name_ << "...\n      " << positional_help_ << "\n\n";
  os << "Options:\n";
  os << "  --help\n      Print this help and exit.\n";
  for (const auto& o : options_) {
    os << "  --" << o.name << " " << o.type;
    if (o.required) os << "  (required)";
    else if (!o.default_text.empty()) os << "  (default: " << o.default_text << ")";
    std::string help = o.help;  // continuation lines indented like the first
    for (size_t i = help.find('\n'); i != std::string::npos; i = help.find('\n', i + 7)) help.insert(i + 1, "      ");
    os << "\n      " << help << "\n";
  }
  return os.str();
}

bool OptionParser::Parse(int argc, char** argv, int first) {
  for (int i = first; i < argc; ++i) {
    std::string arg = argv[i];
    if (arg == "--help" || arg == "-h") {
      help_requested_ = true;
      std::fputs(Help().c_str(), stdout);
      return true;
    }
    if (arg.rfind("--", 0) != 0 && positional_) {
      positional_->push_back(arg);
      continue;
    }
    if (arg.rfind("--", 0) != 0) {
      std::fprintf(stderr, "madsfm %s: unexpected argument '%s' (options are --name value; see --help)\n",
                   command_.c_str(), arg.c_str());
      return false;
    }
    std::string name = arg.substr(2), value;
    bool has_value = false;
    const size_t eq = name.find('=');
    if (eq != std::string::npos) {
      value = name.substr(eq + 1);
      name = name.substr(0, eq);
      has_value = true;
    }
    Option* o = Find(name);
    if (o == nullptr) {
      std::fprintf(stderr, "madsfm %s: unknown option --%s (see --help)\n", command_.c_str(), name.c_str());
      return false;
    }
    if (!has_value) {
      if (i + 1 >= argc || std::string(argv[i + 1]).rfind("--", 0) == 0) {
        std::fprintf(stderr, "madsfm %s: option --%s needs a value\n", command_.c_str(), name.c_str());
        return false;
      }
      value = argv[++i];
    }
    do {
      if (!o->set(value)) {
        std::fprintf(stderr, "madsfm %s: bad value '%s' for --%s (expected %s)\n", command_.c_str(), value.c_str(),
                     name.c_str(), o->type.c_str());
        return false;
      }
      o->seen = true;
      // Multi-valued options take every following non-option argument.
      if (o->multi && i + 1 < argc && std::string(argv[i + 1]).rfind("--", 0) != 0) {
        value = argv[++i];
        continue;
      }
      break;
    } while (true);
  }
  for (const auto& o : options_) {
    if (o.required && !o.seen) {
      std::fprintf(stderr, "madsfm %s: missing required option --%s (see --help)\n", command_.c_str(), o.name.c_str());
      return false;
    }
  }
  if (positional_ && positional_required_ && positional_->empty()) {
    std::fprintf(stderr, "madsfm %s: missing %s... arguments (see --help)\n", command_.c_str(),
                 positional_name_.c_str());
    return false;
  }
  return true;
}

}  // namespace madsfm
