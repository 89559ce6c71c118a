// One writer per output directory (io/output_lock.hpp).
#include "bagdem/io/output_lock.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

#include "bagdem/error.hpp"

namespace bagdem {

namespace {

constexpr const char* kEnclosing = "BAGDEM_ENCLOSING_OUTPUTS";  // directories a parent study writes in, ':'-separated

std::filesystem::path normal(const std::filesystem::path& dir) {
  std::error_code ec;
  const std::filesystem::path p = std::filesystem::weakly_canonical(std::filesystem::absolute(dir), ec);
  return ec ? std::filesystem::absolute(dir).lexically_normal() : p;
}

std::vector<std::string> enclosing_outputs() {
  std::vector<std::string> out;
  const char* env = std::getenv(kEnclosing);
  for (std::string list = env ? env : "", item; !list.empty();) {
    const auto colon = list.find(':');
    item = list.substr(0, colon);
    list = colon == std::string::npos ? "" : list.substr(colon + 1);
    if (!item.empty()) out.push_back(item);
  }
  return out;
}

// Whether another process holds the lock file at `lock` now (an absent file: no).
bool held_by_another(const std::filesystem::path& lock) {
  const int fd = ::open(lock.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return false;
  const bool held = ::flock(fd, LOCK_SH | LOCK_NB) != 0 && errno == EWOULDBLOCK;
  ::close(fd);
  return held;
}

// A directory inside one that another bagdem process writes now (a study's OUT holds the lock,
// and its rounds, maps and points lie inside it) is refused, unless that study is our own parent
// (it named its OUT in the environment when it started us).
void refuse_inside_another(const std::filesystem::path& dir) {
  const std::vector<std::string> ours = enclosing_outputs();
  const std::filesystem::path d = normal(dir);
  for (std::filesystem::path a = d.parent_path(); !a.empty(); a = a.parent_path()) {
    const std::filesystem::path lock = a / ".bagdem-lock";
    if (std::find(ours.begin(), ours.end(), a.string()) == ours.end() && held_by_another(lock))
      throw InputError(dir.string() + ": lies inside " + a.string() + ", which another bagdem process (a study) is writing now; "
                       "wait for it to end, or give an --out outside it");
    if (a == a.root_path()) break;
  }
}

}  // namespace

void refuse_a_file(const std::filesystem::path& dir) {
  std::error_code ec;
  if (std::filesystem::exists(dir, ec) && !std::filesystem::is_directory(dir, ec))
    throw InputError("--out", "", dir.string(), "is a file, not a directory: give a directory for the outputs (nothing was written)");
}

void refuse_other_outputs(const std::filesystem::path& dir, OutputOwner as) {
  namespace fs = std::filesystem;
  refuse_a_file(dir);
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return;
  std::string found;
  if (as == OutputOwner::study) {
    for (const char* f : {"results.h5", "results.h5.part", "checkpoint.bin"})
      if (found.empty() && fs::exists(dir / f, ec)) found = std::string("a run's ") + f;
  } else {
    // A study's own files at its top, and its point and round directories.
    for (const char* f : {"study.h5", "calibration.json", "calibrate.csv", "map.csv", "design.csv", "trade.csv"})
      if (found.empty() && fs::exists(dir / f, ec)) found = std::string("a study's ") + f;
    for (const auto& e : fs::directory_iterator(dir, ec)) {
      const std::string name = e.path().filename().string();
      if (found.empty() && e.is_directory(ec) && (name.rfind("round-", 0) == 0 || (name.rfind("point-", 0) == 0 && fs::exists(e.path() / "point.toml", ec))))
        found = "a study's directory " + name;
    }
    // A study's point, unless a study that started this run writes around it (it names its OUT in
    // our environment; a calibration's points lie in its rounds).
    const std::vector<std::string> ours = enclosing_outputs();
    bool started_by_it = false;
    for (fs::path a = normal(dir).parent_path(); !a.empty() && !started_by_it; a = a == a.root_path() ? fs::path() : a.parent_path())
      started_by_it = std::find(ours.begin(), ours.end(), a.string()) != ours.end();
    if (found.empty() && !started_by_it && fs::exists(dir / "point.toml", ec))
      found = "a study's point.toml (it is a point of the study in " + normal(dir).parent_path().string() + ")";
  }
  if (!found.empty())
    throw InputError(dir.string() + ": holds " + found + (as == OutputOwner::study ? " (bagdem run)" : " (bagdem sweep, characterize, trade, calibrate or design)") +
                     "; a " + (as == OutputOwner::study ? "study" : "run") +
                     " would mix its outputs with those. Give another --out, or delete what is there");
}

void refuse_if_locked(const std::filesystem::path& dir) {
  if (held_by_another(dir / ".bagdem-lock"))
    throw InputError(dir.string() + ": another bagdem process is writing there now (it holds its lock), so it is not cleared "
                     "for a new run; stop that process or wait for it, then run again");
}

void share_output_with_children(const std::filesystem::path& dir) {
  const char* env = std::getenv(kEnclosing);
  const std::string list = (env && *env ? std::string(env) + ":" : std::string()) + normal(dir).string();
  ::setenv(kEnclosing, list.c_str(), 1);
}

OutputLock::OutputLock(const std::filesystem::path& dir) {
  refuse_inside_another(dir);
  refuse_a_file(dir);
  std::filesystem::create_directories(dir);
  const std::filesystem::path path = dir / ".bagdem-lock";
  fd_ = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd_ < 0) throw std::runtime_error("cannot create " + path.string() + ": " + std::strerror(errno));
  if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    const int err = errno;
    ::close(fd_);
    fd_ = -1;
    if (err == EWOULDBLOCK)
      throw InputError(dir.string() + ": another bagdem run is writing to this output directory now; wait for it to end, or give "
                       "another --out");
    throw std::runtime_error("cannot lock " + path.string() + ": " + std::strerror(err));
  }
}

OutputLock::~OutputLock() {
  if (fd_ >= 0) ::close(fd_);  // closing releases the lock
}

}  // namespace bagdem
