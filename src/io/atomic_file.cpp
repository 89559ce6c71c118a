// Atomic writes of small files (io/atomic_file.hpp).
#include "bagdem/io/atomic_file.hpp"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <stdexcept>

#include "bagdem/error.hpp"

namespace bagdem {

void check_output_target(const std::filesystem::path& path, const std::string& option,
                         const std::function<bool(const std::filesystem::path&, const std::string&)>& ours, const std::string& kind) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (!fs::exists(st)) return;
  if (!fs::is_regular_file(st))
    throw InputError(option, "", path.string(), std::string("is ") + (fs::is_directory(st) ? "a directory" : "not a regular file") +
                                                    ": give the path of the file to write (" + kind + ")");
  if (!ours(path, file_head(path)))
    throw InputError(option, "", path.string(), "holds a file that is not " + kind + " (another command's results, or a file of yours), "
                                                "which it would replace: give another path, or move that file away");
}

std::string file_head(const std::filesystem::path& path) {
  std::ifstream f(path, std::ios::binary);
  std::string head(512, '\0');
  f.read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<std::size_t>(f.gcount()));
  return head;
}

bool is_bagdem_table_head(const std::string& head) {
  std::string line = head.substr(0, head.find('\n'));
  if (line.size() == head.size()) line = line.substr(0, line.rfind(','));  // a head cut within its first line: its whole cells
  if (line.empty()) return false;
  std::size_t at = 0;
  while (at <= line.size()) {
    const std::size_t comma = std::min(line.find(',', at), line.size());
    std::string cell = line.substr(at, comma - at);
    if (!cell.empty() && cell.back() == '\r') cell.pop_back();
    const std::size_t open = cell.rfind(" [");
    if (open == std::string::npos || open == 0 || cell.back() != ']') return false;
    at = comma + 1;
  }
  return true;
}

void write_atomically(const std::filesystem::path& path, const std::string& text) {
  const std::filesystem::path tmp = path.string() + ".part";
  {
    std::ofstream f(tmp, std::ios::binary);
    f << text;
    f.close();  // the last bytes reach the disk here, or fail here
    if (!f) throw std::runtime_error("cannot write " + tmp.string() + ": " + std::strerror(errno));
  }
  std::filesystem::rename(tmp, path);
}

}  // namespace bagdem
