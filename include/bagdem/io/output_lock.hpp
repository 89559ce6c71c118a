// One writer per output directory. Two runs given the same --out would write the same
// results.h5.part; HDF5 truncates a file when it creates it, before its own lock refuses the
// second writer, so the first run's results would be destroyed. A run therefore holds an
// exclusive advisory lock (flock) on OUT/.bagdem-lock while it writes, and a second run into OUT
// is refused before it touches anything. A study's rounds, maps and points lie inside its OUT:
// a run or study into a directory inside one that another process holds is refused too, but for
// the study's own children (share_output_with_children).
#pragma once
#include <filesystem>
#include <optional>

namespace bagdem {

// Lets the processes this one starts from now on write inside `dir` while it (or its MPI rank 0)
// holds dir's lock: names it in their environment (BAGDEM_ENCLOSING_OUTPUTS).
void share_output_with_children(const std::filesystem::path& dir);

// Who writes an output directory: a run (results.h5 and its tables at its top) or a study (sweep,
// characterize, trade, calibrate, design: study.h5 and point directories, its runs inside).
enum class OutputOwner { run, study };

// Refuses (InputError naming the directory and what it holds) to write `as` into a directory that
// holds the other's outputs: a study's merged tables would replace a run's, and a run would delete
// a study's tables and leave its points beside a single run that export then takes for the study.
void refuse_other_outputs(const std::filesystem::path& dir, OutputOwner as);

// An output directory that is a file (or a device): InputError naming --out, before anything is
// written (refuse_other_outputs and OutputLock ask it too).
void refuse_a_file(const std::filesystem::path& dir);

// Refuses (InputError) when a process holds dir's lock now (before a study clears a point's
// directory that a run started by hand may be writing).
void refuse_if_locked(const std::filesystem::path& dir);

class OutputLock {
 public:
  // Creates `dir` if need be and locks it; InputError naming the directory when another process
  // holds the lock, or holds that of a directory `dir` lies inside (std::runtime_error when the
  // lock file cannot be made). The lock file is left in
  // place (removing it would let a third run lock a new file while the first still writes).
  explicit OutputLock(const std::filesystem::path& dir);
  ~OutputLock();
  OutputLock(const OutputLock&) = delete;
  OutputLock& operator=(const OutputLock&) = delete;

 private:
  int fd_ = -1;
};

// The lock of an output directory that a command reads and writes tables in (reduce, compare,
// export): refused while a run or a study writes there, so that no table is made from a record
// being replaced. None when the directory does not exist (the command then refuses by its own
// message, and makes no directory).
inline std::optional<OutputLock> lock_existing(const std::filesystem::path& dir) {
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec)) return std::nullopt;
  return std::optional<OutputLock>(std::in_place, dir);
}

}  // namespace bagdem
