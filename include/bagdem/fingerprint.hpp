// Fingerprints: FNV-1a over 64 bits (Fowler, Noll and Vo; http://www.isthe.com/chongo/tech/comp/fnv/),
// to tell an edited text or file from the one recorded. Not a security measure.
#pragma once
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <optional>
#include <string>
#include <string_view>

namespace bagdem {

// FNV's 64-bit offset basis.
inline constexpr std::uint64_t kFnvBasis = 14695981039346656037ULL;

inline std::uint64_t fnv1a64(const char* data, std::size_t n, std::uint64_t basis = kFnvBasis) {
  std::uint64_t h = basis;
  for (std::size_t k = 0; k < n; ++k) h = (h ^ static_cast<unsigned char>(data[k])) * 1099511628211ULL;
  return h;
}

// A hash as 16 hex digits.
inline std::string hex16(std::uint64_t h) {
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h));
  return buf;
}

// A text's or a file's bytes as the fingerprints bagdem records them: "fnv1a64 HEX, N bytes".
inline std::string fingerprint_text(std::string_view bytes) {
  return "fnv1a64 " + hex16(fnv1a64(bytes.data(), bytes.size())) + ", " + std::to_string(bytes.size()) + " bytes";
}
// The file's (std::nullopt when it cannot be opened).
inline std::optional<std::string> file_fingerprint(const std::filesystem::path& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) return std::nullopt;
  const std::string bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  return fingerprint_text(bytes);
}

}  // namespace bagdem
