// libFuzzer: results files as `results check` reads them: sweeps' parseResults after JSON parsing (every claim
// checked without the grid file, verifyClaims), then checkAgainstGrid (the grid's parameters and the selection's
// coverage, GridChecker) when the named grid is one of sweeps/grids. The designed refusal is
// std::runtime_error naming the file and field.
#include "fuzz_common.hpp"
#include "occsweep/sweeps/merge.hpp"
#include "occsweep/sweeps/results.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return occsweep::fuzz::expectRuntimeErrorOnlyAfterJson(data, size, [](const nlohmann::json& j) {
    const occsweep::ResultsFile f = occsweep::parseResults(j, "fuzz.json");
    (void)occsweep::checkAgainstGrid(f, "fuzz.json");
  });
}
