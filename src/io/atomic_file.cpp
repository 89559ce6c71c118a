// Atomic writes of small files (io/atomic_file.hpp).
#include "bagdem/io/atomic_file.hpp"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <stdexcept>

namespace bagdem {

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
