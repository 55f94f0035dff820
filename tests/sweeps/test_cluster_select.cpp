// `occsweep cluster select`: the sets of several generation blocks ranked as one generation would rank them.
#include <catch2/catch.hpp>

#include <fstream>

#include <nlohmann/json.hpp>

#include "test_helpers.hpp"

using namespace occsweep;
namespace fs = std::filesystem;
using Catch::Matchers::Contains;

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
