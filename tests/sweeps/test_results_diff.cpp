// `occsweep results diff GOLDEN NEW` and diffResults (docs/results-format.md, "Regression checks against a golden
// file"): a fresh sweep of the built-in scene matches its golden file; a voxel that changes class, an AUC that moves
// beyond the tolerance, a missing combination or an incomparable header each fail, naming what changed.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include <catch2/catch.hpp>

#include "occsweep/eval/builtin_scene.hpp"
#include "occsweep/sweeps/results_diff.hpp"
#include "occsweep/sweeps/sweep.hpp"
#include "test_helpers.hpp"

using namespace occsweep;
using Catch::Matchers::Contains;
namespace fs = std::filesystem;

namespace {

const fs::path kGolden = occsweep::test::sourceTree() / "results" / "builtin" / "octomap-opt.json";

// The combination every case below changes: map 7 of octomap-opt (p_h 0.62, p_m 0.38), its threshold p_t = 0.38.
constexpr std::size_t kMap = 7, kThreshold = 3;

std::string diffCommand(const fs::path& golden, const fs::path& candidate, const std::string& options = "") {
  return "results diff " + test::shellQuoted(golden) + " " + test::shellQuoted(candidate) + " " + options;
}

std::string number(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

/// The golden file with one voxel of one combination moved from TP to FN (the map's AUCs follow from its counts).
ResultsFile oneVoxelChanged(const ResultsFile& golden) {
  ResultsFile f = golden;
  MapResult& m = f.maps.at(kMap);
  ConfusionCounts& c = m.thresholds.at(kThreshold).counts;
  REQUIRE(c.tp > 0);
  --c.tp, ++c.fn;
  m.area = mapArea(m.thresholds);
  return f;
}

/// A combination id as a cell of the table: between blanks, so that id 6 does not match 66.
std::string idCell(std::uint64_t id) {
  std::string cell = " ";
  cell += std::to_string(id);
  cell += ' ';
  return cell;
}

/// Every output line that holds all of `words`.
std::size_t linesWith(const std::string& output, const std::vector<std::string>& words) {
  std::size_t n = 0, start = 0;
  while (start < output.size()) {
    const std::size_t end = std::min(output.find('\n', start), output.size());
    const std::string line = output.substr(start, end - start);
    n += std::all_of(words.begin(), words.end(), [&](const auto& w) { return line.find(w) != std::string::npos; });
    start = end + 1;
  }
  return n;
}

}  // namespace

TEST_CASE("a fresh sweep of the built-in scene has the golden file's numbers: results diff exits 0") {
  const fs::path dir = test::scratch("results-diff-fresh");
  SweepConfig c;
  c.dataset = dir / "scene";
  writeDataset(makeBuiltinScene(), c.dataset);  // the default settings, as tools/regenerate_golden.sh
  c.grid = "octomap-opt";
  c.out = dir / "fresh.json";
  c.quiet = true;
  const ResultsFile fresh = runSweep(c);
  CHECK(diffResults(readResults(kGolden), fresh, 0.0).empty());
  const auto r = test::runCli(diffCommand(kGolden, c.out));
  INFO(r.output);
  CHECK(r.exit_code == 0);
  CHECK(r.output.find("same numbers as") != std::string::npos);
  CHECK(r.output.find("20 maps, 180 combinations, confusion counts exact, AUC within 0") != std::string::npos);
}

TEST_CASE("one voxel moved from TP to FN in one combination fails, naming that combination") {
  const fs::path dir = test::scratch("results-diff-voxel");
  const ResultsFile golden = readResults(kGolden);
  const ResultsFile changed = oneVoxelChanged(golden);
  writeResults(changed, dir / "changed.json");
  const ThresholdResult& t = golden.maps[kMap].thresholds[kThreshold];

  const ResultsDiff diff = diffResults(golden, readResults(dir / "changed.json"), 0.0);
  CHECK(diff.header.empty());
  std::vector<std::string> count_fields;
  for (const auto& d : diff.combinations) {
    CHECK(d.map_index == kMap);  // nothing else moved
    if (!d.id) continue;  // the map's AUC, moved with the counts
    count_fields.push_back(d.field);
    CHECK(*d.id == t.id);
  }
  CHECK(count_fields == std::vector<std::string>{"tp", "fn"});

  const auto r = test::runCli(diffCommand(kGolden, dir / "changed.json"));
  INFO(r.output);
  CHECK(r.exit_code == 1);
  const std::string params = "p_max=0.98 p_min=0.02 p_h=0.62 p_m=0.38 p_t=0.38";
  const std::string id = idCell(t.id);
  CHECK(linesWith(r.output, {id, "tp", std::to_string(t.counts.tp), std::to_string(t.counts.tp - 1), params}) == 1);
  CHECK(linesWith(r.output, {id, "fn", std::to_string(t.counts.fn), std::to_string(t.counts.fn + 1), params}) == 1);
}

TEST_CASE("an AUC that moves by more than the tolerance fails, by less passes") {
  const ResultsFile golden = readResults(kGolden);
  SECTION("in memory, counts exact") {
    ResultsFile moved = golden;
    moved.maps.at(3).area.anchored += 0.01;
    CHECK(diffResults(golden, moved, 0.02).empty());
    const ResultsDiff diff = diffResults(golden, moved, 0.005);
    REQUIRE(diff.combinations.size() == 1);
    CHECK(diff.combinations[0].map_index == 3);
    CHECK(diff.combinations[0].field == "auc.anchored");
    // The values are printed so that they read back exactly: a difference in the last digit stays visible.
    CHECK(std::stod(diff.combinations[0].golden) == golden.maps[3].area.anchored);
    CHECK(std::stod(diff.combinations[0].candidate) == moved.maps[3].area.anchored);
  }
  SECTION("through the command, AUCs alone (--auc-only), on a file whose one voxel changed") {
    const fs::path dir = test::scratch("results-diff-auc");
    const ResultsFile changed = oneVoxelChanged(golden);
    writeResults(changed, dir / "changed.json");
    const double anchored = std::abs(changed.maps[kMap].area.anchored - golden.maps[kMap].area.anchored);
    const double observed = std::abs(changed.maps[kMap].area.observed - golden.maps[kMap].area.observed);
    REQUIRE(anchored > 0);
    const auto within = test::runCli(diffCommand(kGolden, dir / "changed.json",
                                                 "--auc-only --auc-tolerance " + number(2 * std::max(anchored, observed))));
    INFO(within.output);
    CHECK(within.exit_code == 0);
    CHECK(within.output.find("confusion counts exact") == std::string::npos);
    const auto beyond =
        test::runCli(diffCommand(kGolden, dir / "changed.json", "--auc-only --auc-tolerance " + number(anchored / 2)));
    INFO(beyond.output);
    CHECK(beyond.exit_code == 1);
    CHECK(linesWith(beyond.output, {"auc.anchored", "p_max=0.98 p_min=0.02 p_h=0.62 p_m=0.38"}) == 1);
    CHECK(linesWith(beyond.output, {"tp"}) == 0);  // --auc-only: counts not compared
    // Without --auc-only the moved voxel itself fails, whatever the tolerance.
    CHECK(test::runCli(diffCommand(kGolden, dir / "changed.json", "--auc-tolerance 1")).exit_code == 1);
  }
}

TEST_CASE("a combination missing from the new file fails, each of its ids named") {
  const fs::path dir = test::scratch("results-diff-missing");
  const ResultsFile golden = readResults(kGolden);
  ResultsFile cut = golden;
  cut.maps.erase(cut.maps.begin() + 12);
  cut.complete = false;  // a complete file must hold every map: readResults refuses it otherwise
  writeResults(cut, dir / "cut.json");

  const ResultsDiff diff = diffResults(golden, cut, 0.0);
  REQUIRE(diff.combinations.size() == golden.maps[12].thresholds.size());
  for (std::size_t i = 0; i < diff.combinations.size(); ++i) {
    CHECK(diff.combinations[i].id == golden.maps[12].thresholds[i].id);
    CHECK(diff.combinations[i].field == "combination");
    CHECK(diff.combinations[i].candidate == "missing");
  }
  // The other way round the extra combinations differ as well.
  CHECK(diffResults(cut, golden, 0.0).combinations.size() == golden.maps[12].thresholds.size());

  // The command reads nothing `results check` refuses (docs/results-format.md): an incomplete NEW is exit 2, named.
  const auto r = test::runCli(diffCommand(kGolden, dir / "cut.json"));
  INFO(r.output);
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.output, Contains("cut.json") && Contains("incomplete results"));
}

TEST_CASE("files of another data set or grid are not comparable: the header fields are named") {
  const fs::path dir = test::scratch("results-diff-header");
  const ResultsFile golden = readResults(kGolden);
  ResultsFile other = golden;
  other.header.dataset_name = "other-scene";
  other.header.grid_hash = "0123456789abcdef";
  writeResults(other, dir / "other.json");

  const ResultsDiff diff = diffResults(golden, other, 0.0);
  CHECK(diff.combinations.empty());
  REQUIRE(diff.header.size() == 2);
  CHECK(diff.header[0].field == "grid.file_hash");
  CHECK(diff.header[1].field == "dataset.name");
  CHECK(diff.header[1].candidate == "other-scene");

  const auto r = test::runCli(diffCommand(kGolden, dir / "other.json"));
  INFO(r.output);
  CHECK(r.exit_code == 1);
  CHECK(linesWith(r.output, {"dataset.name", golden.header.dataset_name, "other-scene"}) == 1);
  CHECK(r.output.find("not comparable") != std::string::npos);
}

TEST_CASE("results diff: bad input exits 2 with a message naming the file") {
  const fs::path dir = test::scratch("results-diff-bad");
  {
    std::ofstream(dir / "not-results.json") << R"({"format": "occsweep-comparison"})";
  }
  const auto missing = test::runCli(diffCommand(kGolden, dir / "absent.json"));
  CHECK(missing.exit_code == 2);
  CHECK(missing.output.find("occsweep results: error: " + (dir / "absent.json").string()) != std::string::npos);
  const auto wrong = test::runCli(diffCommand(dir / "not-results.json", kGolden));
  CHECK(wrong.exit_code == 2);
  CHECK(linesWith(wrong.output, {(dir / "not-results.json").string(), "format"}) == 1);
  const auto negative = test::runCli(diffCommand(kGolden, kGolden, "--auc-tolerance -1"));
  CHECK(negative.exit_code == 2);
  CHECK(negative.output.find("--auc-tolerance must be a number >= 0, got -1") != std::string::npos);
  CHECK(test::runCli(diffCommand(kGolden, kGolden)).exit_code == 0);
}
