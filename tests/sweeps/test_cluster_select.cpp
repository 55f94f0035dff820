// `occsweep cluster select`: the sets of several generation blocks ranked as one generation would rank them.
#include <catch2/catch.hpp>

#include <fstream>

#include <nlohmann/json.hpp>

#include "test_helpers.hpp"

using namespace occsweep;
namespace fs = std::filesystem;
using Catch::Matchers::Contains;

namespace {

/// DIR/ranking.json of one set, pcs-ID (its folder made beside it), from the generation `generation` names.
void writeRanking(const fs::path& dir, int id, const nlohmann::json& generation) {
  const std::string folder = "pcs-000" + std::to_string(id);
  fs::create_directories(dir / folder);
  nlohmann::json ranking = generation;
  ranking["format"] = "occsweep-pointcloud-ranking";
  ranking["sets"] = {{{"folder", folder}, {"id", id}, {"naive", {{"fdr", 0.1 * id}, {"tpr", 0.5}}}}};
  std::ofstream(dir / "ranking.json") << ranking.dump();
}

}  // namespace

TEST_CASE("select ranks the sets of several generation blocks as one generation of all of them would") {
  const auto dir = test::scratch("cluster-select");
  // Oracle: the generator's own ranking of ids 0-5 in one run; then the same ids in blocks {0,3,5} and {1,2,4}.
  auto gen = [&](const std::string& out, const std::string& ids) {
    return test::runCli("dataset generate --name parking-voronoi-T --scale ci --no-preview --threads 2 --out " +
                        (dir / out).string() + " --pcs " + ids);
  };
  if (test::runCli("dataset generate --help").exit_code != 0) {
    WARN("occsweep built without stereo data sets (OCCSWEEP_STEREO=OFF): select checked on hand-written rankings only");
  } else {
    REQUIRE(gen("all", "0,1,2,3,4,5").exit_code == 0);
    REQUIRE(gen("a", "0,3,5").exit_code == 0);
    REQUIRE(gen("b", "1,2,4").exit_code == 0);
    const fs::path sets = dir / "sets";
    const auto r = test::runCli("cluster select --out " + sets.string() + " " +
                                (dir / "b/parking-voronoi-T/ranking.json").string() + " " +
                                (dir / "a/parking-voronoi-T/ranking.json").string());
    REQUIRE(r.exit_code == 0);
    std::ifstream in(dir / "all/parking-voronoi-T/ranking.json");
    const auto ranking = nlohmann::json::parse(in);
    REQUIRE(ranking.at("sets").size() == 6);
    const auto selected = nlohmann::json::parse(test::bytesOf(sets / "sets.json"));  // which data set's sets
    for (const char* field : {"dataset", "scale", "seed", "pointcloud_grid"})
      CHECK(selected.at(field) == ranking.at(field));
    CHECK(selected["dataset"] == "parking-voronoi-T");
    for (const auto& s : ranking["sets"]) {
      const auto rank = "rank-" + std::to_string(s.at("rank").get<int>());
      INFO(rank);
      CHECK(fs::read_symlink(sets / rank).filename() == s.at("folder").get<std::string>());
      CHECK(fs::exists(sets / rank / "manifest.json"));
    }
  }
  // Refusals name the file: an id in two rankings, a folder that is not there.
  const fs::path bad = dir / "bad";
  fs::create_directories(bad / "pcs-0001");
  std::ofstream(bad / "ranking.json") << R"({"format": "occsweep-pointcloud-ranking", "sets": [
    {"folder": "pcs-0001", "id": 1, "naive": {"fdr": 0.5, "tpr": 0.5}},
    {"folder": "pcs-0002", "id": 2, "naive": {"fdr": 0.4, "tpr": 0.5}}]})";
  auto r = test::runCli("cluster select --out " + (dir / "s2").string() + " " + (bad / "ranking.json").string());
  CHECK(r.exit_code != 0);
  CHECK_THAT(r.output, Contains("ranking.json") && Contains("pcs-0002"));
  CHECK_FALSE(fs::exists(dir / "s2"));
  fs::create_directories(bad / "pcs-0002");
  r = test::runCli("cluster select --out " + (dir / "s2").string() + " " + (bad / "ranking.json").string() + " " +
                   (bad / "ranking.json").string());
  CHECK_THAT(r.output, Contains("two rankings"));
  r = test::runCli("cluster select --out " + (dir / "s2").string() + " " + (bad / "ranking.json").string());
  REQUIRE(r.exit_code == 0);
  CHECK(fs::read_symlink(dir / "s2" / "rank-1").filename() == "pcs-0002");  // lower FDR first
}

// Old binary: the blocks of two data sets (or scales, seeds, point cloud grids) were ranked as one, exit 0, and
// sets.json named no data set.
TEST_CASE("select refuses the rankings of two generations, naming both files and the field, and records its data set") {
  const auto dir = test::scratch("cluster-select-generations");
  const nlohmann::json generation = {{"dataset", "parking-voronoi-T"}, {"scale", "ci"}, {"seed", 3},
                                     {"pointcloud_grid", {{"name", "pointcloud-sgbm"}, {"file_hash", "0a1b"}}}};
  writeRanking(dir / "a", 1, generation);
  const std::vector<std::pair<std::string, nlohmann::json>> others = {
      {"dataset", "building-plain-I"}, {"scale", "small"}, {"seed", 4},
      {"pointcloud_grid", {{"name", "pointcloud-sgbm"}, {"file_hash", "ffff"}}}};
  for (const auto& [field, value] : others) {
    nlohmann::json other = generation;
    other[field] = value;
    writeRanking(dir / "b", 2, other);
    const auto r = test::runCli("cluster select --out " + (dir / "sets").string() + " " +
                                (dir / "a" / "ranking.json").string() + " " + (dir / "b" / "ranking.json").string());
    INFO(r.output);
    CHECK(r.exit_code == 2);
    CHECK_THAT(r.output, Contains((dir / "b" / "ranking.json").string() + ": " + field + " " + value.dump() + ", but " +
                                  (dir / "a" / "ranking.json").string() + " has " + generation[field].dump()));
    CHECK_FALSE(fs::exists(dir / "sets"));
  }
  writeRanking(dir / "b", 2, generation);
  const auto r = test::runCli("cluster select --out " + (dir / "sets").string() + " " +
                              (dir / "a" / "ranking.json").string() + " " + (dir / "b" / "ranking.json").string());
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  const auto selected = nlohmann::json::parse(test::bytesOf(dir / "sets" / "sets.json"));
  for (const auto& [field, value] : generation.items()) CHECK(selected.at(field) == value);
  CHECK(selected.at("sets").size() == 2);
}

// Old binary: "refused even with --force", of a command that has no --force.
TEST_CASE("select refuses a folder at --out it did not write, saying what to do, and leaves it as it was") {
  const auto dir = test::scratch("cluster-select-foreign-out");
  writeRanking(dir / "a", 1, {{"dataset", "parking-voronoi-T"}});
  fs::create_directories(dir / "sets");
  std::ofstream(dir / "sets" / "notes.txt") << "mine\n";
  const std::string ranking = (dir / "a" / "ranking.json").string();
  const auto r = test::runCli("cluster select --out " + (dir / "sets").string() + " " + ranking);
  INFO(r.output);
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.output, Contains((dir / "sets").string() + ": exists and is not occsweep's folder of selected point "
                                "cloud sets") && Contains("move it away, or give another --out"));
  CHECK_THAT(r.output, !Contains("--force"));
  CHECK(test::bytesOf(dir / "sets" / "notes.txt") == "mine\n");
  CHECK(std::distance(fs::directory_iterator(dir / "sets"), fs::directory_iterator()) == 1);  // no link added
  // Its own folder is replaced: a second run over the first one's output.
  for (int run = 0; run < 2; ++run)
    CHECK(test::runCli("cluster select --out " + (dir / "own").string() + " " + ranking).exit_code == 0);
}
