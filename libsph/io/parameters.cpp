#include "libsph/io/parameters.hpp"

#include <algorithm>
#include <iostream>
#include <charconv>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <limits>
#include <type_traits>

#include <nlohmann/json.hpp>
#include <toml++/toml.h>

namespace sph {
namespace {

std::string format_number(double v) {
  std::ostringstream s;
  s << std::setprecision(15) << v;
  return s.str();
}

std::string quoted(const std::string& s) { return "'" + s + "'"; }

std::string where(const std::string& origin) { return origin.empty() ? "" : " (from " + origin + ")"; }

// Flattens a JSON object into dotted keys with text values.
void flatten_json(const nlohmann::json& node, const std::string& prefix,
                  std::vector<std::pair<std::string, std::string>>& out, const std::string& file) {
  for (auto it = node.begin(); it != node.end(); ++it) {
    const std::string key = prefix.empty() ? it.key() : prefix + "." + it.key();
    const auto& v = it.value();
    if (v.is_object()) flatten_json(v, key, out, file);
    else if (v.is_string()) out.emplace_back(key, v.get<std::string>());
    else if (v.is_boolean()) out.emplace_back(key, v.get<bool>() ? "true" : "false");
    else if (v.is_number_integer()) out.emplace_back(key, std::to_string(v.get<long long>()));
    else if (v.is_number()) out.emplace_back(key, format_number(v.get<double>()));
    else throw ParameterError(file + ": value of " + quoted(key) + " must be a number, a string or a boolean");
  }
}

void flatten_toml(const toml::table& table, const std::string& prefix,
                  std::vector<std::pair<std::string, std::string>>& out, const std::string& file) {
  for (const auto& [k, node] : table) {
    const std::string key = prefix.empty() ? std::string(k.str()) : prefix + "." + std::string(k.str());
    if (const auto* sub = node.as_table()) flatten_toml(*sub, key, out, file);
    else if (const auto* s = node.as_string()) out.emplace_back(key, s->get());
    else if (const auto* b = node.as_boolean()) out.emplace_back(key, b->get() ? "true" : "false");
    else if (const auto* i = node.as_integer()) out.emplace_back(key, std::to_string(i->get()));
    else if (const auto* f = node.as_floating_point()) out.emplace_back(key, format_number(f->get()));
    else throw ParameterError(file + ": value of " + quoted(key) + " must be a number, a string or a boolean");
  }
}

double parse_double(const std::string& key, const std::string& text, const std::string& origin) {
  double v = 0;
  const char* first = text.data();
  const char* last = text.data() + text.size();
  while (first != last && *first == ' ') ++first;
  if (first != last && *first == '+') ++first;
  const auto [end, error] = std::from_chars(first, last, v);
  if (error != std::errc() || end != last || text.empty())
    throw ParameterError("parameter " + quoted(key) + where(origin) + ": " + quoted(text) + " is not a number");
  return v;
}

}  // namespace

bool Range::contains(double v) const {
  if (std::isnan(v)) return false;
  if (min_open ? !(v > min) : !(v >= min)) return false;
  if (max_open ? !(v < max) : !(v <= max)) return false;
  return true;
}

std::string Range::describe() const {
  const bool has_min = std::isfinite(min), has_max = std::isfinite(max);
  if (has_min && has_max)
    return std::string(min_open ? "in (" : "in [") + format_number(min) + ", " + format_number(max) + (max_open ? ")" : "]");
  if (has_min) return std::string(min_open ? "> " : ">= ") + format_number(min);
  if (has_max) return std::string(max_open ? "< " : "<= ") + format_number(max);
  return "any finite value";
}

void Parameters::add_entry(Entry e) {
  if (has(e.key)) throw std::logic_error("parameter '" + e.key + "' declared twice");
  entries_.push_back(std::move(e));
}

// One entry for any arithmetic member: parsed and checked as a double, stored as T; integer types
// also reject fractions and values beyond their range.
template <class T>
void Parameters::add_number(const std::string& key, T& value, const std::string& unit, const std::string& help,
                            Range range) {
  constexpr bool integer = std::is_integral_v<T>;
  Entry e{key, unit, help, range, {}, {}, {}, {}, {}};
  auto text_of = [](double v) { return integer ? std::to_string(static_cast<long long>(v)) : format_number(v); };
  auto check = [key, range, unit, text_of](double v, const std::string& origin) {
    if (!std::isfinite(v) || !range.contains(v))
      throw ParameterError("parameter " + quoted(key) + where(origin) + " = " + text_of(v) + ": must be " +
                           range.describe() + (unit.empty() || unit == "-" ? "" : " [" + unit + "]"));
  };
  e.parse = [&value, key, check](const std::string& text, const std::string& origin) {
    const double v = parse_double(key, text, origin);
    if (integer && (v != std::floor(v) || std::abs(v) >= double(std::numeric_limits<T>::max())))
      throw ParameterError("parameter " + quoted(key) + where(origin) + ": " + quoted(text) + " is not an integer");
    check(v, origin);
    value = static_cast<T>(v);
  };
  e.text = [&value, text_of] { return text_of(double(value)); };
  e.json = [&value](nlohmann::json& out) { out = nlohmann::json(value); };
  e.check = [&value, check](const std::string& origin) { check(double(value), origin); };
  add_entry(std::move(e));
}

void Parameters::add(const std::string& key, double& value, const std::string& unit, const std::string& help, Range range) {
  add_number(key, value, unit, help, range);
}
void Parameters::add(const std::string& key, float& value, const std::string& unit, const std::string& help, Range range) {
  add_number(key, value, unit, help, range);
}
void Parameters::add(const std::string& key, int& value, const std::string& unit, const std::string& help, Range range) {
  add_number(key, value, unit, help, range);
}
void Parameters::add(const std::string& key, long& value, const std::string& unit, const std::string& help, Range range) {
  add_number(key, value, unit, help, range);
}

void Parameters::add(const std::string& key, bool& value, const std::string& help) {
  Entry e{key, "", help, Range::any(), {"true", "false"}, {}, {}, {}, {}};
  e.parse = [&value, key](const std::string& text, const std::string& origin) {
    if (text == "true" || text == "1" || text == "on") value = true;
    else if (text == "false" || text == "0" || text == "off") value = false;
    else throw ParameterError("parameter " + quoted(key) + where(origin) + ": " + quoted(text) + " is not true or false");
  };
  e.text = [&value] { return std::string(value ? "true" : "false"); };
  e.json = [&value](nlohmann::json& out) { out = nlohmann::json(value); };
  e.check = [](const std::string&) {};
  add_entry(std::move(e));
}

void Parameters::add_text(const std::string& key, std::string& value, const std::string& help) {
  Entry e{key, "", help, Range::any(), {}, {}, {}, {}, {}};
  e.parse = [&value](const std::string& text, const std::string&) { value = text; };
  e.text = [&value] { return value; };
  e.json = [&value](nlohmann::json& out) { out = nlohmann::json(value); };
  e.check = [](const std::string&) {};
  add_entry(std::move(e));
}

void Parameters::add_path(const std::string& key, std::filesystem::path& value, const std::string& help) {
  Entry e{key, "", help, Range::any(), {}, {}, {}, {}, {}};
  e.parse = [&value](const std::string& text, const std::string&) { value = text; };
  e.text = [&value] { return value.string(); };
  e.json = [&value](nlohmann::json& out) { out = nlohmann::json(value.string()); };
  e.check = [](const std::string&) {};
  add_entry(std::move(e));
}

void Parameters::add_vector(const std::string& key, Eigen::Vector3d& value, const std::string& unit,
                            const std::string& help, bool allow_zero) {
  Entry e{key, unit, help, Range::any(), {}, {}, {}, {}, {}};
  auto check = [key, allow_zero](const Eigen::Vector3d& v, const std::string& text, const std::string& origin) {
    if (!v.allFinite())
      throw ParameterError("parameter " + quoted(key) + where(origin) + " = " + quoted(text) + ": must be finite");
    if (!allow_zero && v.norm() == 0)
      throw ParameterError("parameter " + quoted(key) + where(origin) + " = " + quoted(text) + ": must not be zero");
  };
  auto text_of = [&value] {
    return format_number(value.x()) + "," + format_number(value.y()) + "," + format_number(value.z());
  };
  e.parse = [&value, key, check](const std::string& text, const std::string& origin) {
    std::string t = text;
    for (char& c : t)
      if (c == ',') c = ' ';
    std::istringstream in(t);
    Eigen::Vector3d v;
    if (!(in >> v.x() >> v.y() >> v.z()) || !(in >> std::ws).eof())
      throw ParameterError("parameter " + quoted(key) + where(origin) + " = " + quoted(text) +
                           ": expected three numbers x,y,z");
    check(v, text, origin);
    value = v;
  };
  e.text = text_of;
  e.json = [&value](nlohmann::json& out) { out = nlohmann::json::array({value.x(), value.y(), value.z()}); };
  e.check = [&value, check, text_of](const std::string& origin) { check(value, text_of(), origin); };
  add_entry(std::move(e));
}

void Parameters::add_named_choice(const std::string& key, std::vector<std::string> choices, const std::string& help,
                                  std::function<void(std::size_t)> select, std::function<std::string()> current) {
  Entry e{key, "", help, Range::any(), choices, {}, {}, {}, {}};
  e.parse = [key, choices, select](const std::string& text, const std::string& origin) {
    const auto it = std::find(choices.begin(), choices.end(), text);
    if (it == choices.end()) {
      std::string list;
      for (const auto& c : choices) list += (list.empty() ? "" : ", ") + c;
      throw ParameterError("parameter " + quoted(key) + where(origin) + " = " + quoted(text) + ": must be one of " + list);
    }
    select(static_cast<std::size_t>(it - choices.begin()));
  };
  e.text = current;
  e.json = [current](nlohmann::json& out) { out = nlohmann::json(current()); };
  e.check = [](const std::string&) {};
  add_entry(std::move(e));
}

void Parameters::add_choice(const std::string& key, std::string& value, std::vector<std::string> choices,
                            const std::string& help) {
  Entry e{key, "", help, Range::any(), choices, {}, {}, {}, {}};
  auto check = [key, choices](const std::string& v, const std::string& origin) {
    if (std::find(choices.begin(), choices.end(), v) != choices.end()) return;
    std::string list;
    for (const auto& c : choices) list += (list.empty() ? "" : ", ") + c;
    throw ParameterError("parameter " + quoted(key) + where(origin) + " = " + quoted(v) + ": must be one of " + list);
  };
  e.parse = [&value, check](const std::string& text, const std::string& origin) {
    check(text, origin);
    value = text;
  };
  e.text = [&value] { return value; };
  e.json = [&value](nlohmann::json& out) { out = nlohmann::json(value); };
  e.check = [&value, check](const std::string& origin) { check(value, origin); };
  add_entry(std::move(e));
}

bool Parameters::has(const std::string& key) const {
  return std::any_of(entries_.begin(), entries_.end(), [&](const Entry& e) { return e.key == key; });
}

Parameters::Entry& Parameters::entry(const std::string& key, const std::string& origin) {
  for (auto& e : entries_)
    if (e.key == key) return e;
  std::string known;
  for (const auto& e : entries_) known += (known.empty() ? "" : ", ") + e.key;
  throw ParameterError("unknown parameter " + quoted(key) + where(origin) + "; this scene has: " + known);
}

void Parameters::add_alias(const std::string& old_key, const std::string& key) {
  if (!has(key)) throw std::logic_error("alias " + quoted(old_key) + " of the undeclared parameter " + quoted(key));
  aliases_.emplace_back(old_key, key);
}

void Parameters::set(const std::string& given, const std::string& text, const std::string& origin) {
  std::string key = given;
  for (const auto& [old_key, name] : aliases_)
    if (old_key == given) {
      std::cerr << "warning: parameter " << quoted(old_key) << where(origin) << " is now called " << quoted(name)
                << "; the old name still works\n";
      key = name;
    }
  entry(key, origin).parse(text, origin);
  if (std::find(explicit_keys_.begin(), explicit_keys_.end(), key) == explicit_keys_.end()) explicit_keys_.push_back(key);
}

void Parameters::apply_presets() {
  for (const auto& preset : presets_) {
    const std::string origin = "preset " + quoted(preset.key + "=" + entry(preset.key, "").text());
    for (const auto& [key, text] : preset.current())
      if (std::find(explicit_keys_.begin(), explicit_keys_.end(), key) == explicit_keys_.end()) entry(key, origin).parse(text, origin);
  }
}

void Parameters::set_assignment(const std::string& assignment, const std::string& origin) {
  const auto eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0)
    throw ParameterError(origin + ": " + quoted(assignment) + " is not of the form key=value");
  set(assignment.substr(0, eq), assignment.substr(eq + 1), origin);
}

void Parameters::load_file(const std::filesystem::path& path) {
  const std::string name = path.string();
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) throw ParameterError("config file " + quoted(name) + " cannot be read: it does not exist");
  if (!std::filesystem::is_regular_file(path, ec))
    throw ParameterError("config file " + quoted(name) + " cannot be read: it is not a regular file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ParameterError("config file " + quoted(name) + " cannot be read: permission denied or I/O error");
  std::stringstream buffer;
  buffer << in.rdbuf();
  const auto extension = path.extension().string();
  if (extension != ".json" && extension != ".toml")
    throw ParameterError("config file " + quoted(name) + ": unknown format (expected a .toml or .json file)");
  load_text(buffer.str(), extension.substr(1), name);
}

void Parameters::load_text(const std::string& text, const std::string& format, const std::string& name) {
  std::vector<std::pair<std::string, std::string>> values;
  if (format == "json") {
    nlohmann::json document;
    try {
      document = nlohmann::json::parse(text);
    } catch (const nlohmann::json::exception& error) {  // a syntax error, or a number beyond double's range
      throw ParameterError("config file " + quoted(name) + " is not valid JSON: " + error.what());
    }
    if (!document.is_object()) throw ParameterError("config file " + quoted(name) + ": top level must be an object");
    flatten_json(document, "", values, name);
  } else if (format == "toml") {
    try {
      const toml::table table = toml::parse(text, name);
      flatten_toml(table, "", values, name);
    } catch (const toml::parse_error& error) {
      std::ostringstream s;
      s << "config file " << quoted(name) << " is not valid TOML: " << error.description() << " (line "
        << error.source().begin.line << ")";
      throw ParameterError(s.str());
    }
  } else {
    throw ParameterError("config " + quoted(name) + ": unknown format '" + format + "' (expected json or toml)");
  }
  for (const auto& [key, value] : values) set(key, value, name);
}

void Parameters::check() const {
  for (const auto& e : entries_) e.check("");
}

nlohmann::json Parameters::to_json() const {
  nlohmann::json out = nlohmann::json::object();
  for (const auto& e : entries_) e.json(out[e.key]);
  return out;
}

std::string Parameters::describe() const {
  std::size_t width = 0;
  for (const auto& e : entries_) width = std::max(width, e.key.size() + 3 + e.text().size());
  std::ostringstream s;
  for (const auto& e : entries_) {
    std::string left = e.key + " = " + e.text();
    s << "  " << std::left << std::setw(static_cast<int>(width)) << left;
    if (!e.unit.empty()) s << "  [" << e.unit << "]";
    s << "  " << e.help;
    if (!e.choices.empty() && e.choices.size() > 2) {
      s << " (";
      for (std::size_t c = 0; c < e.choices.size(); ++c) s << (c ? ", " : "") << e.choices[c];
      s << ")";
    } else if (std::isfinite(e.range.min) || std::isfinite(e.range.max)) {
      s << " (" << e.range.describe() << ")";
    }
    s << '\n';
  }
  return s.str();
}

std::vector<std::string> Parameters::keys() const {
  std::vector<std::string> out;
  for (const auto& e : entries_) out.push_back(e.key);
  return out;
}

}  // namespace sph
