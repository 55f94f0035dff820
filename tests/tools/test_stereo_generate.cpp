// `occsweep dataset generate` end to end (docs/datasets.md): byte-identical outputs, ranking, refusals.
#include <sys/wait.h>

#include <chrono>
#include <fstream>
#include <map>
#include <thread>
#include <sstream>

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "occsweep/eval/dataset.hpp"
#include "test_helpers.hpp"

using namespace occsweep;
namespace fs = std::filesystem;

TEST_CASE("The same name, scale and parameters give byte-identical files, on 1 or 2 threads", "[stereo][cli]") {
  const fs::path a = test::scratch("stereo-gen-a"), b = test::scratch("stereo-gen-b");
  const std::string common = " dataset generate --name parking-plain-S --scale ci --pcs 0,1599 --out ";
  const auto ra = test::runCli(common + a.string() + " --threads 1");
  const auto rb = test::runCli(common + b.string() + " --threads 2");
  REQUIRE(ra.exit_code == 0);
  REQUIRE(rb.exit_code == 0);
  const auto files = test::filesUnder(a);
  REQUIRE(files == test::filesUnder(b));
  CHECK(files.size() > 10);
  for (const auto& f : files) {
    INFO(f);
    CHECK(test::bytesOf(a / f) == test::bytesOf(b / f));
  }
  // Each set is a readable data set recording its parameters; the ranking orders them by naive FDR.
  const auto ranking = nlohmann::json::parse(test::bytesOf(a / "parking-plain-S" / "ranking.json"));
  REQUIRE(ranking["sets"].size() == 2);
  CHECK(ranking["sets"][0]["rank"] == 1);
  CHECK(ranking["sets"][0]["naive"]["fdr"].get<double>() <= ranking["sets"][1]["naive"]["fdr"].get<double>());
  for (const auto& s : ranking["sets"]) {
    const Dataset d = readDataset(a / "parking-plain-S" / s["folder"].get<std::string>());
    CHECK(d.source["pointcloud_id"] == s["id"]);
    CHECK(d.source["sgbm"]["blockSize"] == s["params"]["blockSize"]);
    CHECK(pointCount(d.scans) == s["points"].get<std::uint64_t>());
    CHECK(d.truth.boxes.size() == 4);
  }
  // A different seed changes the sensor noise, hence the clouds.
  const fs::path c = test::scratch("stereo-gen-c");
  REQUIRE(test::runCli(common + c.string() + " --seed 2 --no-preview").exit_code == 0);
  CHECK(test::bytesOf(a / "parking-plain-S/pcs-0000/scans/000000.f32") != test::bytesOf(c / "parking-plain-S/pcs-0000/scans/000000.f32"));
}

TEST_CASE("Voronoi boxes give more valid target disparities than plain ones", "[stereo][cli]") {
  const fs::path dir = test::scratch("stereo-gen-texture");
  for (const char* name : {"building-plain-T", "building-voronoi-T"})
    REQUIRE(test::runCli(std::string(" dataset generate --no-preview --scale ci --pcs 800 --name ") + name + " --out " +
                         dir.string()).exit_code == 0);
  auto valid = [&](const char* name) {
    return nlohmann::json::parse(test::bytesOf(dir / name / "ranking.json"))["sets"][0]["target_valid_fraction"].get<double>();
  };
  CHECK(valid("building-voronoi-T") > 0.95);
  CHECK(valid("building-plain-T") < valid("building-voronoi-T") - 0.05);
}

TEST_CASE("Two textures, seeds and SGBM settings of one layout share the scene, other geometry does not", "[stereo][cli]") {
  // provenance.scene (docs/dataset-format.md, "Provenance"): compare counts the sets that share it as one scene.
  const fs::path dir = test::scratch("stereo-gen-scene");
  const std::vector<std::pair<std::string, std::string>> runs = {
      {"plain", "--name building-plain-T --pcs 0"},
      {"voronoi", "--name building-voronoi-T --pcs 800 --seed 3"},
      {"parking", "--name parking-plain-T --pcs 0"},
      {"lower", "--name building-plain-T --pcs 0 --box-height 0.47"}};
  std::map<std::string, nlohmann::json> scene;
  for (const auto& [label, args] : runs) {
    REQUIRE(test::runCli(" dataset generate --no-preview --scale ci " + args + " --out " + (dir / label).string())
                .exit_code == 0);
    const std::string set = label == "voronoi" ? "pcs-0800" : "pcs-0000";
    const fs::path folder = dir / label / args.substr(7, args.find(' ', 7) - 7) / set;
    scene[label] = readDataset(folder).source.at("provenance").at("scene");
  }
  CHECK(scene["plain"] == scene["voronoi"]);
  CHECK(scene["plain"] != scene["parking"]);
  CHECK(scene["plain"] != scene["lower"]);
}

TEST_CASE("Bad arguments are refused with a clear message and no output", "[stereo][cli]") {
  const fs::path dir = test::scratch("stereo-gen-bad");
  const fs::path out = dir / "out";
  auto refused = [&](const std::string& args, const std::string& message) {
    const auto r = test::runCli(" dataset generate --out " + out.string() + " " + args);
    INFO(r.output);
    CHECK(r.exit_code != 0);
    CHECK(r.output.find(message) != std::string::npos);
    CHECK(!fs::exists(out));
  };
  refused("--name building-plain-X", "layout must be one of I, O, T, L, S");
  refused("--name building-plain-L --all", "either --name");
  refused("--name building-plain-L --pcs 1600", "ids run from 0 to 1599");
  refused("--name building-plain-L --sgbm blockSize=4", "blockSize 4: must be odd");
  refused("--name building-plain-L --scale huge", "huge");
}

TEST_CASE("Every scan records the left camera at its keyframe and the observable truth stays what it was", "[stereo][cli]") {
  // docs/dataset-format.md, "Sensor views"; the counts of docs/fidelity.md's observable-truth table.
  const fs::path dir = test::scratch("stereo-gen-views");
  REQUIRE(test::runCli(" dataset generate --no-preview --scale ci --pcs 0 --name building-plain-L --out " +
                       dir.string()).exit_code == 0);
  const fs::path set = dir / "building-plain-L" / "pcs-0000";
  const Dataset d = readDataset(set);
  std::size_t in_view = 0;
  for (const Scan& scan : d.scans) {
    REQUIRE(scan.view);
    const auto* camera = std::get_if<PinholeView>(&*scan.view);
    REQUIRE(camera);
    CHECK(camera->width == 320);
    CHECK(camera->height == 180);
    CHECK(camera->fx == 175.0);
    for (const auto& p : scan.points) in_view += inView(*scan.view, scan.origin, p);
  }
  // The points are reprojected pixels, voxel-filtered: centroids of the image's edge may leave it by a hair.
  CHECK(double(in_view) > 0.99 * double(pointCount(d.scans)));
  const auto map = test::runCli(" map --dataset " + set.string() + " --method octomap --truth observable --out " +
                                (dir / "m.ot").string());
  INFO(map.output);
  CHECK_THAT(map.output, Catch::Contains("(observable truth): TP 272 FP 380 FN 1 "));
}

TEST_CASE("dataset generate replaces its own earlier output only with --force, and refuses before any work",
          "[stereo][cli][ownership]") {
  const fs::path dir = test::scratch("stereo-gen-force");
  const std::string command = "dataset generate --name building-plain-I --scale ci --pcs 0 --no-preview --quiet --out " +
                              dir.string();
  REQUIRE(test::runCli(command).exit_code == 0);
  const fs::path set = dir / "building-plain-I" / "pcs-0000";
  const std::string manifest = test::bytesOf(set / "manifest.json");
  // Old binary: a re-run with another seed replaced the earlier set without a word, exit 0.
  auto r = test::runCli(command + " --seed 5");
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.output, Catch::Contains("pcs-0000") && Catch::Contains("--force"));
  CHECK(test::bytesOf(set / "manifest.json") == manifest);
  // Old binary: with a user's ranking.json there, pcs-0000 was regenerated first, then the run said "nothing was
  // changed". Now the user's file is found before any work, with or without --force.
  const fs::path ranking = dir / "building-plain-I" / "ranking.json";
  std::ofstream(ranking, std::ios::trunc) << "{\"format\": \"mine\"}\n";
  r = test::runCli(command + " --seed 5 --force");
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.output, Catch::Contains("ranking.json"));
  CHECK(test::bytesOf(set / "manifest.json") == manifest);
  CHECK(test::bytesOf(ranking) == "{\"format\": \"mine\"}\n");
  fs::remove(ranking);
  r = test::runCli(command + " --seed 5 --force");
  CHECK(r.exit_code == 0);
  CHECK(test::bytesOf(set / "manifest.json") != manifest);
}

TEST_CASE("a generation that fails removes what it made, never a file put in a folder it made",
          "[stereo][cli][ownership]") {
  // Old binary: the failure removed the outermost folder it had made (new/), with the user's notes.txt in it.
  const fs::path dir = test::scratch("stereo-gen-fail");
  const fs::path out = dir / "new" / "ds";
  // ulimit -f 1: the first scan written fails (EFBIG), after the folders are made and the keyframes rendered.
  const pid_t pid = test::startShell("ulimit -f 1; exec " + test::shellQuoted(test::cliUnderTest()) +
                                     " dataset generate --name building-plain-I --scale ci --pcs 0 --quiet --out " +
                                     test::shellQuoted(out) + " > /dev/null 2>&1");
  for (int i = 0; i < 2000 && !fs::exists(out / "building-plain-I"); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  REQUIRE(fs::exists(out / "building-plain-I"));
  std::ofstream(dir / "new" / "notes.txt") << "the user's notes\n";
  int status = 0;
  ::waitpid(pid, &status, 0);
  CHECK(WIFEXITED(status));
  CHECK(WEXITSTATUS(status) == 2);
  CHECK(test::bytesOf(dir / "new" / "notes.txt") == "the user's notes\n");
  CHECK_FALSE(fs::exists(out));  // the folders it made and left empty are gone
}
