// Text files, gzip-compressed or not (io/text_file.hpp), read through zlib's gz* interface.
#include "bagdem/io/text_file.hpp"

#include <zlib.h>

#include <stdexcept>

namespace bagdem {

std::optional<std::string> read_text_file(const std::string& path) {
  gzFile f = gzopen(path.c_str(), "rb");
  if (!f) return std::nullopt;
  std::string text;
  char buf[1 << 16];
  int n = 0;
  while ((n = gzread(f, buf, sizeof buf)) > 0) text.append(buf, static_cast<std::size_t>(n));
  int err = Z_OK;
  const std::string what = n < 0 ? gzerror(f, &err) : "";
  // gzclose reports a stream cut short (Z_BUF_ERROR) that gzread may have let through.
  const int closed = gzclose(f);
  if (n < 0 || closed != Z_OK)
    throw std::runtime_error("cannot read " + path + ": " + (n < 0 ? what : closed == Z_BUF_ERROR ? "the gzip stream ends early (a truncated file)" : "read error"));
  return text;
}

}  // namespace bagdem
