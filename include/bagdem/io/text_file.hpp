// A whole text file read into memory, gzip-compressed or not (zlib reads a file that is not
// compressed as it is): the particle files of a case (a LAMMPS data file, a CSV), which may be given
// as name.gz.
#pragma once
#include <optional>
#include <string>

namespace bagdem {

// The text of the file at `path`, decompressed when it is gzip; std::nullopt when it cannot be
// opened. Throws std::runtime_error naming the file when it is damaged (a truncated or corrupt
// gzip stream) or cannot be read.
std::optional<std::string> read_text_file(const std::string& path);

}  // namespace bagdem
