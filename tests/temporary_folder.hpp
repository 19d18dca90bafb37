#pragma once
// A fresh folder for one test in one process, removed when it goes out of scope. The name holds
// the process id and the running test's name, so that suites run side by side on one machine (two
// builds, two clones) never share a folder.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>
#include <system_error>

namespace test {

class TemporaryFolder {
 public:
  explicit TemporaryFolder(const std::string& label = "test") {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    const std::string test_name = info != nullptr ? std::string(info->test_suite_name()) + "." + info->name() : "";
    path_ = std::filesystem::temp_directory_path() /
            ("cardiosph_" + label + "_" + std::to_string(::getpid()) + "_" + test_name);
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~TemporaryFolder() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  TemporaryFolder(const TemporaryFolder&) = delete;
  TemporaryFolder& operator=(const TemporaryFolder&) = delete;

  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path operator/(const std::string& name) const { return path_ / name; }

 private:
  std::filesystem::path path_;
};

}  // namespace test
