// A sweep's partial output against a user who moves it away while the sweep runs: what the sweep writes goes into
// the file it locked, never into a file put at its name (docs/io.md, "Ownership"). These test the engine's
// LockedFile (io) and PartialLog directly: through the command the moment between locking and writing cannot
// be hit on purpose.
#include <catch2/catch.hpp>

#include <fstream>

#include "../sweeps/engine/src/sweep_internal.hpp"
#include "exchange_fault.hpp"
#include "test_helpers.hpp"

namespace fs = std::filesystem;
using occsweep::ResultsHeader;
using occsweep::LockedFile;
using occsweep::sweep_detail::lockPartial;
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
  LockedFile lock = lockPartial(log_file);
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

TEST_CASE("a --force sweep's new partial output takes the old one's place, never a user's file put there meanwhile",
          "[sweep][ownership]") {
  // Previous code: the new partial output was renamed over whatever stood at the name by then (the sweep locks the
  // old one at its start, then prepares its data for minutes before it publishes the new one).
  const fs::path dir = scratch("sweep_partial/force");
  const fs::path partial = dir / "r.json.partial.jsonl";
  auto header = [](const fs::path& temporary) { writeText(temporary, "{\"new header\":1}\n"); };
  SECTION("the old partial output still there: replaced") {
    writeText(partial, "{\"old header\":1}\n");
    const LockedFile old = lockPartial(partial);
    const LockedFile now = LockedFile::publish(partial, &old, header);
    CHECK(bytesOf(partial) == "{\"new header\":1}\n");
    CHECK(now.holdsFile(partial));
    CHECK(std::distance(fs::directory_iterator(dir), fs::directory_iterator()) == 1);
  }
  SECTION("a user's file at its name by then: kept, and the sweep stops naming it") {
    writeText(partial, "{\"old header\":1}\n");
    const LockedFile old = lockPartial(partial);
    fs::rename(partial, dir / "moved");
    writeText(partial, "the user's notes\n");
    CHECK_THROWS_WITH(LockedFile::publish(partial, &old, header),
                      Catch::Contains("r.json.partial.jsonl: was replaced while occsweep was preparing it"));
    CHECK(bytesOf(partial) == "the user's notes\n");
    CHECK(bytesOf(dir / "moved") == "{\"old header\":1}\n");
    CHECK(std::distance(fs::directory_iterator(dir), fs::directory_iterator()) == 2);
  }
  SECTION("a user's file at its name by then, and the exchange back refused: put back by a rename, else kept") {
    // Old code: the exchange back's failure was ignored, and the user's file, left at the temporary's name, was
    // removed with it.
    if (!occsweep::test::exchangeSupported(dir)) {
      WARN("no RENAME_EXCHANGE on this file system: the partial output is renamed, never exchanged");
      return;
    }
    writeText(partial, "{\"old header\":1}\n");
    const LockedFile old = lockPartial(partial);
    fs::rename(partial, dir / "moved");
    writeText(partial, "the user's notes\n");
    auto temporaries = [&] {
      std::vector<fs::path> found;
      for (const auto& e : fs::directory_iterator(dir))
        if (e.path().filename().string().starts_with(".r.json.partial.jsonl.tmp-")) found.push_back(e.path());
      return found;
    };
    {
      const occsweep::test::ExchangeFault fault(1, false);
      CHECK_THROWS_WITH(LockedFile::publish(partial, &old, header),
                        Catch::Contains("r.json.partial.jsonl: was replaced while occsweep was preparing it"));
    }
    CHECK(bytesOf(partial) == "the user's notes\n");
    CHECK(temporaries().empty());
    {
      const occsweep::test::ExchangeFault fault(1, true);
      CHECK_THROWS_WITH(LockedFile::publish(partial, &old, header),
                        Catch::Contains("r.json.partial.jsonl: was replaced while occsweep was preparing it, "
                                        "and could not be put back (exchange: Input/output error; rename: "
                                        "Input/output error): the file that stood there is now at " +
                                        (dir / ".r.json.partial.jsonl.tmp-").string()));
    }
    const std::vector<fs::path> kept = temporaries();
    REQUIRE(kept.size() == 1);
    CHECK(bytesOf(kept[0]) == "the user's notes\n");
    CHECK(bytesOf(partial) == "{\"new header\":1}\n");  // the sweep's, at the name: named in the message
  }
}
