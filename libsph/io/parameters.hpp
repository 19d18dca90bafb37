#pragma once
// Scene parameters: declared once, bound to a member of the scene's typed parameter struct or
// directly to a member of a library component's settings (its default is the member's value),
// with a unit, a valid range and a help text. Enumerated choices are bound to the enum itself
// (add_enum, with the names the component declares next to the enum), so a choice is parsed once,
// here, and never compared as a string in a scene. Values can then be set from
// a config file (TOML or JSON; nested tables give dotted keys) and from the command line
// (`--set key=value`); an unknown key or a value out of range throws ParameterError naming the key,
// the value, where it came from and what was expected. A preset (add_preset) is a named set of
// values for other parameters; apply_presets() gives them to every parameter that the config file
// and the command line left alone, so an explicit setting wins whatever its order.

#include <Eigen/Core>
#include <filesystem>
#include <functional>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json_fwd.hpp>

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

/// One choice of a preset (Parameters::add_preset): its name, the enum value it selects and the
/// values it gives to other parameters, as they would be written after `--set key=`.
template <class E>
struct PresetChoice {
  PresetChoice(std::string choice, E selects, std::vector<std::pair<std::string, std::string>> assignments = {})
      : name(std::move(choice)), value(selects), values(std::move(assignments)) {}
  std::string name;
  E value;
  std::vector<std::pair<std::string, std::string>> values;
};

class Parameters {
 public:
  void add(const std::string& key, double& value, const std::string& unit, const std::string& help,
           Range range = Range::any());
  void add(const std::string& key, float& value, const std::string& unit, const std::string& help,
           Range range = Range::any());
  void add(const std::string& key, long& value, const std::string& unit, const std::string& help,
           Range range = Range::any());
  void add(const std::string& key, int& value, const std::string& unit, const std::string& help,
           Range range = Range::any());
  void add(const std::string& key, bool& value, const std::string& help);
  void add_choice(const std::string& key, std::string& value, std::vector<std::string> choices, const std::string& help);
  /// Free text; the scene checks its meaning.
  void add_text(const std::string& key, std::string& value, const std::string& help);
  /// A file or folder path (empty allowed; the scene checks that it exists when it needs it).
  void add_path(const std::string& key, std::filesystem::path& value, const std::string& help);
  /// Three numbers "x,y,z" (commas or spaces); zero is rejected unless allow_zero (directions).
  void add_vector(const std::string& key, Eigen::Vector3d& value, const std::string& unit, const std::string& help,
                  bool allow_zero = false);
  /// One of the named values of an enum; `names` lists every value once, e.g. {{"moment", moment}, ...}.
  template <class E>
  void add_enum(const std::string& key, E& value, const std::vector<std::pair<std::string, E>>& names,
                const std::string& help) {
    std::vector<std::string> choices;
    for (const auto& [name, v] : names) choices.push_back(name);
    add_named_choice(
        key, choices, help,
        [&value, names](std::size_t k) { value = names[k].second; },
        [&value, names]() -> std::string {
          for (const auto& [name, v] : names)
            if (v == value) return name;
          return "?";
        });
  }

  /// A preset parameter: chosen like add_enum; its values are applied by apply_presets().
  template <class E>
  void add_preset(const std::string& key, E& value, const std::vector<PresetChoice<E>>& choices, const std::string& help) {
    std::vector<std::pair<std::string, E>> names;
    for (const auto& c : choices) names.emplace_back(c.name, c.value);
    add_enum(key, value, names, help);
    presets_.push_back({key, [&value, choices]() -> const PresetValues& {
                          for (const auto& c : choices)
                            if (c.value == value) return c.values;
                          throw std::logic_error("preset without its choice");
                        }});
  }
  /// Sets the values of each preset's current choice on the parameters not set by set() (config
  /// file, command line); throws ParameterError if a preset names an unknown parameter or a bad value.
  void apply_presets();

  bool has(const std::string& key) const;
  /// An old name of the declared parameter `key` (a renamed parameter keeps working): setting it, on
  /// the command line or in a file, sets `key` and prints a warning that names both on stderr.
  void add_alias(const std::string& old_key, const std::string& key);
  /// Parses `text` for `key` and checks it; `origin` (e.g. "--set", a file name) goes into errors.
  void set(const std::string& key, const std::string& text, const std::string& origin);
  /// Applies every value of a .toml or .json file.
  void load_file(const std::filesystem::path& path);
  /// Sets the values of a config text in `format` ("json" or "toml"); `name` names it in errors.
  void load_text(const std::string& text, const std::string& format, const std::string& name);
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
    std::function<void(nlohmann::json&)> json;  // writes the current value
    std::function<void(const std::string&)> check;  // origin
  };
  Entry& entry(const std::string& key, const std::string& origin);
  template <class T>
  void add_number(const std::string& key, T& value, const std::string& unit, const std::string& help, Range range);
  void add_named_choice(const std::string& key, std::vector<std::string> choices, const std::string& help,
                        std::function<void(std::size_t)> select, std::function<std::string()> current);
  void add_entry(Entry e);
  std::vector<std::pair<std::string, std::string>> aliases_;  // (old name, name)
  using PresetValues = std::vector<std::pair<std::string, std::string>>;
  struct Preset {
    std::string key;
    std::function<const PresetValues&()> current;
  };
  std::vector<Entry> entries_;
  std::vector<Preset> presets_;
  std::vector<std::string> explicit_keys_;  // set by set(): presets leave them alone
};

}  // namespace sph
