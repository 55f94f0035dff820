// Sweeps: shards merge to the whole, merge refuses bad sets, a killed sweep resumes to the same result,
// a hand-edited results file is caught.
#include <catch2/catch.hpp>

#include <csignal>
#include <fstream>
#include <thread>

#include "occsweep/sweeps/merge.hpp"
#include "occsweep/sweeps/sweep.hpp"
#include "small_scene.hpp"
#include "test_helpers.hpp"

using namespace occsweep;
using Catch::Matchers::Contains;
namespace fs = std::filesystem;

namespace {

using test::smallScene;

ResultsFile sweep(const fs::path& data, const std::string& grid, const fs::path& out, std::uint64_t shard = 0,
                  std::uint64_t shards = 1) {
  return runSweep(test::quietSweep(data, grid, out, shard, shards));
}

std::string mergeError(const std::vector<fs::path>& files) {
  try {
    (void)mergeResults(files);
  } catch (const std::exception& e) {
    return e.what();
  }
  return "merged";
}

std::size_t lines(const fs::path& file) {
  std::ifstream in(file);
  std::size_t n = 0;
  for (std::string l; std::getline(in, l);) ++n;
  return n;
}

}  // namespace

TEST_CASE("more shards than the selection has maps are refused before anything is written") {
  // Old binary: shard 20/21 of octomap-opt's 20 maps wrote a store of no map (its header's engine "mixed"), which
  // results check, merge and the next sweep refused; shard 0/181 wrote a file results check refused.
  const auto dir = test::scratch("sweep-empty-shards");
  const auto data = smallScene(dir);
  for (const std::string out : {"s.db", "s.json"}) {
    CHECK_THROWS_WITH(sweep(data, "octomap-opt", dir / out, 20, 21),
                      Contains("21 shards of grid octomap-opt, but its 20 maps") && Contains("at most 20 shards"));
    CHECK_THROWS_WITH(sweep(data, "octomap-opt", dir / out, 0, 181), Contains("but its 20 maps"));
    CHECK_FALSE(fs::exists(dir / out));
  }
  // An Eq. 16 group counts its own maps: group 19 of 20 holds the 9 ids of at most 9 maps.
  SweepConfig grouped = test::quietSweep(data, "octomap-opt", dir / "g.json", 0, 10);
  grouped.selection.group = SweepSelection::Group{19, 20, 5};
  CHECK_THROWS_WITH(runSweep(grouped), Contains("group holds"));
  CHECK_FALSE(fs::exists(dir / "g.json"));
  // As many shards as maps: each holds one, and they merge to the whole.
  std::vector<fs::path> parts;
  for (std::uint64_t i = 0; i < 20; ++i) {
    parts.push_back(dir / ("one" + std::to_string(i) + ".json"));
    CHECK(sweep(data, "octomap-opt", parts.back(), i, 20).maps.size() == 1);
  }
  CHECK(resultDifferences(sweep(data, "octomap-opt", dir / "whole.json"), mergeResults(parts)).empty());
}

TEST_CASE("shards merge to exactly the unsharded sweep, and merge refuses missing, duplicated and foreign work") {
  const auto dir = test::scratch("sweep-shards");
  const auto data = smallScene(dir);
  const ResultsFile whole = sweep(data, "octomap-opt", dir / "whole.json");
  CHECK(whole.maps.size() == 20);
  std::vector<fs::path> parts;
  for (std::uint64_t i = 0; i < 3; ++i) {
    parts.push_back(dir / ("part" + std::to_string(i) + ".json"));
    (void)sweep(data, "octomap-opt", parts.back(), i, 3);
  }
  const ResultsFile merged = mergeResults(parts);
  CHECK(resultDifferences(whole, merged).empty());
  CHECK(mergeError({parts[0], parts[2]}) != "merged");
  CHECK_THAT(mergeError({parts[0], parts[2]}), Contains("missing"));
  CHECK_THAT(mergeError({parts[0], parts[1], parts[2], parts[1]}), Contains("duplicated") && Contains("part1.json"));
  (void)sweep(data, "knn-opt", dir / "knn0.json", 0, 40);
  CHECK_THAT(mergeError({parts[0], parts[1], parts[2], dir / "knn0.json"}), Contains("knn0.json") && Contains("foreign"));
  const auto other = smallScene(dir, 4);
  (void)sweep(other, "octomap-opt", dir / "other.json", 0, 3);
  CHECK_THAT(mergeError({parts[0], parts[1], parts[2], dir / "other.json"}), Contains("another data set"));
  // The CLI says the same with a non-zero exit, and writes nothing.
  const auto r = test::runCli("merge " + parts[0].string() + " " + parts[2].string() + " --out " + (dir / "m.json").string());
  CHECK(r.exit_code != 0);
  CHECK_THAT(r.output, Contains("missing"));
  CHECK_FALSE(fs::exists(dir / "m.json"));
}

TEST_CASE("a sweep killed part-way resumes and gives the same merged result as an uninterrupted one") {
  const auto dir = test::scratch("sweep-resume");
  const auto data = smallScene(dir);
  const ResultsFile reference = sweep(data, "knn-opt", dir / "reference.json");
  const fs::path out = dir / "killed.json", partial = dir / "killed.json.partial.jsonl";
  const std::string cli = occsweep::test::builtCli();
  const pid_t child = ::fork();
  if (child == 0) {
    ::execl(cli.c_str(), cli.c_str(), "sweep", "--dataset", data.c_str(), "--grid", "knn-opt", "--out", out.c_str(),
            "--threads", "1", "--quiet", static_cast<char*>(nullptr));
    std::_Exit(127);
  }
  // Wait until some maps are done, then kill it hard.
  for (int i = 0; i < 3000 && lines(partial) < 20; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  ::kill(child, SIGKILL);
  int status = 0;
  ::waitpid(child, &status, 0);
  REQUIRE(WIFSIGNALED(status));
  CHECK_FALSE(fs::exists(out));  // no half results file
  const std::size_t finished = lines(partial) - 1;
  CHECK(finished >= 19);
  CHECK(finished < 450);
  const auto r = test::runCli("sweep --dataset " + data.string() + " --grid knn-opt --out " + out.string());
  REQUIRE(r.exit_code == 0);
  // The maps finished before the kill are taken from the partial file, not done again (a line cut by the kill is).
  const auto at = r.output.find("resuming ");
  REQUIRE(at != std::string::npos);
  const auto colon = r.output.find(": ", at);
  const std::size_t reused = std::stoul(r.output.substr(colon + 2));
  CHECK(reused + 1 >= finished);
  CHECK(reused <= finished);
  CHECK_THAT(r.output, Contains(" of 450 maps done before"));
  CHECK_FALSE(fs::exists(partial));
  const ResultsFile resumed = readResults(out);
  CHECK(resumed.complete);
  CHECK(resultDifferences(reference, mergeResults({out})).empty());
  // Re-running with a complete output leaves it as it is.
  const auto before = fs::last_write_time(out);
  CHECK(test::runCli("sweep --dataset " + data.string() + " --grid knn-opt --out " + out.string() + " --quiet").exit_code == 0);
  CHECK(fs::last_write_time(out) == before);
}

TEST_CASE("an Eq. 16 group sweeps only its ids, and merges on its own") {
  const auto dir = test::scratch("sweep-group");
  const auto data = smallScene(dir);
  SweepConfig c;
  c.dataset = data;
  c.grid = "knn-opt";
  c.out = dir / "g.json";
  c.selection.group = SweepSelection::Group{3, 20, 5};
  c.quiet = true;
  const ResultsFile g = runSweep(c);
  CHECK(coveredIds(g).size() == 203);  // 4050 = 20 * 202 + 10: group 3 is one of the longer ones
  CHECK(mergeResults({c.out}).maps.size() == g.maps.size());
}

TEST_CASE("a results file edited by hand is refused with the field named") {
  const auto dir = test::scratch("sweep-edited");
  const auto data = smallScene(dir);
  (void)sweep(data, "octomap-opt", dir / "r.json");
  std::ifstream in(dir / "r.json");
  auto j = nlohmann::json::parse(in);
  auto write = [&](const nlohmann::json& edited) { std::ofstream(dir / "e.json") << edited.dump(); };
  auto error = [&] {
    try {
      (void)readResults(dir / "e.json");
    } catch (const std::exception& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  write(j);
  CHECK(error() == "accepted");
  auto e = j;
  e["maps"][2]["thresholds"][1]["tp"] = e["maps"][2]["thresholds"][1]["tp"].get<int>() + 1;
  write(e);
  CHECK_THAT(error(), Contains("e.json") && Contains("maps[2].thresholds[1]"));
  e = j;
  e["maps"][0]["auc"]["anchored"] = 0.99;
  write(e);
  CHECK_THAT(error(), Contains("maps[0].auc.anchored"));
  e = j;
  e["maps"][0]["params"]["p_h"] = 0.74;
  e["maps"][0]["params"]["p_m"] = 0.38;
  write(e);
  CHECK_THAT(test::runCli("results check " + (dir / "e.json").string()).output, Contains("parameters differ"));
  std::ofstream(dir / "e.json") << j.dump().substr(0, 500);
  CHECK_THAT(error(), Contains("not valid JSON"));
  CHECK(test::runCli("results check " + (dir / "e.json").string()).exit_code != 0);
}

TEST_CASE("several grids swept in one process give each grid's results as its own sweep does") {
  const auto dir = test::scratch("sweep-grids");
  const auto data = smallScene(dir);
  const std::vector<std::string> grids = {"knn-opt", "octomap-opt", "sor-octomap-opt", "range-octomap-opt"};
  std::vector<SweepConfig> together;
  for (std::size_t i = 0; i < grids.size(); ++i) {
    SweepConfig c;
    c.dataset = data;
    c.grid = grids[i];
    c.out = dir / (grids[i] + (i % 2 ? ".db" : ".json"));  // each grid's output in its own format
    c.quiet = true;
    together.push_back(c);
  }
  const std::vector<SweepSummary> written = sweepGrids(together);
  REQUIRE(written.size() == grids.size());
  for (std::size_t i = 0; i < grids.size(); ++i) {
    const ResultsFile alone = sweep(data, grids[i], dir / (grids[i] + ".alone.json"));
    CHECK(written[i].header.grid_name == grids[i]);
    CHECK(written[i].maps == alone.maps.size());
    CHECK(resultDifferences(alone, readResults(together[i].out)).empty());
  }
  // Grids swept together share the data set and its settings, and each writes its own file.
  std::vector<SweepConfig> other_resolution = together;
  other_resolution[1].map.resolution = 0.2;
  CHECK_THROWS_WITH(sweepGrids(other_resolution), Contains("share the data set and every map setting"));
  // Two spellings of one file, or one through a folder's symbolic link, are one output (old library: compared as
  // spelt, so `./x` and `x` swept both grids into one file and the first grid's results were lost).
  fs::create_directory_symlink(".", dir / "here");
  for (const fs::path& other : {dir / "same.json", dir / "." / "same.json", dir / "here" / "same.json",
                                dir / "same.json.partial.jsonl"}) {
    std::vector<SweepConfig> one_out = together;
    one_out[0].out = dir / "same.json";
    one_out[1].out = other;
    INFO(other);
    CHECK_THROWS_WITH(sweepGrids(one_out), Contains("name one file"));
    CHECK_FALSE(fs::exists(dir / "same.json"));
  }
  // A user's file at an output is refused before the data set is read: the refusal costs no read and no recording.
  std::ofstream(dir / "users.json") << "the user's file\n";
  std::vector<SweepConfig> users = together;
  users[1].out = dir / "users.json";
  for (SweepConfig& c : users) c.dataset = dir / "no-such-data-set";
  CHECK_THROWS_WITH(sweepGrids(users), Contains("users.json: exists and is not occsweep's results file"));
  CHECK(test::bytesOf(dir / "users.json") == "the user's file\n");
}
