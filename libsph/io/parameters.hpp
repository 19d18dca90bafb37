#pragma once
// Scene parameters: declared once, bound to a member of the scene's typed parameter struct, with
// a default (the member's value), a unit, a valid range and a help text. Values can then be set from
// a config file (TOML or JSON; nested tables give dotted keys) and from the command line
// (`--set key=value`); an unknown key or a value out of range throws ParameterError naming the key,
// the value, where it came from and what was expected.

#include <filesystem>
#include <functional>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "libsph/core/types.hpp"

namespace sph {

/// Bad user input (parameter, config file, command line). Applications exit with code 2.
class ParameterError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

/// Closed or open interval for a numeric parameter.
struct Range {
  double min = -std::numeric_limits<double>::infinity();
  double max = std::numeric_limits<double>::infinity();
  bool min_open = false;
  bool max_open = false;

  static Range positive() { return {0, std::numeric_limits<double>::infinity(), true, false}; }
  static Range non_negative() { return {0, std::numeric_limits<double>::infinity(), false, false}; }
  static Range closed(double lo, double hi) { return {lo, hi, false, false}; }
  static Range any() { return {}; }
  bool contains(double v) const;
  std::string describe() const;
};

class Parameters {
 public:
  void add(const std::string& key, double& value, const std::string& unit, const std::string& help,
           Range range = Range::any());
  void add(const std::string& key, long& value, const std::string& unit, const std::string& help,
           Range range = Range::any());
  void add(const std::string& key, bool& value, const std::string& help);
  void add_choice(const std::string& key, std::string& value, std::vector<std::string> choices, const std::string& help);
  /// Free text (a file path, a vector "x,y,z"); the scene checks its meaning.
  void add_text(const std::string& key, std::string& value, const std::string& help);

  bool has(const std::string& key) const;
  /// Parses `text` for `key` and checks it; `origin` (e.g. "--set", a file name) goes into errors.
  void set(const std::string& key, const std::string& text, const std::string& origin);
  /// Applies every value of a .toml or .json file.
  void load_file(const std::filesystem::path& path);
  /// Applies "key=value".
  void set_assignment(const std::string& assignment, const std::string& origin);
  /// Re-checks every current value against its range (defaults included).
  void check() const;

  nlohmann::json to_json() const;
  /// One line per parameter: key = value [unit]  help (range).
  std::string describe() const;
  std::vector<std::string> keys() const;

 private:
  struct Entry {
    std::string key, unit, help;
    Range range;
    std::vector<std::string> choices;
    std::function<void(const std::string&, const std::string&)> parse;  // (text, origin)
    std::function<std::string()> text;
    std::function<nlohmann::json()> json;
    std::function<void(const std::string&)> check;  // origin
  };
  Entry& entry(const std::string& key, const std::string& origin);
  void add_entry(Entry e);
  std::vector<Entry> entries_;
};

}  // namespace sph
