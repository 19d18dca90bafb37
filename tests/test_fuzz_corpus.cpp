// The fuzz corpus replayed (fuzz/corpus/<target>/*: the seeds and every input that once found a
// bug): each input must be read or rejected with the reader's own error, without a crash or
// another exception (fuzz/fuzz_inputs.hpp). The same inputs run under libFuzzer with ASan and UBSan
// in the fuzz build (docs/reliability.md).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

#include "fuzz/fuzz_inputs.hpp"

namespace {

namespace fs = std::filesystem;

TEST(FuzzCorpus, EveryInputIsReadOrRejectedCleanly) {
  const fs::path corpus = fs::path(CARDIOSPH_SOURCE_DIR) / "fuzz" / "corpus";
  ASSERT_TRUE(fs::is_directory(corpus)) << corpus;
  for (const auto& target : cardiosph::fuzz::targets()) {
    const fs::path folder = corpus / target.name;
    ASSERT_TRUE(fs::is_directory(folder)) << "no corpus for target " << target.name << " in " << folder;
    std::size_t inputs = 0;
    for (const auto& file : fs::directory_iterator(folder)) {
      std::ifstream in(file.path(), std::ios::binary);
      const std::vector<std::uint8_t> bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
      SCOPED_TRACE(file.path().string());
      EXPECT_NO_THROW(target.run(bytes));
      ++inputs;
    }
    EXPECT_GT(inputs, 0u) << target.name;
    std::cout << "  " << target.name << ": " << inputs << " inputs replayed\n";
  }
}

}  // namespace
