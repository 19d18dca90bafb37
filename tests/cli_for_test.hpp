#pragma once
// Runs the command line in this process as `cardiosph <args>`, capturing its exit code and output.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "apps/cli.hpp"

namespace test {

struct CliRun {
  int code = 0;
  std::string out, err;
};

inline CliRun run_cli(std::vector<std::string> args) {
  args.insert(args.begin(), "cardiosph");
  std::vector<const char*> argv;
  for (const auto& a : args) argv.push_back(a.c_str());
  testing::internal::CaptureStderr();
  testing::internal::CaptureStdout();
  CliRun r;
  r.code = cardiosph::run_cli(static_cast<int>(argv.size()), argv.data());
  r.out = testing::internal::GetCapturedStdout();
  r.err = testing::internal::GetCapturedStderr();
  return r;
}

}  // namespace test
