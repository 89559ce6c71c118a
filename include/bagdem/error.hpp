// The two kinds of failure a user sees.
//  InputError: bad case input, found while reading and validating (exit code 2).
//  RunError:   the simulation became unphysical while running (exit code 3).
#pragma once
#include <stdexcept>
#include <string>

namespace bagdem {

// Bad input: names the file, the key, the value and what is allowed.
class InputError : public std::runtime_error {
 public:
  InputError(const std::string& file, const std::string& key, const std::string& value,
             const std::string& allowed)
      : std::runtime_error(format(file, key, value, allowed)) {}
  explicit InputError(const std::string& message) : std::runtime_error(message) {}

 private:
  static std::string format(const std::string& file, const std::string& key,
                            const std::string& value, const std::string& allowed) {
    std::string m = file;
    if (!key.empty()) m += ": key '" + key + "'";
    if (!value.empty()) m += " = " + value;
    m += ": " + allowed;
    return m;
  }
};

// The run went unstable or unphysical: says what happened and what to change.
class RunError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

inline constexpr int kExitInputError = 2;
inline constexpr int kExitRunError = 3;

// The exit code of an error, the same for every command: bad input 2, a run that went unstable 3,
// anything else (I/O, a full disk) 1.
inline int exit_code_of(const std::exception& e) {
  if (dynamic_cast<const InputError*>(&e)) return kExitInputError;
  if (dynamic_cast<const RunError*>(&e)) return kExitRunError;
  return 1;
}

}  // namespace bagdem
