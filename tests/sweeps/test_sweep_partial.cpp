// A sweep's partial output against a user who moves it away while the sweep runs: what the sweep writes goes into
// the file it locked, never into a file put at its name (docs/robustness.md, "Ownership"). These test the engine's
// internal PartialLock and PartialLog directly: through the command the moment between locking and writing cannot
// be hit on purpose.
#include <catch2/catch.hpp>

#include <fstream>

#include "../sweeps/engine/src/sweep_internal.hpp"
#include "test_helpers.hpp"

namespace fs = std::filesystem;
using occsweep::ResultsHeader;
using occsweep::sweep_detail::PartialLock;
using occsweep::sweep_detail::PartialLog;
using occsweep::test::bytesOf;
using occsweep::test::scratch;

namespace {

void writeText(const fs::path& file, const std::string& text) {
  std::ofstream(file, std::ios::binary) << text;
}

}  // namespace

TEST_CASE("a resumed partial log appends to the file it locked, not to a user's file put at its name meanwhile",
          "[sweep][ownership]") {
  const fs::path dir = scratch("sweep_partial/resumed");
  const fs::path log_file = dir / "r.json.partial.jsonl";
  const std::string header = "{\"a sweep's header\":1}\n";
  writeText(log_file, header);
  PartialLock lock = PartialLock::existing(log_file);
  fs::rename(log_file, dir / "moved");
  writeText(log_file, "the user's notes\n");
  CHECK_FALSE(lock.holdsFile(log_file));
  CHECK(lock.holdsFile(dir / "moved"));
  {
    PartialLog log(log_file, ResultsHeader{}, 1, std::move(lock));
    log.append({{"map_index", 7}});
    log.remove();  // the sweep's end: removes its own log only, wherever its name now points
  }
  CHECK(bytesOf(log_file) == "the user's notes\n");
  CHECK(bytesOf(dir / "moved") == header + "{\"map_index\":7}\n");
}

TEST_CASE("a new partial log is written into the file it published, whatever is put at its name afterwards",
          "[sweep][ownership]") {
  const fs::path dir = scratch("sweep_partial/new");
  const fs::path log_file = dir / "r.json.partial.jsonl";
  {
    PartialLog log(log_file, ResultsHeader{}, 0, PartialLock{});
    const std::string published = bytesOf(log_file);
    CHECK(published.find("\"grid\"") != std::string::npos);  // its header line, written before it appeared
    fs::rename(log_file, dir / "moved");
    writeText(log_file, "the user's notes\n");
    log.append({{"map_index", 3}});
    log.remove();
    CHECK(bytesOf(dir / "moved") == published + "{\"map_index\":3}\n");
  }
  CHECK(bytesOf(log_file) == "the user's notes\n");
  CHECK(fs::exists(dir / "moved"));
}
