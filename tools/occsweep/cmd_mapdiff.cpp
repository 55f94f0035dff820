// occsweep mapdiff A.ot B.ot: how many voxels two maps of the same data disagree on at p_t (the real
// samples have no ground truth, so OctoMap's and the k-NN model's maps are compared with each other).
#include <iostream>
#include <memory>
#include <sstream>

#include <nlohmann/json.hpp>
#include <octomap/OcTree.h>

#include "command_registry.hpp"
#include "option_checks.hpp"
#include "limit_options.hpp"
#include "occsweep/core/log_odds.hpp"
#include "occsweep/data/octree_file.hpp"

namespace occsweep::cli {
namespace {

/// Holds what liboctomap writes to std::cout and std::cerr ("Reading octree type OcTree", "Done (N nodes)": its
/// OCTOMAP_DEBUG_STR and OCTOMAP_ERROR_STR macros) while alive, so that the output is occsweep's JSON alone; its
/// errors are occsweep's own: readOcTree checks the bytes before liboctomap reads them (docs/robustness.md).
class HeldLibraryChatter {
 public:
  HeldLibraryChatter() : out_(std::cout.rdbuf(held_.rdbuf())), err_(std::cerr.rdbuf(held_.rdbuf())) {}
  HeldLibraryChatter(const HeldLibraryChatter&) = delete;
  HeldLibraryChatter& operator=(const HeldLibraryChatter&) = delete;
  ~HeldLibraryChatter() {
    std::cout.rdbuf(out_);
    std::cerr.rdbuf(err_);
  }

 private:
  std::ostringstream held_;
  std::streambuf *out_, *err_;
};

// readOcTree bounds the finest-depth voxels by limits().map_voxels, so expand() is bounded too.
std::unique_ptr<octomap::OcTree> readTree(const std::string& file) {
  std::unique_ptr<octomap::OcTree> tree;
  {
    HeldLibraryChatter quiet;
    tree = readOcTree(file);
  }
  tree->expand();  // every leaf at the finest depth: voxel counts do not depend on pruning
  return tree;
}

// Occupied at p_t (docs/definitions.md, Occupied at a threshold): known and log-odds >= l(p_t) in float;
// unknown is not occupied.
struct Counts {
  std::uint64_t both_occupied = 0, only_a = 0, only_b = 0, both_known = 0, known_a_only = 0, known_b_only = 0;
};

Counts compare(const octomap::OcTree& a, const octomap::OcTree& b, float threshold) {
  Counts c;
  for (auto it = a.begin_leafs(); it != a.end_leafs(); ++it) {
    const bool occ_a = it->getLogOdds() >= threshold;
    const auto* nb = b.search(it.getKey());
    const bool occ_b = nb && nb->getLogOdds() >= threshold;
    (nb ? c.both_known : c.known_a_only)++;
    if (occ_a && occ_b) ++c.both_occupied;
    else if (occ_a) ++c.only_a;
    else if (occ_b) ++c.only_b;
  }
  for (auto it = b.begin_leafs(); it != b.end_leafs(); ++it) {
    if (a.search(it.getKey())) continue;  // counted above
    ++c.known_b_only;
    if (it->getLogOdds() >= threshold) ++c.only_b;
  }
  return c;
}

const RegisterCommand kMapDiff{"mapdiff", "Count the voxels two maps (.ot) disagree on at p_t, as JSON",
                               [](CLI::App& app) {
  addExample(app, "occsweep map --dataset ds --method octomap --out a.ot\noccsweep map --dataset ds --method knn --out b.ot\noccsweep mapdiff a.ot b.ot");
  struct Options {
    std::string a, b;
    double p_t = 0.5;
  };
  auto o = std::make_shared<Options>();
  app.add_option("a", o->a, "First map, .ot")->type_name(kPath)->required();
  app.add_option("b", o->b, "Second map, .ot (same resolution)")->type_name(kPath)->required();
  app.add_option("--p-t", o->p_t, "Occupancy threshold")->capture_default_str()->check(probability());
  addLimitOptions(app, {Limit::MapVoxels});
  return [o] {
    const auto a = readTree(o->a), b = readTree(o->b);
    if (a->getResolution() != b->getResolution())
      throw std::runtime_error(o->b + ": resolution " + std::to_string(b->getResolution()) + " differs from " +
                               o->a + "'s " + std::to_string(a->getResolution()));
    const Counts c = compare(*a, *b, logOdds(o->p_t));
    const nlohmann::json j = {{"a", o->a}, {"b", o->b}, {"p_t", o->p_t}, {"resolution", a->getResolution()},
                              {"occupied_both", c.both_occupied}, {"occupied_only_a", c.only_a},
                              {"occupied_only_b", c.only_b}, {"disagree", c.only_a + c.only_b},
                              {"known_both", c.both_known}, {"known_only_a", c.known_a_only},
                              {"known_only_b", c.known_b_only}};
    std::cout << j.dump(1) << '\n';
    return 0;
  };
}};

}  // namespace
}  // namespace occsweep::cli
