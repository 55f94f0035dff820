// `occsweep map` writes OctoMap's .ot format with the probabilities kept: liboctomap reads it back, voxel for voxel.
#include <catch2/catch.hpp>

#include <fstream>

#include <nlohmann/json.hpp>
#include <octomap/AbstractOcTree.h>

#include "occsweep/methods/knn/knn_inverse_sensor_model.hpp"
#include "occsweep/core/map_voxels.hpp"
#include "occsweep/eval/builtin_scene.hpp"
#include "test_helpers.hpp"

using namespace occsweep;

TEST_CASE("occsweep map writes a .ot that liboctomap reads back with the same log-odds, settings beside it") {
  const auto dir = test::scratch("map-file");
  const Dataset d = makeBuiltinScene({.seed = 2, .scans = 4, .width = 32, .height = 24});
  writeDataset(d, dir / "scene");
  const auto r = test::runCli("map --dataset " + (dir / "scene").string() +
                              " --method knn --k 2 --p-t 0.62 --p-max 0.95 --out " + (dir / "knn.ot").string());
  REQUIRE(r.exit_code == 0);
  std::unique_ptr<octomap::AbstractOcTree> read(octomap::AbstractOcTree::read((dir / "knn.ot").string()));
  REQUIRE(read);
  auto* tree = dynamic_cast<octomap::OcTree*>(read.get());
  REQUIRE(tree);
  // The .ot format stores resolution and log-odds but not the thresholds: those go in the sidecar JSON.
  std::ifstream sidecar(dir / "knn.ot.json");
  const auto config = nlohmann::json::parse(sidecar);
  CHECK(config.at("method") == "knn");
  CHECK(config.at("parameters").at("p_t") == 0.62);
  CHECK(config.at("parameters").at("p_max") == 0.95);
  CHECK(config.at("parameters").at("k") == 2);
  KnnParams p;
  p.k = 2;
  p.p_t = 0.62;
  p.p_max = 0.95;
  const auto expected = voxelLogOdds(*KnnInverseSensorModel(p).buildMap(readDataset(dir / "scene").scans));
  const auto actual = voxelLogOdds(*tree);
  REQUIRE(actual.size() == expected.size());
  for (const auto& [key, value] : expected) REQUIRE(actual.at(key) == value);
}
