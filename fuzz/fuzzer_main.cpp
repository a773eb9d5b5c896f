// libFuzzer entry, built once per target with OMNISHADOW_FUZZ_CHECK naming the check in fuzz_entries.h.
// A violated contract aborts, so libFuzzer saves the input as a crash artifact.
#include <cstdio>
#include <cstdlib>

#include "fuzz/fuzz_entries.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::string violation = omnishadow::fuzz::OMNISHADOW_FUZZ_CHECK(data, size);
  if (!violation.empty()) {
    std::fprintf(stderr, "contract violated: %s\n", violation.c_str());
    std::abort();
  }
  return 0;
}
