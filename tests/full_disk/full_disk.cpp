// Test support: a disk that fills up, preloaded into the bagdem binary (LD_PRELOAD) by the
// FullDisk tests. Writes to regular files succeed until BAGDEM_FULL_DISK_BYTES bytes have been
// written to them in this process; from then on every such write fails with ENOSPC, as on a full
// file system. Writes to anything else (the terminal, pipes) pass through.
#include <dlfcn.h>
#include <errno.h>
#include <stdlib.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <sys/uio.h>
#include <unistd.h>

#include <atomic>
#include <cstdint>

namespace {

std::atomic<long long> g_written{0};

long long budget() {
  static const long long b = [] {
    const char* s = getenv("BAGDEM_FULL_DISK_BYTES");
    return s ? atoll(s) : -1;
  }();
  return b;
}

// True when `n` more bytes to `fd` would not fit: the write must fail with ENOSPC.
bool full(int fd, std::size_t n) {
  if (budget() < 0 || fd <= 2) return false;
  struct stat st;
  if (fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) return false;
  if (g_written.load() + static_cast<long long>(n) > budget()) {
    g_written.store(budget() + 1);  // full stays full
    errno = ENOSPC;
    return true;
  }
  g_written += static_cast<long long>(n);
  return false;
}

template <class F>
F next(const char* name) {
  return reinterpret_cast<F>(dlsym(RTLD_NEXT, name));
}

}  // namespace

extern "C" {

ssize_t write(int fd, const void* buf, size_t n) {
  static auto real = next<ssize_t (*)(int, const void*, size_t)>("write");
  return full(fd, n) ? -1 : real(fd, buf, n);
}

ssize_t pwrite(int fd, const void* buf, size_t n, off_t at) {
  static auto real = next<ssize_t (*)(int, const void*, size_t, off_t)>("pwrite");
  return full(fd, n) ? -1 : real(fd, buf, n, at);
}

ssize_t pwrite64(int fd, const void* buf, size_t n, off64_t at) {
  static auto real = next<ssize_t (*)(int, const void*, size_t, off64_t)>("pwrite64");
  return full(fd, n) ? -1 : real(fd, buf, n, at);
}

ssize_t writev(int fd, const struct iovec* v, int count) {
  static auto real = next<ssize_t (*)(int, const struct iovec*, int)>("writev");
  std::size_t n = 0;
  for (int k = 0; k < count; ++k) n += v[k].iov_len;
  return full(fd, n) ? -1 : real(fd, v, count);
}

}  // extern "C"
