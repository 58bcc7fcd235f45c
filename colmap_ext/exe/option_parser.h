// COLMAP-style command-line options: `--name value` pairs, `--help`, required and defaulted
// options bound to typed variables, and errors that name the bad option.
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace madsfm {

class OptionParser {
 public:
  // `usage` is the first line of --help, e.g. "madsfm pair --pair_path DIR [options]".
  OptionParser(std::string command, std::string description);

  void AddRequired(const std::string& name, std::string* value, const std::string& help);
  void AddDefault(const std::string& name, std::string* value, const std::string& help);
  void AddDefault(const std::string& name, int* value, const std::string& help);
  void AddDefault(const std::string& name, double* value, const std::string& help);
  void AddDefault(const std::string& name, bool* value, const std::string& help);
  // An option that may be given several times or with several values (--pairs_path A B C).
  void AddMulti(const std::string& name, std::vector<std::string>* values, bool required, const std::string& help);

  // Non-option arguments (`madsfm merge_shards --database_path DB a.sqlite b.sqlite`); without this call they are
  // an error. Shown in --help as <name>...
  void AddPositional(const std::string& name, std::vector<std::string>* values, bool required, const std::string& help);

  // Parses argv[first..argc). Returns true on success. On --help prints the help to stdout and
  // sets help_requested(); on error prints "madsfm <command>: <message>" to stderr.
  bool Parse(int argc, char** argv, int first = 1);
  bool help_requested() const { return help_requested_; }
  std::string Help() const;

 private:
  struct Option {
    std::string name;
    std::string help;
    std::string default_text;
    std::string type;
    bool required = false;
    bool multi = false;
    bool seen = false;
    std::function<bool(const std::string&)> set;
  };
  Option* Find(const std::string& name);

  std::string command_;
  std::string description_;
  std::vector<Option> options_;
  std::vector<std::string>* positional_ = nullptr;
  std::string positional_name_, positional_help_;
  bool positional_required_ = false;
  bool help_requested_ = false;
};

}  // namespace madsfm
