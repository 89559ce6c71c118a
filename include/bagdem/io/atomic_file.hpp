// Writing a small file (summary.json, a CSV table, a marker) so that a reader never sees half of it.
#pragma once
#include <filesystem>
#include <functional>
#include <string>

namespace bagdem {

// Writes `text` to `path` atomically (temporary name, then rename); std::runtime_error naming the
// file and the system's reason when it cannot be written (a full disk).
void write_atomically(const std::filesystem::path& path, const std::string& text);

// Before writing at a path the user gave (`option`, e.g. "--to"): InputError (exit 2) naming the
// option and the path when it is a directory or another file that is not a regular one (a device),
// or a regular file that `ours` (given its path and its first 512 bytes) does not take for an earlier
// output of the same kind (another command's results, a file of the user's). Nothing is replaced
// but what the command itself wrote there before.
void check_output_target(const std::filesystem::path& path, const std::string& option,
                         const std::function<bool(const std::filesystem::path&, const std::string&)>& ours, const std::string& kind);

// A CSV table's head as bagdem writes them: a first line of `name [unit]` entries.
bool is_bagdem_table_head(const std::string& head);

// A file's first 512 bytes (fewer if it is shorter; empty if it cannot be read): what
// check_output_target shows its `ours`.
std::string file_head(const std::filesystem::path& path);

}  // namespace bagdem
