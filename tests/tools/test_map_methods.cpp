// `occsweep map` builds every registered method, including one a program registers from outside the library
// (occsweep_with_example_method: examples/occupancy_method's density-octomap and the whole command line), and its
// maps count what the replay engine counted: by flags at each stored p_t, and by --from RESULTS at all of them.
#include <catch2/catch.hpp>

#include <algorithm>
#include <sstream>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <regex>

#include <sys/stat.h>

#include "occsweep/sweeps/results.hpp"
#include "test_helpers.hpp"

namespace fs = std::filesystem;
using occsweep::test::CommandResult;

namespace {

// One program under test: occsweep, or occsweep with the example method registered.
struct Program {
  std::string path;
  CommandResult run(const fs::path& dir, const std::string& args) const {
    return occsweep::test::runShell("cd " + occsweep::test::shellQuoted(dir) + " && " +
                                    occsweep::test::shellQuoted(path) + " " + args + " 2>&1");
  }
};

// "--p-h 0.62 --k 3 ..." for every parameter of the map as the results file holds it.
std::string parameterFlags(const occsweep::ResultsFile& f, const occsweep::MapResult& m) {
  std::string flags;
  for (std::size_t i = 0; i < f.header.parameters.names.size(); ++i) {
    std::string flag = "--" + f.header.parameters.names[i];
    std::replace(flag.begin(), flag.end(), '_', '-');
    char value[64];
    std::snprintf(value, sizeof value, "%.17g", occsweep::toDouble(m.params.values[i]));
    flags += " " + flag + " " + value;
  }
  return flags;
}

// The best map of a results file by compare's rule (the highest AUC, NaN never, ties to the lowest map index).
const occsweep::MapResult& bestOf(const occsweep::ResultsFile& f) {
  const occsweep::MapResult* best = nullptr;
  for (const auto& m : f.maps)
    if (!std::isnan(m.area.anchored) && (!best || m.area.anchored > best->area.anchored)) best = &m;
  REQUIRE(best);
  return *best;
}

// Sweeps `grid` with the replay engine, then checks `map` against what it stored: the best map rebuilt by flags at
// every stored p_t (the counts printed equal the stored ones), and by --from --best (the command's own check).
void checkMapAgainstReplay(const Program& program, const fs::path& dir, const std::string& grid) {
  INFO(grid);
  const std::string out = grid + ".json";
  const CommandResult sweep =
      program.run(dir, "sweep --dataset ds --engine replay --quiet --grid " + grid + " --out " + out);
  INFO(sweep.output);
  REQUIRE(sweep.exit_code == 0);
  const occsweep::ResultsFile f = occsweep::readResults(dir / out);
  const occsweep::MapResult& best = bestOf(f);
  REQUIRE(best.thresholds.size() >= 3);
  for (const auto& t : best.thresholds) {
    char p_t[32];
    std::snprintf(p_t, sizeof p_t, "%.17g", occsweep::toDouble(t.p_t));
    const CommandResult map = program.run(dir, "map --dataset ds --method " + f.header.method + parameterFlags(f, best) +
                                                   " --p-t " + p_t + " --out flags.ot --force");
    INFO(map.output);
    REQUIRE(map.exit_code == 0);
    const std::string expected = "TP " + std::to_string(t.counts.tp) + " FP " + std::to_string(t.counts.fp) + " FN " +
                                 std::to_string(t.counts.fn) + " TN " + std::to_string(t.counts.tn) + " ";
    CHECK(map.output.find(expected) != std::string::npos);
  }
  const CommandResult from = program.run(dir, "map --dataset ds --from " + out + " --best --out best-" + grid + ".ot");
  INFO(from.output);
  CHECK(from.exit_code == 0);
  CHECK(from.output.find("map " + std::to_string(best.map_index) + " of " + out) != std::string::npos);
  const std::string n = std::to_string(best.thresholds.size());
  CHECK(from.output.find("counts equal the stored ones at all " + n + " of " + n + " thresholds") != std::string::npos);
}

fs::path sceneIn(const std::string& name) {
  const fs::path dir = occsweep::test::scratch(name);
  const CommandResult scene = occsweep::test::runIn(dir, "scene --out ds --scans 6 --width 32 --height 24");
  REQUIRE(scene.exit_code == 0);
  return dir;
}

}  // namespace

TEST_CASE("map builds every shipped method with the counts its replayed sweep stored, by flags and by --from") {
  const fs::path dir = sceneIn("map-methods");
  const Program occsweep{occsweep::test::cliUnderTest()};
  for (const std::string grid : {"octomap-opt", "knn-opt", "sor-octomap-opt", "ror-octomap-opt", "range-octomap-opt"})
    checkMapAgainstReplay(occsweep, dir, grid);
}

TEST_CASE("map builds a method a program registers from outside the library, as its replayed sweep counted") {
  const fs::path dir = sceneIn("map-outside-method");
  fs::copy_file(occsweep::test::sourceTree() / "examples/occupancy_method/density-octomap-opt.json",
                dir / "density-octomap-opt.json");
  const Program with_method{(occsweep::test::buildTree() / "tests/tools/occsweep_with_example_method").string()};
  checkMapAgainstReplay(with_method, dir, "density-octomap-opt.json");
  // The program without the method does not know it.
  const CommandResult plain = occsweep::test::runIn(dir, "map --dataset ds --method density-octomap --out d.ot");
  CHECK(plain.exit_code == 2);
  CHECK(plain.output.find("density-octomap") != std::string::npos);
}

TEST_CASE("a method whose parameter is named like one of map's flags is refused by the command, naming both") {
  // The registry knows no flag (core knows no command): the command checks every registered method as it starts.
  const fs::path dir = occsweep::test::processScratch("map-flag-clash");
  const std::string program = (occsweep::test::buildTree() / "tests/tools/occsweep_with_example_method").string();
  const auto methodsWithParameter = [&](const std::string& name) {
    return occsweep::test::runShell("cd " + occsweep::test::shellQuoted(dir) + " && OCCSWEEP_EXAMPLE_PARAMETER=" +
                                    name + " " + occsweep::test::shellQuoted(program) + " methods 2>&1");
  };
  for (const std::string name : {"threads", "max_points", "from", "truth", "map_index"}) {
    INFO(name);
    const CommandResult clash = methodsWithParameter(name);
    CHECK(clash.exit_code == 2);
    std::string flag = "--" + name;
    std::replace(flag.begin(), flag.end(), '_', '-');
    CHECK(clash.output.find("method density-octomap-extra: parameter '" + name + "' would be `occsweep map " + flag +
                            "`, one of map's own flags") != std::string::npos);
  }
  const CommandResult fine = methodsWithParameter("spread");  // a name no flag has is taken
  CHECK(fine.exit_code == 0);
  CHECK(fine.output.find("density-octomap-extra") != std::string::npos);
}

TEST_CASE("map refuses a parameter its method lacks, settings beside --from, and another data set") {
  const fs::path dir = sceneIn("map-refusals");
  REQUIRE(occsweep::test::runIn(dir, "scene --out other --scans 5 --width 32 --height 24").exit_code == 0);
  REQUIRE(occsweep::test::runIn(dir, "sweep --dataset ds --quiet --grid octomap-opt --out oct.json").exit_code == 0);
  const auto refused = [&](const std::string& args, const std::string& says) {
    const CommandResult r = occsweep::test::runIn(dir, args);
    INFO(args << "\n" << r.output);
    CHECK(r.exit_code == 2);
    CHECK(r.output.find(says) != std::string::npos);
    CHECK_FALSE(fs::exists(dir / "m.ot"));
  };
  refused("map --dataset ds --method knn --std-mul 1 --out m.ot", "method knn has no parameter std_mul");
  refused("map --dataset ds --method octomap --p-h 0.9 --p-max 0.8 --out m.ot", "p_max >= p_h does not hold");
  refused("map --dataset ds --method octomap --p-t 0.99 --out m.ot", "--p-t 0.99 (to 1e-6) must lie in [p_min, p_max]");
  refused("map --dataset ds --from oct.json --best --p-h 0.7 --out m.ot", "--p-h: --from takes every parameter");
  refused("map --dataset ds --from oct.json --best --resolution 0.2 --out m.ot", "drop --resolution");
  refused("map --dataset ds --from oct.json --out m.ot", "--from needs exactly one of --best and --map-index");
  refused("map --dataset ds --best --out m.ot", "--best and --map-index choose a map of --from RESULTS");
  refused("map --dataset ds --from oct.json --best --map-index 0 --out m.ot", "exactly one of --best and --map-index");
  refused("map --dataset other --from oct.json --best --out m.ot", "is not the data set oct.json was swept on");
  refused("map --dataset ds --from oct.json --map-index 100000 --out m.ot", "no map of index 100000");
  refused("map --dataset ds --from oct.json --map-index -1 --out m.ot", "--map-index must be an integer >= 0, got -1");
  refused("map --dataset ds --method knn --p-t 0.1199 --out m.ot", "--p-t 0.1199 (to 1e-6) must lie in");
  // A FIFO at --out: refused as another thing than occsweep's map, not read (a read blocked for ever).
  REQUIRE(::mkfifo((dir / "fifo.ot").c_str(), 0600) == 0);
  const CommandResult fifo = occsweep::test::runIn(dir, "map --dataset ds --method octomap --force --out fifo.ot",
                                                   "timeout 60");
  INFO(fifo.output);
  CHECK(fifo.exit_code == 2);
  CHECK(fifo.output.find("fifo.ot") != std::string::npos);
}

TEST_CASE("map --from says so when the rebuilt map's counts differ from the stored ones") {
  const fs::path dir = sceneIn("map-from-differs");
  // A grid of the user's, changed after the sweep: its hash no longer matches, so no check can hold the maps'
  // parameters against it and the edit below reads as a valid file; only the rebuild can tell.
  nlohmann::json grid = nlohmann::json::parse(
      occsweep::test::bytesOf(occsweep::test::sourceTree() / "sweeps/grids/octomap-opt.json"));
  grid["name"] = "mine";
  std::ofstream(dir / "mine.json") << grid.dump();
  REQUIRE(occsweep::test::runIn(dir, "sweep --dataset ds --quiet --grid mine.json --out oct.json").exit_code == 0);
  std::ofstream(dir / "mine.json", std::ios::app) << "\n";
  // Map 0's parameters replaced by the last map's: its stored counts no longer belong to them (the AUC still
  // matches the counts, so the file reads).
  nlohmann::json j = nlohmann::json::parse(occsweep::test::bytesOf(dir / "oct.json"));
  auto& maps = j.at("maps");
  maps.at(0).at("params") = maps.at(maps.size() - 1).at("params");
  std::ofstream(dir / "edited.json") << j.dump();
  const CommandResult check = occsweep::test::runIn(dir, "results check edited.json");
  INFO(check.output);
  REQUIRE(check.exit_code == 0);
  const CommandResult r = occsweep::test::runIn(dir, "map --dataset ds --from edited.json --map-index 0 --out m.ot");
  INFO(r.output);
  CHECK(r.exit_code == 1);
  CHECK(r.output.find("map 0 of edited.json") != std::string::npos);
  CHECK(r.output.find("counts differ at") != std::string::npos);
  // The unedited file's map 0 is rebuilt with its counts.
  const CommandResult same = occsweep::test::runIn(dir, "map --dataset ds --from oct.json --map-index 0 --out m0.ot");
  INFO(same.output);
  CHECK(same.exit_code == 0);
}

TEST_CASE("compare names the best map map --from --best rebuilds, with every parameter the grid fixes") {
  const fs::path dir = sceneIn("map-compare-best");
  for (const std::string grid : {"octomap-opt", "knn-opt"})
    REQUIRE(occsweep::test::runIn(dir, "sweep --dataset ds --quiet --grid " + grid + " --out " + grid + ".json").exit_code == 0);
  const CommandResult compare = occsweep::test::runIn(dir, "compare octomap-opt.json knn-opt.json --json c.json");
  INFO(compare.output);
  REQUIRE(compare.exit_code == 0);
  CHECK(compare.output.find("p_max=0.98 p_min=0.02 p_h=") != std::string::npos);  // the grid's fixed values too
  const nlohmann::json row = nlohmann::json::parse(occsweep::test::bytesOf(dir / "c.json")).at("rows").at(0);
  const occsweep::ResultsFile knn = occsweep::readResults(dir / "knn-opt.json");
  CHECK(row.at("methods").at("knn").at("map_index") == bestOf(knn).map_index);
  CHECK(row.at("methods").at("knn").at("parameters").at("p_max") == 0.98);
  CHECK(row.at("methods").at("knn").at("parameters").at("k").is_number_integer());  // as results files write it
  const CommandResult from = occsweep::test::runIn(dir, "map --dataset ds --from knn-opt.json --best --out b.ot");
  INFO(from.output);
  CHECK(from.output.find("map " + row.at("methods").at("knn").at("map_index").dump() + " of knn-opt.json") != std::string::npos);
}

TEST_CASE("a best map compare prints at other settings, typed back as flags, rebuilds its stored counts") {
  // Previous code: compare printed the parameters alone; typed back, the map was built at map's default settings
  // (0.1 m, s_c 4, default variant, batch statistics) and its counts were another map's.
  const fs::path dir = sceneIn("map-compare-settings");
  const std::string settings = " --resolution 0.2 --s-c 3 --variant literal --stats online";
  REQUIRE(occsweep::test::runIn(dir, "sweep --dataset ds --quiet --grid knn-opt --out knn.json" + settings).exit_code == 0);
  const CommandResult compare = occsweep::test::runIn(dir, "compare knn.json --baseline knn --json c.json");
  INFO(compare.output);
  REQUIRE(compare.exit_code == 0);
  // The printed map: "map N of knn.json: k=3 p_u=... resolution=0.2 s_c=3 variant=literal stats=online".
  // (wrapped onto indented lines when long).
  const std::string head = "of knn.json:";
  const auto at = compare.output.find(head);
  REQUIRE(at != std::string::npos);
  std::istringstream lines(compare.output.substr(at + head.size()));
  std::string printed, line;
  std::getline(lines, printed);
  while (std::getline(lines, line) && line.starts_with("    ") && line.find(" AUC ") == std::string::npos)
    printed += " " + line;
  std::istringstream words(printed);
  std::string flags;
  for (std::string word; words >> word;) {
    const auto eq = word.find('=');
    REQUIRE(eq != std::string::npos);
    std::string flag = "--" + word.substr(0, eq);
    std::replace(flag.begin(), flag.end(), '_', '-');
    flags += " " + flag + " " + word.substr(eq + 1);
  }
  CHECK(flags.find("--resolution 0.2 --s-c 3 --variant literal --stats online") != std::string::npos);
  const nlohmann::json row = nlohmann::json::parse(occsweep::test::bytesOf(dir / "c.json")).at("rows").at(0);
  CHECK(row.at("methods").at("knn").at("settings") ==
        nlohmann::json({{"resolution", 0.2}, {"s_c", 3.0}, {"variant", "literal"}, {"stats", "online"}}));
  const occsweep::ResultsFile f = occsweep::readResults(dir / "knn.json");
  const occsweep::MapResult& best = bestOf(f);
  const auto& t = best.thresholds.at(best.thresholds.size() / 2);
  char p_t[32];
  std::snprintf(p_t, sizeof p_t, "%.17g", occsweep::toDouble(t.p_t));
  const CommandResult map =
      occsweep::test::runIn(dir, "map --dataset ds --method knn" + flags + " --p-t " + p_t + " --out typed.ot");
  INFO(map.output);
  REQUIRE(map.exit_code == 0);
  CHECK(map.output.find("TP " + std::to_string(t.counts.tp) + " FP " + std::to_string(t.counts.fp) + " FN " +
                        std::to_string(t.counts.fn) + " TN " + std::to_string(t.counts.tn) + " ") != std::string::npos);
}

