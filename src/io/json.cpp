// JSON string escaping (io/json.hpp).
#include "bagdem/io/json.hpp"

namespace bagdem {

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

}  // namespace bagdem
