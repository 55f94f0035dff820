// Refusals: parameters that break Eq. 12, and data sets that are broken on disk.
#include <catch2/catch.hpp>

#include <fstream>

#include "occsweep/methods/knn/knn_parameters.hpp"
#include "occsweep/core/method_registry.hpp"
#include "occsweep/core/splitmix64.hpp"
#include "occsweep/eval/builtin_scene.hpp"
#include "occsweep/io/data_error.hpp"
#include "test_helpers.hpp"

using namespace occsweep;
using Catch::Matchers::Contains;

TEST_CASE("parameter sets that break Eq. 12 are refused with the relation named") {
  auto knn = [](auto edit) {
    KnnParams p;
    edit(p);
    auto why = brokenRelation(p);
    return why ? *why : std::string("valid");
  };
  CHECK(knn([](KnnParams&) {}) == "valid");
  CHECK_THAT(knn([](KnnParams& p) { p.p_max = 1.0; }), Contains("p_max = 1 must lie in [0.5, 1) (Eq. 12)"));
  CHECK_THAT(knn([](KnnParams& p) { p.p_max = 0.45; }), Contains("p_max = 0.45 must lie in [0.5, 1) (Eq. 12)"));
  CHECK_THAT(knn([](KnnParams& p) { p.p_m_out = 0.5; }), Contains("p'_m = 0.5 must lie in (0, 0.5) (Eq. 12)"));
  CHECK_THAT(knn([](KnnParams& p) { p.p_m_out = 0.3; }), Contains("p'_m >= p_m does not hold"));
  CHECK_THAT(knn([](KnnParams& p) { p.p_min = 0.41; p.p_t = 0.5; }), Contains("p_m >= p_min does not hold"));
  CHECK_THAT(knn([](KnnParams& p) { p.p_min = 0.0; }), Contains("p_min = 0 must lie in (0, 0.5) (Eq. 12)"));
  CHECK_THAT(knn([](KnnParams& p) { p.p_t = 0.99; }), Contains("p_max >= p_t does not hold"));
  CHECK_THAT(knn([](KnnParams& p) { p.p_t = 0.05; }), Contains("p_t >= p_min does not hold"));
  CHECK_THAT(knn([](KnnParams& p) { p.p_u = 0.2; }), Contains("p_u >= p_l does not hold"));
  CHECK_THAT(knn([](KnnParams& p) { p.k = 0; }), Contains("k = 0 must lie in [1, 100000], an integer"));
  CHECK_THAT(knn([](KnnParams& p) { p.map.s_c = 0; }), Contains("s_c must be a finite number > 0"));
  OctoMapParams om;
  CHECK_FALSE(brokenRelation(om));
  om.p_h = 0.99;
  CHECK_THAT(*brokenRelation(om), Contains("p_max >= p_h does not hold"));
  om.p_h = 0.45;
  CHECK_THAT(*brokenRelation(om), Contains("p_h = 0.45 must lie in [0.5, 1) (Eq. 12)"));
  CHECK_THROWS_AS(validate(om), std::invalid_argument);
}

TEST_CASE("the mappers' settings check exactly what their methods check, with the methods' defaults") {
  // Eq. 12 is written once (octomap_parameters.hpp, knn_parameters.hpp): a KnnParams or OctoMapParams is refused
  // exactly when the same values are refused as a map of the registered method, over random values around every bound.
  const MappingMethod& knn_method = findMethod("knn");
  const MappingMethod& octomap_method = findMethod("octomap");
  CHECK(defaultValues(knn_method) == MethodValues{double(KnnParams{}.k), KnnParams{}.p_u, KnnParams{}.p_l,
                                                  KnnParams{}.p_max, KnnParams{}.p_min, KnnParams{}.p_m,
                                                  KnnParams{}.p_m_out});
  CHECK(defaultValues(octomap_method) ==
        MethodValues{OctoMapParams{}.p_max, OctoMapParams{}.p_min, OctoMapParams{}.p_h, OctoMapParams{}.p_m});
  SplitMix64 rng(12);
  auto draw = [&] { return double(rng.below(23)) * 0.05 - 0.05; };  // -0.05 .. 1.05: every bound, both sides
  for (int i = 0; i < 4000; ++i) {
    KnnParams p;
    p.k = int(rng.below(3));
    p.p_u = draw(), p.p_l = draw(), p.p_max = draw(), p.p_min = draw(), p.p_m = draw(), p.p_m_out = draw();
    p.p_t = p.p_min;  // p_t is no parameter of a method
    const MethodValues v = {double(p.k), p.p_u, p.p_l, p.p_max, p.p_min, p.p_m, p.p_m_out};
    INFO(i);
    CHECK(brokenRelation(p).has_value() == brokenRelation(knn_method, v).has_value());
    OctoMapParams o;
    o.p_max = draw(), o.p_min = draw(), o.p_h = draw(), o.p_m = draw();
    o.p_t = o.p_min;
    CHECK(brokenRelation(o).has_value() ==
          brokenRelation(octomap_method, MethodValues{o.p_max, o.p_min, o.p_h, o.p_m}).has_value());
  }
}

TEST_CASE("the occsweep command refuses broken parameters with a non-zero exit") {
  const auto dir = test::scratch("params-cli");
  writeDataset(makeBuiltinScene({.scans = 2, .width = 8, .height = 6}), dir / "scene");
  const auto r = test::runCli("map --dataset " + (dir / "scene").string() + " --method knn --p-u 0.2 --p-l 0.4 --out " +
                              (dir / "m.ot").string());
  CHECK(r.exit_code != 0);
  CHECK_THAT(r.output, Contains("p_u >= p_l"));
  CHECK_FALSE(std::filesystem::exists(dir / "m.ot"));
  const auto ok = test::runCli("map --dataset " + (dir / "scene").string() + " --method octomap --out " +
                               (dir / "m.ot").string());
  CHECK(ok.exit_code == 0);
  CHECK(std::filesystem::exists(dir / "m.ot"));
}

TEST_CASE("data sets round-trip through the on-disk format") {
  const auto dir = test::scratch("dataset-roundtrip");
  const Dataset d = makeBuiltinScene({.seed = 7, .scans = 3, .width = 16, .height = 12});
  writeDataset(d, dir / "s");
  const Dataset r = readDataset(dir / "s");
  CHECK(r.name == d.name);
  REQUIRE(r.scans.size() == d.scans.size());
  for (std::size_t i = 0; i < d.scans.size(); ++i) {
    CHECK(r.scans[i].origin == d.scans[i].origin);
    REQUIRE(r.scans[i].points.size() == d.scans[i].points.size());
    for (std::size_t j = 0; j < d.scans[i].points.size(); ++j) CHECK(r.scans[i].points[j] == d.scans[i].points[j]);
  }
  CHECK(r.truth.boxes.size() == 4);
  CHECK(datasetContentHash(dir / "s") == datasetContentHash(dir / "s"));
  writeDataset(makeBuiltinScene({.seed = 8, .scans = 3, .width = 16, .height = 12}), dir / "t");
  CHECK(datasetContentHash(dir / "s") != datasetContentHash(dir / "t"));
}

TEST_CASE("broken data sets give an error naming the file and the field") {
  const auto dir = test::scratch("dataset-broken");
  const Dataset d = makeBuiltinScene({.scans = 2, .width = 8, .height = 6});
  auto fresh = [&] {
    std::filesystem::remove_all(dir / "s");
    writeDataset(d, dir / "s");
    return dir / "s";
  };
  // The reader's message; and the command, given the same data set, must exit non-zero with that message and
  // write no map.
  auto error = [&](const std::filesystem::path& p) {
    std::string message = "no error";
    try {
      (void)readDataset(p);
    } catch (const DataError& e) {
      message = e.what();
    }
    const auto map = dir / "m.ot";
    const auto r = test::runCli("map --dataset " + p.string() + " --method octomap --out " + map.string());
    CHECK(r.exit_code != 0);
    CHECK_THAT(r.output, Contains(message));
    CHECK_FALSE(std::filesystem::exists(map));
    return message;
  };
  SECTION("NaN coordinate") {
    const auto s = fresh();
    std::fstream f(s / "scans/000001.f32", std::ios::in | std::ios::out | std::ios::binary);
    const float nan = NAN;
    f.seekp(12 * 3 + 4);
    f.write(reinterpret_cast<const char*>(&nan), 4);
    f.close();
    CHECK_THAT(error(s), Contains("000001.f32") && Contains("scans[1]") && Contains("point 3"));
  }
  SECTION("infinite coordinate") {
    const auto s = fresh();
    std::fstream f(s / "scans/000000.f32", std::ios::in | std::ios::out | std::ios::binary);
    const float inf = INFINITY;
    f.write(reinterpret_cast<const char*>(&inf), 4);
    f.close();
    CHECK_THAT(error(s), Contains("000000.f32") && Contains("NaN or infinite"));
  }
  SECTION("truncated scan file") {
    const auto s = fresh();
    std::filesystem::resize_file(s / "scans/000001.f32", 12 * 5 + 7);
    CHECK_THAT(error(s), Contains("000001.f32") && Contains("truncated"));
  }
  SECTION("missing scan file") {
    const auto s = fresh();
    std::filesystem::remove(s / "scans/000000.f32");
    CHECK_THAT(error(s), Contains("000000.f32") && Contains("missing"));
  }
  SECTION("empty scan") {
    const auto s = fresh();
    std::ifstream in(s / "manifest.json");
    auto j = nlohmann::json::parse(in);
    j["scans"][1]["points"] = 0;
    std::ofstream(s / "manifest.json") << j.dump();
    CHECK_THAT(error(s), Contains("manifest.json") && Contains("scans[1].points") && Contains("empty scan"));
  }
  SECTION("missing manifest and bad fields") {
    const auto s = fresh();
    std::ofstream(s / "manifest.json") << "{\"format\": \"occsweep-dataset\", \"version\": 1";
    CHECK_THAT(error(s), Contains("manifest.json") && Contains("not valid JSON"));
    std::filesystem::remove(s / "manifest.json");
    CHECK_THAT(error(s), Contains("manifest.json") && Contains("missing"));
  }
  SECTION("the command exits non-zero and writes no map") {
    const auto s = fresh();
    std::filesystem::resize_file(s / "scans/000001.f32", 5);
    const auto r = test::runCli("map --dataset " + s.string() + " --method octomap --out " + (dir / "m.ot").string());
    CHECK(r.exit_code != 0);
    CHECK_THAT(r.output, Contains("000001.f32"));
    CHECK_FALSE(std::filesystem::exists(dir / "m.ot"));
  }
}
