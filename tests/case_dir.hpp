// Test support: a case directory in the temporary directory, removed when the object goes.
#pragma once
#include <filesystem>
#include <fstream>
#include <random>
#include <string>

namespace bagdem::testing {

class CaseDir {
 public:
  explicit CaseDir(const std::string& case_toml) {
    std::random_device rd;
    path_ = std::filesystem::temp_directory_path() / ("bagdem_case_" + std::to_string(rd()) + std::to_string(rd()));
    std::filesystem::create_directories(path_);
    write("case.toml", case_toml);
  }
  ~CaseDir() { std::filesystem::remove_all(path_); }
  CaseDir(const CaseDir&) = delete;
  CaseDir& operator=(const CaseDir&) = delete;
  void write(const std::string& name, const std::string& text) const { std::ofstream(path_ / name) << text; }
  std::string str() const { return path_.string(); }

 private:
  std::filesystem::path path_;
};

}  // namespace bagdem::testing
