// Reading case.toml: typed access by dotted key with units, defaults, and bookkeeping of every key
// read, so that any key nobody asked for is reported as unknown. Every error names the file, the
// key, the value and what is allowed (InputError, exit code 2).
#pragma once
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <toml++/toml.h>

#include "bagdem/units.hpp"
#include "bagdem/vec3.hpp"

namespace bagdem {

// Random seeds: any integer from 0 to this (a negative seed is a typo, not a seed).
inline constexpr long long kMaxSeed = 9223372036854775807LL;

class CaseReader {
 public:
  // Parses `file`, then applies overrides "a.b.c=value" (value in TOML syntax; a bare word that is
  // not valid TOML is taken as a string).
  CaseReader(const std::string& file, const std::vector<std::string>& overrides);

  const std::string& file() const { return file_; }
  const toml::table& root() const { return root_; }
  bool has(const std::string& key) const;
  // The value at key is a string (false when absent).
  bool is_string(const std::string& key) const;
  // Child keys of a table (e.g. the material names under "materials"); marks the table as read.
  std::vector<std::string> keys(const std::string& table) const;
  // Number of elements of an array (of tables) at key, 0 if absent.
  std::size_t array_size(const std::string& key) const;

  // A quantity: a number (SI) or a string with units of the expected dimension.
  double quantity(const std::string& key, Dimension d) const;
  double quantity(const std::string& key, Dimension d, double fallback) const;
  // A quantity or the word "auto" (nullopt).
  std::optional<double> quantity_or_auto(const std::string& key, Dimension d) const;
  Vec3 vector(const std::string& key, Dimension d, const Vec3& fallback) const;
  Vec3 vector(const std::string& key, Dimension d) const;
  std::string string(const std::string& key, const std::string& fallback) const;
  std::string string(const std::string& key) const;
  // A string that must be one of `allowed`.
  std::string choice(const std::string& key, const std::vector<std::string>& allowed,
                     const std::string& fallback) const;
  long long integer(const std::string& key, long long fallback) const;
  // An integer in [lo, hi].
  long long integer(const std::string& key, long long fallback, long long lo, long long hi) const;
  bool boolean(const std::string& key, bool fallback) const;
  // Rows of numbers (e.g. explicit positions [[x,y,z], ...]), each a quantity of dimension d.
  std::vector<Vec3> vector_list(const std::string& key, Dimension d) const;

  // Throws InputError naming `key` and its current value with the message `allowed`. When `key` is
  // absent and its table holds an unread key a typo away from it, names that key instead.
  [[noreturn]] void fail(const std::string& key, const std::string& allowed) const;
  // After everything was read: throws for the first key nobody asked for, with the nearest key the
  // loader asked for in the same table (edit distance), or the list of those keys.
  void reject_unknown_keys() const;
  // The value at key as written in TOML ("(missing)" when absent).
  std::string value_text(const std::string& key) const;
  // The path of the file the case names at `key`, relative to its directory `dir`, its contents
  // fingerprinted at once into text() and files(): an edited file is a changed case (a resume, a
  // study's points, a map's damper and the commands that read results.h5 refuse it).
  std::string file_path(const std::string& key, const std::string& dir) const;
  // Each file named so far: key -> "fnv1a64 <16 hex digits>, <size> bytes" ("not found" when absent).
  const std::map<std::string, std::string>& files() const { return files_; }
  // The TOML text of the case with overrides applied, then a comment line for each file it reads
  // ("# reads <key> = <fingerprint>").
  std::string text() const;
  // Each key read with a default (given or not; "auto" for quantity_or_auto) -> that default in SI
  // as text (si_text): a key given at its default value is the same damper as the key left out (a
  // map's damper record). Not a key whose presence the loader asks (has, is_string): its presence
  // alone may change the scene (a saved bag is moved only when bag.centre is given).
  std::map<std::string, std::string> defaults() const;

 private:
  const toml::node* node(const std::string& key) const;  // marks key and parents as read
  double to_quantity(const toml::node& n, const std::string& key, Dimension d) const;
  std::string unknown_key_message(const std::string& path) const;
  // An unread key of the case that looks like a typo of the absent `key`.
  std::optional<std::string> misspelling_of(const std::string& key) const;

  std::string file_;
  toml::table root_;
  mutable std::set<std::string> read_;   // keys present in the case and read
  mutable std::set<std::string> asked_;  // keys asked for, present or not: the allowed keys
  mutable std::map<std::string, std::string> files_;  // file_path's fingerprints, by key
  mutable toml::table defaults_;                      // the defaults offered, by dotted key (a flat key each)
  mutable std::set<std::string> presence_;            // keys whose presence was asked (has, is_string)
  template <class T>
  T defaulted(const std::string& key, const T& value) const;
};

// A TOML value in SI as text: numbers to 12 digits, a string with a unit converted ("4 mm" ->
// 0.004; -0 is 0), other strings as they are, arrays element by element ("[a, b, c]").
std::string si_text(const toml::node& n);

// The one of `candidates` nearest to `name` in edit distance, if it is close enough to be what a
// typo of `name` meant (at most 2 edits, or a third of the longer name).
std::optional<std::string> nearest_key(const std::string& name, const std::vector<std::string>& candidates);

// A string as a TOML value, quoted and escaped (for an override built from text such as a path:
// "a\"b" for a"b).
std::string toml_string(const std::string& text);

// Splits "a.b.0.c" into its parts.
std::vector<std::string> split_key(const std::string& key);

// Every leaf under `node` as ("prefix.key", its node), tables' keys in order, an array of tables
// by index ("bag.strings.0.stiffness"), an array of values as one leaf; keys in `skip` (with all
// under them) left out. `prefix` "" for a whole case.
std::vector<std::pair<std::string, const toml::node*>> toml_leaves(const toml::node& node, const std::string& prefix,
                                                                   const std::vector<std::string>& skip = {});

}  // namespace bagdem
