// The libFuzzer entry of one target (FUZZ_TARGET, a name of cardiosph::fuzz::targets()).
#include <cstdlib>
#include <cstring>

#include "fuzz/fuzz_inputs.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const auto run = [] {
    for (const auto& t : cardiosph::fuzz::targets())
      if (std::strcmp(t.name, FUZZ_TARGET) == 0) return t.run;
    std::abort();
  }();
  run({data, size});
  return 0;
}
