// JSON string escaping (io/json.hpp).
#include "bagdem/io/json.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>

#include "bagdem/error.hpp"

namespace bagdem {

std::string json_number_text(double x, int digits) {
  if (!std::isfinite(x)) return "null";
  char b[64];
  std::snprintf(b, sizeof b, "%.*g", digits, x);
  return b;
}

std::string json_escape(const std::string& s) {
  std::string o;
  for (char c : s) {
    if (c == '"' || c == '\\') o += '\\';
    if (c == '\n') {
      o += "\\n";
      continue;
    }
    o += c;
  }
  return o;
}

nlohmann::ordered_json read_json(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path.string(), "", "", "cannot be opened");
  try {
    return nlohmann::ordered_json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(path.string(), "", "", std::string("is not a JSON document: ") + e.what());
  }
}

double json_number(const nlohmann::ordered_json& doc, const std::string& pointer) {
  const nlohmann::json::json_pointer at(pointer);
  if (!doc.contains(at) || !doc.at(at).is_number()) return std::nan("");
  return doc.at(at).get<double>();
}

}  // namespace bagdem
