// INI configuration with strict key checking.
//
// Every component reads its options through get(); each read marks the key as
// used and records the effective value (the file's, an override's, or the
// default). After all components are configured, check_all_used() turns any
// key no component read into an error naming the key and the file, so a typo
// never falls back silently to a default. effective_ini() dumps every value in
// force, defaults included, for the output folder.
//
// Configurations layer: overlay() puts one on top of another (the built-in
// defaults, then each --config file, then --set), a key of the upper one
// replacing the lower one's. Each entry remembers where it came from, so
// errors name the layer that gave the key, and the folder its relative paths
// are taken from (the file's).
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
  // starting with ';' or '#'. `origin` names the text in error messages;
  // `dir` is the folder relative paths in it are taken from (empty: none).
  static Config from_string(const std::string& text, const std::string& origin,
                            const std::string& dir = "");
  // The file's folder is its entries' `dir`.
  static Config from_file(const std::string& path);

  // "SECTION.key=value", as given on the command line with --set; a relative
  // path in it is taken from `dir`.
  void apply_override(const std::string& assignment, const std::string& dir = "");

  // Every entry of `upper` replaces this one's with the same section and key
  // (keys only `upper` has are added; nothing is read yet). origin() becomes
  // upper's.
  void overlay(const Config& upper);

  // The folder relative paths of [section] key are taken from (its layer's),
  // or "" when the key is absent or its layer has none.
  std::string dir_of(const std::string& section, const std::string& key) const;

  double get_double(const std::string& section, const std::string& key,
                    double default_value);
  int get_int(const std::string& section, const std::string& key,
              int default_value);
  bool get_bool(const std::string& section, const std::string& key,
                bool default_value);
  std::string get_string(const std::string& section, const std::string& key,
                         const std::string& default_value);

  bool has(const std::string& section, const std::string& key) const;

  // A key that takes a number or "auto" (a value derived later, e.g. from
  // the log). On entry *is_auto says which the default is; on return,
  // which was given, with a number in *value (left as is for "auto"). The
  // effective configuration records "auto" or the number used.
  void get_double_or_auto(const std::string& section, const std::string& key, double* value,
                          bool* is_auto);

  // Every entry's value as given (not read or checked), by section and key.
  std::map<std::string, std::map<std::string, std::string>> values() const;
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
    std::string dir;    // folder of relative paths (the file's)
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
