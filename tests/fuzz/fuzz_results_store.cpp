// libFuzzer: results stores (SQLite files, docs/results-format.md "Results store") as `results check` reads them:
// the bytes written to a file, then checkResultsFile (the header, every map streamed and its AUC derived again,
// every claim, the grid when it is one of sweeps/grids). SQLite refuses a malformed file itself ("database disk
// image is malformed"); the designed refusal, ours or SQLite's, is std::runtime_error naming the file.
#include <fstream>
#include <string>

#include <unistd.h>

#include "fuzz_common.hpp"
#include "occsweep/sweeps/results_verify.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string file = "/tmp/fuzz-results-store-" + std::to_string(::getpid()) + ".db";
  {
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), std::streamsize(size));
  }
  try {
    (void)occsweep::checkResultsFile(file, "");
  } catch (const std::runtime_error&) {
  }
  return 0;
}
