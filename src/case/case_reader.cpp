#include "bagdem/case/case_reader.hpp"

#include <functional>
#include <sstream>

#include "bagdem/error.hpp"

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

std::string render(const toml::node& n) {
  std::ostringstream s;
  if (auto* str = n.as_string()) {
    s << '"' << str->get() << '"';
  } else if (n.is_table()) {
    s << "{...}";
  } else {
    n.visit([&](auto&& v) { s << v; });
  }
  return s.str();
}

}  // namespace

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
    const auto eq = o.find('=');
    if (eq == std::string::npos || eq == 0)
      throw InputError("--set " + o + ": expected key=value, e.g. --set particles.balls.count=200");
    const std::string key = o.substr(0, eq), val = o.substr(eq + 1);
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
    n = child(const_cast<toml::node*>(n), p);
    if (!n) return nullptr;
    path += (path.empty() ? "" : ".") + p;
    read_.insert(path);
  }
  return n;
}

bool CaseReader::has(const std::string& key) const { return node(key) != nullptr; }

bool CaseReader::is_string(const std::string& key) const {
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
  throw InputError(file_, key, value_text(key), allowed);
}

double CaseReader::to_quantity(const toml::node& n, const std::string& key, Dimension d) const {
  if (auto v = n.value<double>()) return *v;  // integers convert too
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

double CaseReader::quantity(const std::string& key, Dimension d, double fallback) const {
  return has(key) ? quantity(key, d) : fallback;
}

std::optional<double> CaseReader::quantity_or_auto(const std::string& key, Dimension d) const {
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
  return has(key) ? vector(key, d) : fallback;
}

std::string CaseReader::string(const std::string& key) const {
  const toml::node* n = node(key);
  if (!n) fail(key, "is required (a string)");
  if (!n->is_string()) fail(key, "must be a string");
  return n->as_string()->get();
}

std::string CaseReader::string(const std::string& key, const std::string& fallback) const {
  return has(key) ? string(key) : fallback;
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
  const toml::node* n = node(key);
  if (!n) return fallback;
  if (!n->is_integer()) fail(key, "must be an integer");
  return n->as_integer()->get();
}

bool CaseReader::boolean(const std::string& key, bool fallback) const {
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
    if (!path.empty() && !read_.count(path)) {
      const auto dot = path.rfind('.');
      const std::string parent = dot == std::string::npos ? "" : path.substr(0, dot);
      throw InputError(file_, path, render(n),
                       "unknown key" + std::string(parent.empty() ? "" : " in [" + parent + "]") +
                           "; see docs/case-schema.md for the allowed keys");
    }
    if (const auto* t = n.as_table()) {
      for (const auto& [k, v] : *t) walk(v, path.empty() ? std::string(k.str()) : path + "." + std::string(k.str()));
    } else if (const auto* a = n.as_array(); a && !path.empty()) {
      for (std::size_t i = 0; i < a->size(); ++i)
        if (a->get(i)->is_table()) walk(*a->get(i), path + "." + std::to_string(i));
    }
  };
  walk(root_, "");
}

std::string CaseReader::text() const {
  std::ostringstream s;
  s << root_;
  return s.str();
}

}  // namespace bagdem
