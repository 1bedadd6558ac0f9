// libFuzzer target: recordings as `strata view` reads them (tools/view/Recording.h). Any input must be a
// checked recording or an error, never a crash, an uncaught exception, a stack overflow or a sanitizer
// report.
#include <cstddef>
#include <cstdint>

#include "FuzzInput.h"
#include "tools/view/Recording.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::filesystem::path path = strata::fuzz::WriteInput(data, size, "strata_fuzz_recording", ".json");
  (void)strata::view::ReadRecording(path);
  return 0;
}
