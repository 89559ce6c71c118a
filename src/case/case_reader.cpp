#include "bagdem/case/case_reader.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <functional>
#include <sstream>
#include <type_traits>

#include "bagdem/error.hpp"
#include "bagdem/fingerprint.hpp"

namespace bagdem {

std::vector<std::string> split_key(const std::string& key) {
  std::vector<std::string> parts;
  std::string cur;
  for (char c : key) {
    if (c == '.') {
      parts.push_back(cur);
      cur.clear();
    } else {
      cur += c;
    }
  }
  parts.push_back(cur);
  return parts;
}

namespace {

bool is_index(const std::string& s) {
  return !s.empty() && s.find_first_not_of("0123456789") == std::string::npos;
}

// Descends one level: a table key or an array index.
toml::node* child(toml::node* n, const std::string& part) {
  if (!n) return nullptr;
  if (auto* t = n->as_table()) return t->get(part);
  if (auto* a = n->as_array(); a && is_index(part)) return a->get(std::stoul(part));
  return nullptr;
}

// A value as the case wrote it, on one line: strings quoted, floats in their shortest form that
// reads back the same (0.1, not toml++'s 0.10000000000000001), arrays element by element.
std::string render(const toml::node& n) {
  if (auto* str = n.as_string()) return '"' + str->get() + '"';
  if (n.is_table()) return "{...}";
  if (auto* a = n.as_array()) {
    std::string o = "[";
    for (std::size_t k = 0; k < a->size(); ++k) o += (k ? ", " : "") + render(*a->get(k));
    return o + "]";
  }
  if (auto* f = n.as_floating_point()) {
    const double x = f->get();
    if (std::isnan(x)) return "nan";
    char b[32];
    return std::string(b, std::to_chars(b, b + sizeof b, x).ptr);
  }
  std::ostringstream s;
  n.visit([&](auto&& v) { s << v; });
  return s.str();
}

// Edit distance between two keys: insertions, deletions, substitutions and swaps of neighbours
// (the optimal string alignment distance), so "cuont" is one edit from "count".
std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::vector<std::size_t>> d(a.size() + 1, std::vector<std::size_t>(b.size() + 1));
  for (std::size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
  for (std::size_t j = 0; j <= b.size(); ++j) d[0][j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i)
    for (std::size_t j = 1; j <= b.size(); ++j) {
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1)});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1]) d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
    }
  return d[a.size()][b.size()];
}

// Close enough to be a typo of one another. Loose (2 edits, or a third of the longer name) when
// choosing among the keys a table allows; strict (1 edit, or a quarter) when guessing which present
// key was meant for an absent one, since the loader has not asked for every key yet.
bool near_miss(const std::string& a, const std::string& b, bool strict) {
  const std::size_t len = std::max(a.size(), b.size());
  return edit_distance(a, b) <= (strict ? std::max<std::size_t>(1, len / 4) : std::max<std::size_t>(2, len / 3));
}

std::string parent_of(const std::string& path) {
  const auto dot = path.rfind('.');
  return dot == std::string::npos ? "" : path.substr(0, dot);
}

std::string leaf_of(const std::string& path) {
  const auto dot = path.rfind('.');
  return dot == std::string::npos ? path : path.substr(dot + 1);
}

}  // namespace

std::optional<std::string> nearest_key(const std::string& name, const std::vector<std::string>& candidates) {
  std::optional<std::string> best;
  std::size_t best_distance = 0;
  for (const std::string& c : candidates) {
    const std::size_t d = edit_distance(name, c);
    if (near_miss(name, c, false) && (!best || d < best_distance)) best = c, best_distance = d;
  }
  return best;
}

CaseReader::CaseReader(const std::string& file, const std::vector<std::string>& overrides) : file_(file) {
  try {
    root_ = toml::parse_file(file);
  } catch (const toml::parse_error& e) {
    std::ostringstream m;
    m << file << ":" << e.source().begin.line << ":" << e.source().begin.column
      << ": not valid TOML: " << e.description();
    throw InputError(m.str());
  }
  for (const std::string& o : overrides) {
    // "key = value" as a case file writes it is "key=value" (the key's spaces were part of its name).
    const auto eq = o.find('=');
    const auto first = o.find_first_not_of(" \t"), last = eq == std::string::npos ? eq : o.find_last_not_of(" \t", eq - 1);
    if (eq == std::string::npos || first == eq || last == std::string::npos || last < first)
      throw InputError("--set " + o + ": expected key=value, e.g. --set particles.balls.count=200");
    const std::string key = o.substr(first, last + 1 - first), val = o.substr(eq + 1);
    toml::table parsed;
    try {
      parsed = toml::parse("v = " + val);
    } catch (const toml::parse_error&) {
      parsed.insert("v", val);  // a bare word: a string
    }
    const auto parts = split_key(key);
    toml::node* n = &root_;
    for (std::size_t k = 0; k + 1 < parts.size(); ++k) {
      toml::node* next = child(n, parts[k]);
      if (!next) {
        auto* t = n->as_table();
        if (!t) throw InputError("--set " + o + ": '" + parts[k] + "' is not a table");
        next = &t->insert_or_assign(parts[k], toml::table{}).first->second;
      }
      n = next;
    }
    if (auto* t = n->as_table()) {
      t->insert_or_assign(parts.back(), *parsed.get("v"));
    } else if (auto* a = n->as_array(); a && is_index(parts.back()) && std::stoul(parts.back()) < a->size()) {
      a->replace(a->begin() + static_cast<long>(std::stoul(parts.back())), *parsed.get("v"));
    } else {
      throw InputError("--set " + o + ": cannot set '" + key + "'");
    }
  }
}

const toml::node* CaseReader::node(const std::string& key) const {
  const auto parts = split_key(key);
  const toml::node* n = &root_;
  std::string path;
  for (const auto& p : parts) {
    path += (path.empty() ? "" : ".") + p;
    asked_.insert(path);  // a key the loader looks for is an allowed key, present or not
  }
  path.clear();
  for (const auto& p : parts) {
    n = child(const_cast<toml::node*>(n), p);
    if (!n) return nullptr;
    path += (path.empty() ? "" : ".") + p;
    read_.insert(path);
  }
  return n;
}

std::string CaseReader::unknown_key_message(const std::string& path) const {
  const std::string parent = parent_of(path);
  const std::string where = parent.empty() ? "" : " in [" + parent + "]";
  // The keys allowed beside it: those the loader asked for in the same table.
  std::vector<std::string> allowed;
  for (const std::string& k : asked_)
    if (parent_of(k) == parent && k != path) allowed.push_back(leaf_of(k));
  if (const auto near = nearest_key(leaf_of(path), allowed))
    return "unknown key" + where + "; did you mean '" + (parent.empty() ? "" : parent + ".") + *near + "'?";
  std::string list;
  for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
  if (allowed.empty() || allowed.size() > 24) return "unknown key" + where + "; see docs/case-schema.md for the allowed keys";
  return "unknown key" + where + "; allowed there: " + list + " (docs/case-schema.md)";
}

std::optional<std::string> CaseReader::misspelling_of(const std::string& key) const {
  // The first part of `key` that is absent, and its table: a key there nobody read that is a near
  // miss of that part is the likely typo (e.g. "duraton" for a missing "duration").
  const auto parts = split_key(key);
  const toml::node* n = &root_;
  std::string path;
  for (const auto& p : parts) {
    const toml::node* next = child(const_cast<toml::node*>(n), p);
    if (!next) {
      const auto* t = n->as_table();
      if (!t) return std::nullopt;
      for (const auto& [k, v] : *t) {
        const std::string sibling = (path.empty() ? "" : path + ".") + std::string(k.str());
        if (!read_.count(sibling) && !asked_.count(sibling) && near_miss(std::string(k.str()), p, true)) return sibling;
      }
      return std::nullopt;
    }
    path += (path.empty() ? "" : ".") + p;
    n = next;
  }
  return std::nullopt;
}

bool CaseReader::has(const std::string& key) const {
  presence_.insert(key);
  return node(key) != nullptr;
}

bool CaseReader::is_string(const std::string& key) const {
  presence_.insert(key);
  const toml::node* n = node(key);
  return n && n->is_string();
}

std::vector<std::string> CaseReader::keys(const std::string& table) const {
  std::vector<std::string> out;
  const toml::node* n = table.empty() ? &root_ : node(table);
  if (!n) return out;
  const auto* t = n->as_table();
  if (!t) fail(table, "must be a table");
  for (const auto& [k, v] : *t) out.emplace_back(k.str());
  return out;
}

std::size_t CaseReader::array_size(const std::string& key) const {
  const toml::node* n = node(key);
  if (!n) return 0;
  if (!n->is_array()) fail(key, "must be an array");
  return n->as_array()->size();
}

std::string CaseReader::value_text(const std::string& key) const {
  const toml::node* n = node(key);
  return n ? render(*n) : "(missing)";
}

void CaseReader::fail(const std::string& key, const std::string& allowed) const {
  if (!node(key)) {
    if (const auto typo = misspelling_of(key)) {
      const toml::node* t = node(*typo);
      throw InputError(file_, *typo, render(*t),
                       "unknown key" + std::string(parent_of(*typo).empty() ? "" : " in [" + parent_of(*typo) + "]") +
                           "; did you mean '" + key + "'? (" + key + " " + allowed + ")");
    }
  }
  throw InputError(file_, key, value_text(key), allowed);
}

double CaseReader::to_quantity(const toml::node& n, const std::string& key, Dimension d) const {
  if (auto v = n.value<double>()) {  // integers convert too
    if (!std::isfinite(*v))
      fail(key, "must be a finite number (not inf or nan): a number in SI units or a string with units of dimension " + d.si_unit());
    return *v;
  }
  if (auto* s = n.as_string()) {
    std::string why;
    if (auto q = parse_quantity(s->get(), d, &why)) return *q;
    fail(key, why + " (a number in SI units, or a string with units of dimension " + d.si_unit() + ")");
  }
  fail(key, "must be a number in SI units or a string with units of dimension " + d.si_unit());
}

double CaseReader::quantity(const std::string& key, Dimension d) const {
  const toml::node* n = node(key);
  if (!n) fail(key, "is required (dimension " + d.si_unit() + ")");
  return to_quantity(*n, key, d);
}

// A key's default, offered whether the key is given or not: recorded (defaults()), then returned.
template <class T>
T CaseReader::defaulted(const std::string& key, const T& value) const {
  if constexpr (std::is_same_v<T, Vec3>)
    defaults_.insert_or_assign(key, toml::array{value.x(), value.y(), value.z()});
  else if constexpr (std::is_same_v<T, long long>)
    defaults_.insert_or_assign(key, static_cast<std::int64_t>(value));
  else
    defaults_.insert_or_assign(key, value);
  return value;
}

std::map<std::string, std::string> CaseReader::defaults() const {
  std::map<std::string, std::string> out;
  for (const auto& [key, value] : defaults_)
    if (!presence_.count(std::string(key.str()))) out[std::string(key.str())] = si_text(value);
  return out;
}

std::string si_text(const toml::node& n) {
  auto number = [](double x) {
    char b[32];
    std::snprintf(b, sizeof b, "%.12g", x == 0 ? 0.0 : x);  // -0 is 0
    return std::string(b);
  };
  if (const auto* i = n.as_integer()) return number(static_cast<double>(i->get()));
  if (const auto* d = n.as_floating_point()) return number(d->get());
  if (const auto* b = n.as_boolean()) return b->get() ? "true" : "false";
  if (const auto* s = n.as_string()) {
    const auto q = parse_any_quantity(s->get());
    return q ? number(q->si) : s->get();
  }
  if (const auto* a = n.as_array()) {
    std::string t = "[";
    for (std::size_t k = 0; k < a->size(); ++k) t += (k ? ", " : "") + si_text(*a->get(k));
    return t + "]";
  }
  return "(a date or time)";
}

double CaseReader::quantity(const std::string& key, Dimension d, double fallback) const {
  defaulted(key, fallback);
  return node(key) ? quantity(key, d) : fallback;
}

std::optional<double> CaseReader::quantity_or_auto(const std::string& key, Dimension d) const {
  defaulted(key, std::string("auto"));
  const toml::node* n = node(key);
  if (!n) return std::nullopt;
  if (auto* s = n->as_string(); s && s->get() == "auto") return std::nullopt;
  return to_quantity(*n, key, d);
}

Vec3 CaseReader::vector(const std::string& key, Dimension d) const {
  const toml::node* n = node(key);
  if (!n) fail(key, "is required: an array of 3 components of dimension " + d.si_unit());
  const auto* a = n->as_array();
  if (!a || a->size() != 3) fail(key, "must be an array of 3 components of dimension " + d.si_unit());
  Vec3 v;
  for (int k = 0; k < 3; ++k) v[k] = to_quantity(*a->get(static_cast<std::size_t>(k)), key, d);
  return v;
}

Vec3 CaseReader::vector(const std::string& key, Dimension d, const Vec3& fallback) const {
  defaulted(key, fallback);
  return node(key) ? vector(key, d) : fallback;
}

std::string CaseReader::string(const std::string& key) const {
  const toml::node* n = node(key);
  if (!n) fail(key, "is required (a string)");
  if (!n->is_string()) fail(key, "must be a string");
  return n->as_string()->get();
}

std::string CaseReader::string(const std::string& key, const std::string& fallback) const {
  defaulted(key, fallback);
  return node(key) ? string(key) : fallback;
}

std::string CaseReader::choice(const std::string& key, const std::vector<std::string>& allowed,
                               const std::string& fallback) const {
  const std::string v = string(key, fallback);
  for (const auto& a : allowed)
    if (v == a) return v;
  std::string list;
  for (const auto& a : allowed) list += (list.empty() ? "\"" : ", \"") + a + "\"";
  fail(key, "must be one of " + list);
}

long long CaseReader::integer(const std::string& key, long long fallback) const {
  defaulted(key, fallback);
  const toml::node* n = node(key);
  if (!n) return fallback;
  if (!n->is_integer()) fail(key, "must be an integer");
  return n->as_integer()->get();
}

long long CaseReader::integer(const std::string& key, long long fallback, long long lo, long long hi) const {
  const long long v = integer(key, fallback);
  if (v < lo || v > hi) fail(key, "must be an integer from " + std::to_string(lo) + " to " + std::to_string(hi));
  return v;
}

bool CaseReader::boolean(const std::string& key, bool fallback) const {
  defaulted(key, fallback);
  const toml::node* n = node(key);
  if (!n) return fallback;
  if (!n->is_boolean()) fail(key, "must be true or false");
  return n->as_boolean()->get();
}

std::vector<Vec3> CaseReader::vector_list(const std::string& key, Dimension d) const {
  std::vector<Vec3> out;
  const std::size_t n = array_size(key);
  for (std::size_t k = 0; k < n; ++k) out.push_back(vector(key + "." + std::to_string(k), d));
  return out;
}

void CaseReader::reject_unknown_keys() const {
  // Walk every leaf and table; the first one never read is unknown.
  std::function<void(const toml::node&, const std::string&)> walk = [&](const toml::node& n,
                                                                         const std::string& path) {
    if (!path.empty() && !read_.count(path)) throw InputError(file_, path, render(n), unknown_key_message(path));
    if (const auto* t = n.as_table()) {
      for (const auto& [k, v] : *t) walk(v, path.empty() ? std::string(k.str()) : path + "." + std::string(k.str()));
    } else if (const auto* a = n.as_array(); a && !path.empty()) {
      for (std::size_t i = 0; i < a->size(); ++i)
        if (a->get(i)->is_table()) walk(*a->get(i), path + "." + std::to_string(i));
    }
  };
  walk(root_, "");
}

std::string toml_string(const std::string& text) {
  std::ostringstream o;
  o << toml::value<std::string>(text);
  return o.str();
}

std::vector<std::pair<std::string, const toml::node*>> toml_leaves(const toml::node& n, const std::string& prefix,
                                                                   const std::vector<std::string>& skip) {
  std::vector<std::pair<std::string, const toml::node*>> out;
  if (std::find(skip.begin(), skip.end(), prefix) != skip.end()) return out;
  auto add = [&](const toml::node& child, const std::string& key) {
    const auto more = toml_leaves(child, prefix.empty() ? key : prefix + "." + key, skip);
    out.insert(out.end(), more.begin(), more.end());
  };
  if (const auto* t = n.as_table()) {
    for (const auto& [k, v] : *t) add(v, std::string(k.str()));
  } else if (const auto* a = n.as_array(); a && !a->empty() && a->get(0)->is_table()) {
    for (std::size_t k = 0; k < a->size(); ++k) add(*a->get(k), std::to_string(k));
  } else {
    out.emplace_back(prefix, &n);
  }
  return out;
}

std::string CaseReader::file_path(const std::string& key, const std::string& dir) const {
  const std::string path = (std::filesystem::path(dir) / string(key)).string();
  std::error_code ec;
  if (std::filesystem::exists(path, ec) && !std::filesystem::is_regular_file(path, ec))
    fail(key, "names " + std::string(std::filesystem::is_directory(path, ec) ? "a directory" : "no regular file") + " (" + path +
                  "): give a file, relative to the case directory");
  files_[key] = file_fingerprint(path).value_or("not found");
  return path;
}

std::string CaseReader::text() const {
  std::ostringstream s;
  s << root_;
  for (const auto& [key, print] : files_) s << "\n# reads " << key << " = " << print;
  return s.str();
}

}  // namespace bagdem
