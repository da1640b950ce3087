#include "hmt/common/config.h"

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "hmt/common/error.h"

namespace hmt {
namespace {

std::string trim(const std::string& s) {
  const char* ws = " \t\r\n";
  const auto b = s.find_first_not_of(ws);
  if (b == std::string::npos) return "";
  const auto e = s.find_last_not_of(ws);
  return s.substr(b, e - b + 1);
}

bool valid_name(const std::string& s) {
  if (s.empty()) return false;
  for (char c : s) {
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' ||
          c == '.'))
      return false;
  }
  return true;
}

// Why `value` cannot be written back into an INI file as it is (empty if it
// can): the effective configuration a run writes must read back as the
// values it ran with, and a comment marker (';' or '#' at the start of the
// value or after a blank) or a line break would cut it short.
std::string unwritable(const std::string& value) {
  for (size_t i = 0; i < value.size(); ++i) {
    const char c = value[i];
    if (c == '\n') return "holds a line break";
    if ((c == ';' || c == '#') && (i == 0 || value[i - 1] == ' ' || value[i - 1] == '\t'))
      return std::string("holds '") + c + "' where it would start a comment";
  }
  return "";
}

std::string lower(std::string s) {
  for (auto& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

}  // namespace

Config Config::from_string(const std::string& text, const std::string& origin,
                           const std::string& dir) {
  Config cfg;
  cfg.origin_ = origin;
  std::istringstream in(text);
  std::string line, section;
  int lineno = 0;
  while (std::getline(in, line)) {
    ++lineno;
    const std::string where = origin + ":" + std::to_string(lineno);
    // Strip comments: ';' or '#' at line start or after whitespace.
    for (size_t i = 0; i < line.size(); ++i) {
      if ((line[i] == ';' || line[i] == '#') &&
          (i == 0 || line[i - 1] == ' ' || line[i - 1] == '\t')) {
        line.resize(i);
        break;
      }
    }
    const std::string t = trim(line);
    if (t.empty()) continue;
    if (t.front() == '[') {
      if (t.back() != ']')
        throw ConfigError(where + ": malformed section header '" + t + "'");
      section = trim(t.substr(1, t.size() - 2));
      if (!valid_name(section))
        throw ConfigError(where + ": malformed section name '" + section + "'");
      continue;
    }
    const auto eq = t.find('=');
    if (eq == std::string::npos)
      throw ConfigError(where + ": expected 'key = value', got '" + t + "'");
    const std::string key = trim(t.substr(0, eq));
    const std::string value = trim(t.substr(eq + 1));
    if (!valid_name(key))
      throw ConfigError(where + ": malformed key '" + key + "'");
    if (section.empty())
      throw ConfigError(where + ": key '" + key + "' appears before any [section]");
    if (const std::string why = unwritable(value); !why.empty())
      throw ConfigError(where + ": [" + section + "] " + key + " = '" + value + "' " + why +
                        " (a value cannot start with ';' or '#')");
    auto& sec = cfg.entries_[section];
    if (sec.count(key))
      throw ConfigError(where + ": duplicate key [" + section + "] " + key +
                        " (first at " + sec[key].where + ")");
    sec[key] = Entry{value, where, false, dir};
  }
  return cfg;
}

Config Config::from_file(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw ConfigError("cannot open config file '" + path + "'");
  std::stringstream ss;
  ss << f.rdbuf();
  if (f.bad()) throw ConfigError("cannot read config file '" + path + "'");
  return from_string(ss.str(), path, std::filesystem::path(path).parent_path().string());
}

void Config::apply_override(const std::string& assignment, const std::string& dir) {
  const auto eq = assignment.find('=');
  const auto dot = assignment.find('.');
  if (eq == std::string::npos || dot == std::string::npos || dot > eq)
    throw ConfigError("--set '" + assignment +
                      "': expected SECTION.key=value");
  const std::string section = trim(assignment.substr(0, dot));
  const std::string key = trim(assignment.substr(dot + 1, eq - dot - 1));
  const std::string value = trim(assignment.substr(eq + 1));
  if (!valid_name(section) || !valid_name(key))
    throw ConfigError("--set '" + assignment + "': malformed section or key");
  if (const std::string why = unwritable(value); !why.empty())
    throw ConfigError("--set '" + assignment + "': the value " + why +
                      " (an INI file, such as the effective configuration, could not hold it)");
  entries_[section][key] = Entry{value, "--set " + assignment, false, dir};
}

void Config::overlay(const Config& upper) {
  for (const auto& [section, keys] : upper.entries_)
    for (const auto& [key, e] : keys) entries_[section][key] = e;
  origin_ = upper.origin_;
}

std::string Config::dir_of(const std::string& section, const std::string& key) const {
  auto s = entries_.find(section);
  if (s == entries_.end()) return "";
  auto k = s->second.find(key);
  return k == s->second.end() ? "" : k->second.dir;
}

const Config::Entry* Config::lookup(const std::string& section,
                                    const std::string& key) {
  auto s = entries_.find(section);
  if (s == entries_.end()) return nullptr;
  auto k = s->second.find(key);
  if (k == s->second.end()) return nullptr;
  k->second.used = true;
  return &k->second;
}

void Config::get_double_or_auto(const std::string& section, const std::string& key,
                                double* value, bool* is_auto) {
  if (has(section, key) ? get_string(section, key, "") == "auto" : *is_auto) {
    *is_auto = true;
    get_string(section, key, "auto");  // recorded in the effective configuration
  } else {
    *is_auto = false;
    *value = get_double(section, key, *value);
  }
}

bool Config::has(const std::string& section, const std::string& key) const {
  auto s = entries_.find(section);
  return s != entries_.end() && s->second.count(key) > 0;
}

std::map<std::string, std::map<std::string, std::string>> Config::values() const {
  std::map<std::string, std::map<std::string, std::string>> out;
  for (const auto& [section, keys] : entries_)
    for (const auto& [key, e] : keys) out[section][key] = e.value;
  return out;
}

std::vector<std::pair<std::string, std::string>> Config::keys() const {
  std::vector<std::pair<std::string, std::string>> out;
  for (const auto& [section, keys] : entries_)
    for (const auto& kv : keys) out.emplace_back(section, kv.first);
  return out;
}

void Config::record(const std::string& section, const std::string& key,
                    const std::string& value) {
  effective_[section][key] = value;
}

void Config::bad_value(const std::string& section, const std::string& key,
                       const Entry& e, const char* expected) const {
  throw ConfigError(e.where + ": [" + section + "] " + key + " = '" + e.value +
                    "' is not " + expected);
}

double Config::get_double(const std::string& section, const std::string& key,
                          double default_value) {
  double v = default_value;
  if (const Entry* e = lookup(section, key)) {
    const char* b = e->value.c_str();
    char* end = nullptr;
    errno = 0;
    v = std::strtod(b, &end);
    if (e->value.empty() || end != b + e->value.size() || errno == ERANGE ||
        !std::isfinite(v))
      bad_value(section, key, *e, "a finite number");
  }
  std::ostringstream os;
  os.precision(17);
  os << v;
  record(section, key, os.str());
  return v;
}

int Config::get_int(const std::string& section, const std::string& key,
                    int default_value) {
  long v = default_value;
  if (const Entry* e = lookup(section, key)) {
    const char* b = e->value.c_str();
    char* end = nullptr;
    errno = 0;
    v = std::strtol(b, &end, 10);
    if (e->value.empty() || end != b + e->value.size() || errno == ERANGE ||
        v < -2147483647L || v > 2147483647L)
      bad_value(section, key, *e, "an integer");
  }
  record(section, key, std::to_string(v));
  return static_cast<int>(v);
}

bool Config::get_bool(const std::string& section, const std::string& key,
                      bool default_value) {
  bool v = default_value;
  if (const Entry* e = lookup(section, key)) {
    const std::string s = lower(e->value);
    if (s == "true" || s == "1" || s == "yes" || s == "on")
      v = true;
    else if (s == "false" || s == "0" || s == "no" || s == "off")
      v = false;
    else
      bad_value(section, key, *e, "a boolean (true/false)");
  }
  record(section, key, v ? "true" : "false");
  return v;
}

std::string Config::get_string(const std::string& section,
                               const std::string& key,
                               const std::string& default_value) {
  std::string v = default_value;
  if (const Entry* e = lookup(section, key)) v = e->value;
  record(section, key, v);
  return v;
}

void Config::check_all_used() const {
  for (const auto& [section, keys] : entries_)
    for (const auto& [key, e] : keys)
      if (!e.used)
        throw ConfigError(e.where + ": unknown configuration key [" + section +
                          "] " + key + " (no component reads it; typo?)");
}

std::string Config::effective_ini() const {
  std::ostringstream os;
  os << "; effective configuration (every value in force, defaults included)\n";
  for (const auto& [section, keys] : effective_) {
    os << "\n[" << section << "]\n";
    for (const auto& [key, value] : keys) os << key << " = " << value << "\n";
  }
  return os.str();
}

void require(bool ok, const std::string& section, const std::string& key,
             const std::string& what) {
  if (!ok) throw ConfigError("[" + section + "] " + key + ": must be " + what);
}

}  // namespace hmt
