#pragma once
// A test fixture that gives each test a fresh directory under the system's temporary folder,
// root_ = <tmp>/talus_<suite>_<test>_<pid>_<random>, removed with everything in it afterwards.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <random>
#include <string>
#include <system_error>

namespace talus::test_support {

class TemporaryDirectoryTest : public ::testing::Test {
protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    const std::filesystem::path base = std::filesystem::temp_directory_path();
    std::random_device rd;
    for (int attempt = 0; attempt < 100 && root_.empty(); ++attempt) {
      const std::filesystem::path candidate =
          base / ("talus_" + std::string(info->test_suite_name()) + "_" + info->name() + "_" +
                  std::to_string(::getpid()) + "_" + std::to_string(rd()));
      std::error_code ec;
      if (std::filesystem::create_directory(candidate, ec))
        root_ = candidate;
    }
    ASSERT_FALSE(root_.empty()) << "cannot create a temporary directory in " << base;
  }
  void TearDown() override {
    std::error_code ec;
    if (!root_.empty())
      std::filesystem::remove_all(root_, ec);
  }

  std::filesystem::path root_;
};

} // namespace talus::test_support
