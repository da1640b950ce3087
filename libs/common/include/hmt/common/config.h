// INI configuration with strict key checking.
//
// Every component reads its options through get(); each read marks the key as
// used and records the effective value (the file's, an override's, or the
// default). After all components are configured, check_all_used() turns any
// key no component read into an error naming the key and the file, so a typo
// never falls back silently to a default. effective_ini() dumps every value in
// force, defaults included, for the output folder.
#pragma once

#include <map>
#include <string>
#include <utility>
#include <vector>

namespace hmt {

class Config {
 public:
  Config() = default;

  // Parses INI text: "[section]" headers, "key = value" lines, comments
  // starting with ';' or '#'. `origin` names the text in error messages.
  static Config from_string(const std::string& text, const std::string& origin);
  static Config from_file(const std::string& path);

  // "SECTION.key=value", as given on the command line with --set.
  void apply_override(const std::string& assignment);

  double get_double(const std::string& section, const std::string& key,
                    double default_value);
  int get_int(const std::string& section, const std::string& key,
              int default_value);
  bool get_bool(const std::string& section, const std::string& key,
                bool default_value);
  std::string get_string(const std::string& section, const std::string& key,
                         const std::string& default_value);

  bool has(const std::string& section, const std::string& key) const;

  // Every (section, key) given, by the text or by overrides, sorted.
  std::vector<std::pair<std::string, std::string>> keys() const;

  // Throws ConfigError naming the first key present but never read.
  void check_all_used() const;

  // "[section]\nkey = value\n" for every key read so far, sorted.
  std::string effective_ini() const;

  const std::string& origin() const { return origin_; }

 private:
  struct Entry {
    std::string value;
    std::string where;  // "file:line" or "--set"
    bool used = false;
  };
  // Returns the raw entry or nullptr, marking it used.
  const Entry* lookup(const std::string& section, const std::string& key);
  void record(const std::string& section, const std::string& key,
              const std::string& value);
  [[noreturn]] void bad_value(const std::string& section,
                              const std::string& key, const Entry& e,
                              const char* expected) const;

  std::string origin_ = "<defaults>";
  std::map<std::string, std::map<std::string, Entry>> entries_;
  std::map<std::string, std::map<std::string, std::string>> effective_;
};

// Throws ConfigError "[section] key = value: must be <what>" when !ok.
void require(bool ok, const std::string& section, const std::string& key,
             const std::string& what);

}  // namespace hmt
