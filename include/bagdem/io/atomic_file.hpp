// Writing a small file (summary.json, a CSV table, a marker) so that a reader never sees half of it.
#pragma once
#include <filesystem>
#include <string>

namespace bagdem {

// Writes `text` to `path` atomically (temporary name, then rename); std::runtime_error naming the
// file and the system's reason when it cannot be written (a full disk).
void write_atomically(const std::filesystem::path& path, const std::string& text);

}  // namespace bagdem
