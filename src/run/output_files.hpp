// Internal to src/run: writing the small result files (summary.json, sweep.csv) so that a reader
// never sees half of one.
#pragma once
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

namespace bagdem {

// Writes `text` to `path` atomically (temporary name, then rename).
inline void write_atomically(const std::filesystem::path& path, const std::string& text) {
  const std::filesystem::path tmp = path.string() + ".part";
  {
    std::ofstream f(tmp, std::ios::binary);
    f << text;
    if (!f) throw std::runtime_error("cannot write " + tmp.string());
  }
  std::filesystem::rename(tmp, path);
}

// A string for a JSON document: quotes, backslashes and newlines escaped.
inline std::string json_escape(const std::string& s) {
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
