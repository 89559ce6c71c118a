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

// SIGINT or SIGTERM stopped a study: what it keeps and how to go on (exit 128 + the signal).
class Interrupted : public std::runtime_error {
 public:
  Interrupted(int signal, const std::string& what) : std::runtime_error(what), signal(signal) {}
  int signal;
};

inline constexpr int kExitInputError = 2;
inline constexpr int kExitRunError = 3;

// The exit code of an error, the same for every command: bad input 2, a run that went unstable 3,
// a signal 128 + it, anything else (I/O, a full disk) 1.
inline int exit_code_of(const std::exception& e) {
  if (dynamic_cast<const InputError*>(&e)) return kExitInputError;
  if (dynamic_cast<const RunError*>(&e)) return kExitRunError;
  if (const auto* i = dynamic_cast<const Interrupted*>(&e)) return 128 + i->signal;
  return 1;
}

// How stderr names an error: "interrupted" for a signal (not a fault), else "error".
inline const char* error_label(const std::exception& e) { return dynamic_cast<const Interrupted*>(&e) ? "interrupted" : "error"; }

// The same once a study's runs have started, where bad input is no longer "nothing was run": 1.
inline int exit_code_after_runs(const std::exception& e) {
  const int code = exit_code_of(e);
  return code == kExitInputError ? 1 : code;
}

}  // namespace bagdem
