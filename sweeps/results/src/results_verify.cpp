// Everything a results file claims, checked (docs/results-format.md): a hand edit, a merge gone wrong or a
// truncated selection cannot pass for a complete sweep.
#include "occsweep/sweeps/results_verify.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <stdexcept>

#include "occsweep/core/method_registry.hpp"
#include "occsweep/eval/coordinates.hpp"
#include "occsweep/eval/dataset.hpp"
#include "occsweep/sweeps/sharding.hpp"
#include "occsweep/sweeps/selection.hpp"

namespace occsweep {
namespace {

struct Claims {
  const ResultsFile& f;
  const std::string& file;

  [[noreturn]] void fail(const std::string& where, const std::string& rule) const {
    throw std::runtime_error(file + ": " + where + ": " + rule);
  }

  void settings() const {
    const ResultsHeader& h = f.header;
    if (!std::isfinite(h.resolution) || !(h.resolution > 0))
      fail("map.resolution", "must be a finite number > 0 (metres)");
    if (!std::isfinite(h.s_c) || !(h.s_c > 0)) fail("map.s_c", "must be a finite number > 0 (metres)");
    if (!kUpdateVariantNames.accepts(h.variant))
      fail("map.variant", "must be " + kUpdateVariantNames.alternatives("\""));
    if (!kStatsModeNames.accepts(h.stats)) fail("map.stats", "must be " + kStatsModeNames.alternatives("\""));
    if (h.grid_combinations == 0) fail("grid.combinations", "must be at least 1");
    if (h.selection.shard_count > h.grid_combinations)
      fail("selection.shard.count", "is more than the grid's " + std::to_string(h.grid_combinations) + " combinations");
    if (h.selection.group && h.selection.group->count > h.grid_combinations)
      fail("selection.group.count", "is more than the grid's " + std::to_string(h.grid_combinations) +
                                        " combinations (every Eq. 16 group holds at least one)");
  }

  void probability(Fixed v, const std::string& where) const {
    if (v < 0 || v > kFixedScale) fail(where, "must be a probability in [0, 1]");
  }

  // Each value within its parameter's bounds, when this program has the method registered (docs/methods.md).
  void params(const MapResult& m, const std::string& where) const {
    if (m.params.values.size() != f.header.parameters.names.size()) fail(where + ".params", "has other parameters");
    const MappingMethod* method = nullptr;
    try {
      method = &findMethod(f.header.method);
    } catch (const std::invalid_argument&) {
      return;  // another program's method: its bounds are not known here
    }
    const std::vector<MethodParameter> parameters = method->parameters();
    for (std::size_t i = 0; i < parameters.size() && i < m.params.values.size(); ++i) {
      const MethodParameter& p = parameters[i];
      const double v = toDouble(m.params.values[i]);
      if ((p.lowest_open ? !(v > p.lowest) : !(v >= p.lowest)) || (p.highest_open ? !(v < p.highest) : !(v <= p.highest)))
        fail(where + ".params." + p.name, "is outside the bounds of " + f.header.method + "'s " + p.name);
    }
  }

  // Ids unique across the file, inside the grid; p_t increasing within a map; one region for every map.
  std::uint64_t mapsAndCounts() const {
    std::set<std::uint64_t> ids;
    std::uint64_t total = 0, truth = 0;
    bool first = true;
    for (std::size_t i = 0; i < f.maps.size(); ++i) {
      const MapResult& m = f.maps[i];
      const std::string where = "maps[" + std::to_string(i) + "]";
      if (i > 0 && m.map_index <= f.maps[i - 1].map_index)
        fail(where + ".map_index", "map " + std::to_string(m.map_index) + " after map " +
                                       std::to_string(f.maps[i - 1].map_index) +
                                       ": every map at most once, in increasing order (duplicated map?)");
      if (m.map_index >= f.header.grid_combinations) fail(where + ".map_index", "is beyond the grid's combinations");
      params(m, where);
      for (std::size_t t = 0; t < m.thresholds.size(); ++t) {
        const ThresholdResult& r = m.thresholds[t];
        const std::string tw = where + ".thresholds[" + std::to_string(t) + "]";
        probability(r.p_t, tw + ".p_t");
        if (t > 0 && !(r.p_t > m.thresholds[t - 1].p_t))
          fail(tw + ".p_t", "thresholds must have increasing p_t, each at most once (duplicated threshold?)");
        if (r.id >= f.header.grid_combinations) fail(tw + ".id", "is beyond the grid's combinations");
        if (!ids.insert(r.id).second) fail(tw + ".id", "id " + std::to_string(r.id) + " appears twice in the file");
        const auto& c = r.counts;
        std::uint64_t sum = 0, positives = 0;
        if (__builtin_add_overflow(c.tp, c.fn, &positives) || __builtin_add_overflow(positives, c.fp, &sum) ||
            __builtin_add_overflow(sum, c.tn, &sum) || sum > kMaxRegionVoxels)
          fail(tw, "TP+FP+FN+TN is more than the 2^48 voxels OctoMap's keys can address");
        if (first) {
          total = sum;
          truth = positives;
          first = false;
        }
        if (sum != total)
          fail(tw, "TP+FP+FN+TN is " + std::to_string(sum) + ", another map of the file counts " +
                       std::to_string(total) + ": every map classifies the same region");
        if (positives != truth)
          fail(tw, "TP+FN is " + std::to_string(positives) + ", another map of the file counts " +
                       std::to_string(truth) + ": every map has the same true voxels");
      }
    }
    return ids.size();
  }

  // A complete file of a whole grid or Eq. 16 group holds exactly the selection's ids.
  void completeSelection(std::uint64_t id_count) const {
    const ResultsHeader& h = f.header;
    if (!f.complete || h.selection.shard_count != 1) return;  // a shard's maps need the grid: verifyCoverage
    const std::uint64_t n = h.grid_combinations;
    std::uint64_t expected = n;
    if (h.selection.group) {
      const auto& g = *h.selection.group;
      const Block b = contiguousBlock(n, g.count, g.index);
      expected = b.end - b.begin;
    }
    if (id_count != expected)
      fail("maps", "complete, but holds " + std::to_string(id_count) + " combinations of the " +
                       std::to_string(expected) + " its selection claims (a missing map?)");
    if (h.selection.group && n <= kMaxCheckedPermutation) {
      GridEnumeration shape;
      shape.combinations = n;
      const auto group_ids = expectedIds(shape, h.selection);
      for (std::size_t i = 0; i < f.maps.size(); ++i)
        for (const auto& t : f.maps[i].thresholds)
          if (!std::binary_search(group_ids.begin(), group_ids.end(), t.id))
            fail("maps[" + std::to_string(i) + "]", "id " + std::to_string(t.id) + " is not in Eq. 16 group " +
                                                        std::to_string(h.selection.group->index));
    }
  }
};

}  // namespace

void verifyClaims(const ResultsFile& f, const std::string& file) {
  const Claims c{f, file};
  c.settings();
  c.completeSelection(c.mapsAndCounts());
}

void verifyCoverage(const ResultsFile& f, const GridSpec& grid, const GridEnumeration& e, const std::string& file) {
  if (!f.complete) return;
  std::map<std::uint64_t, const MapResult*> maps;
  for (const auto& m : f.maps) maps[m.map_index] = &m;
  const auto items = selectWork(grid, e, f.header.selection);
  for (const SweepItem& item : items) {
    const std::string where = file + ": map " + std::to_string(item.map_index);
    const auto it = maps.find(item.map_index);
    if (it == maps.end()) throw std::runtime_error(where + ": missing, though the file says complete");
    const MapResult& m = *it->second;
    if (m.thresholds.size() != item.thresholds.size())
      throw std::runtime_error(where + ": holds " + std::to_string(m.thresholds.size()) + " thresholds, its selection " +
                               std::to_string(item.thresholds.size()));
    for (std::size_t t = 0; t < item.thresholds.size(); ++t)
      if (m.thresholds[t].id != e.first_id[item.map_index] + item.thresholds[t])
        throw std::runtime_error(where + ": threshold " + std::to_string(t) + " has id " +
                                 std::to_string(m.thresholds[t].id) + ", not the selection's");
    maps.erase(it);
  }
  if (!maps.empty())
    throw std::runtime_error(file + ": map " + std::to_string(maps.begin()->first) +
                             ": not in this file's selection (shard " +
                             std::to_string(f.header.selection.shard_index) + "/" +
                             std::to_string(f.header.selection.shard_count) + ")");
}

void verifyAgainstDataset(const ResultsFile& f, const std::string& file, const std::filesystem::path& dir) {
  const std::string hash = datasetContentHash(dir);
  if (hash != f.header.dataset_hash)
    throw std::runtime_error(file + ": dataset.content_hash: is " + f.header.dataset_hash + ", " + dir.string() +
                             " has " + hash + ": results of another data set (or of an edited one)");
  const Dataset d = readDataset(dir);
  requireInKeyRange(d, dir, f.header.resolution);
  // Observable truth leaves its unobservable voxels out of the region and of the truth alike.
  const GroundTruth gt = evaluatedTruth(f.header.truth, makeGroundTruth(d.truth, d.region, f.header.resolution),
                                        d.scans, f.header.s_c);
  const std::uint64_t region = gt.evaluatedVoxelCount(), truth = gt.evaluatedTrueVoxelCount();
  for (std::size_t i = 0; i < f.maps.size(); ++i)
    for (std::size_t t = 0; t < f.maps[i].thresholds.size(); ++t) {
      const auto& c = f.maps[i].thresholds[t].counts;
      const std::string where = file + ": maps[" + std::to_string(i) + "].thresholds[" + std::to_string(t) + "]: ";
      if (c.tp + c.fp + c.fn + c.tn != region)
        throw std::runtime_error(where + "TP+FP+FN+TN is " + std::to_string(c.tp + c.fp + c.fn + c.tn) + ", the region of " +
                                 dir.string() + " holds " + std::to_string(region) + " voxels at resolution " +
                                 std::to_string(f.header.resolution) + " m");
      if (c.tp + c.fn != truth)
        throw std::runtime_error(where + "TP+FN is " + std::to_string(c.tp + c.fn) + ", the truth of " + dir.string() +
                                 " fills " + std::to_string(truth) + " voxels of the region" +
                                 (f.header.truth == TruthMode::Observable ? " observable from its scans" : ""));
    }
}

}  // namespace occsweep
