// The canonical enumeration of a grid and Eq. 15's closed form for its size (any method whose relations form a
// forest).
#include "occsweep/sweeps/grid.hpp"

#include <algorithm>

#include "occsweep/core/limits.hpp"
#include "occsweep/core/method_registry.hpp"

namespace occsweep {
namespace {

// p_t from p_min to p_max by its step (docs/definitions.md, Parameter grids).
std::vector<Fixed> thresholdValues(Fixed p_min, Fixed p_max, Fixed step) {
  ParamRange range;
  range.min = p_min, range.max = p_max, range.step = step;
  return range.values();
}

// g(p_t) for one p_max and p_min.
std::int64_t thresholdCount(Fixed p_max, Fixed p_min, Fixed step) { return p_max < p_min ? 0 : (p_max - p_min) / step + 1; }

}  // namespace

std::vector<Fixed> ParamRange::values() const {
  if (!listed.empty()) return listed;
  std::vector<Fixed> v;
  if (step == 0) {
    if (min <= max) v.push_back(min);
    return v;
  }
  for (Fixed x = min; x <= max; x += step) v.push_back(x);
  return v;
}

std::int64_t ParamRange::count() const {
  if (!listed.empty()) return std::int64_t(listed.size());
  if (min > max) return 0;
  return step == 0 ? 1 : (max - min) / step + 1;
}

namespace {

// A relation as indices into the layout, checked as soon as its later parameter has a value.
struct IndexedRelation {
  std::size_t larger, smaller, depth;
  bool strict;
};

std::vector<IndexedRelation> indexedRelations(const GridSpec& g) {
  std::vector<IndexedRelation> out;
  for (const ParameterRelation& r : findMethod(g.method).relations()) {
    const std::size_t a = g.layout.index(r.larger), b = g.layout.index(r.smaller);
    out.push_back({a, b, std::max(a, b), r.strict});
  }
  return out;
}

// Calls visit(values) for every combination of the grid's parameter values that keeps every relation of its
// method, in canonical order: the method's first parameter outermost, each range ascending (its ids: grid.hpp).
template <class Visit>
void forEachMap(const GridSpec& g, Visit&& visit) {
  const std::vector<IndexedRelation> relations = indexedRelations(g);
  std::vector<std::vector<Fixed>> values;
  for (const ParamRange& r : g.ranges) values.push_back(r.values());
  MapParams m;
  m.values.assign(values.size(), 0);
  const auto holds = [&](std::size_t depth) {
    for (const IndexedRelation& r : relations)
      if (r.depth == depth && !(r.strict ? m.values[r.larger] > m.values[r.smaller]
                                         : m.values[r.larger] >= m.values[r.smaller]))
        return false;
    return true;
  };
  const auto descend = [&](const auto& self, std::size_t depth) -> void {
    if (depth == values.size()) return visit(m);
    for (Fixed v : values[depth]) {
      m.values[depth] = v;
      if (holds(depth)) self(self, depth + 1);
    }
  };
  descend(descend, 0);
}

}  // namespace

std::size_t ParameterLayout::index(const std::string& name) const {
  for (std::size_t i = 0; i < names.size(); ++i)
    if (names[i] == name) return i;
  throw std::invalid_argument("no parameter " + name);
}

bool ParameterLayout::has(const std::string& name) const {
  return std::find(names.begin(), names.end(), name) != names.end();
}

Fixed parameter(const ParameterLayout& layout, const MapParams& params, const std::string& name) {
  return params.values.at(layout.index(name));
}

ParameterLayout layoutOf(const std::string& method) {
  ParameterLayout layout;
  for (const MethodParameter& p : findMethod(method).parameters()) {
    layout.names.push_back(p.name);
    layout.integer.push_back(p.integer);
  }
  return layout;
}

GridEnumeration enumerateGrid(const GridSpec& g) {
  // Counted before anything is allocated (a p_t step of 1e-6 would take 3.9 GB, then abort).
  checkLimit("grid " + g.name + ": combinations", combinationCount(g), limits().combinations, "--max-combinations");
  GridEnumeration e;
  const std::size_t p_max = g.layout.index("p_max"), p_min = g.layout.index("p_min");
  forEachMap(g, [&](const MapParams& m) {
    e.maps.push_back(m);
    e.first_id.push_back(e.combinations);
    e.thresholds.push_back(thresholdValues(m.values[p_min], m.values[p_max], g.p_t_step));
    e.combinations += e.thresholds.back().size();
    if (!e.thresholds.back().empty()) ++e.thresholded_maps;
  });
  e.map_count = e.maps.size();
  return e;
}

// The combinations of the thresholded maps [begin, end): the closed form for the whole grid, else counted.
std::uint64_t windowCombinations(const GridSpec& g, std::uint64_t begin, std::uint64_t end, bool whole) {
  if (whole) return combinationCount(g);
  const std::size_t p_max = g.layout.index("p_max"), p_min = g.layout.index("p_min");
  std::uint64_t ordinal = 0, n = 0;
  forEachMap(g, [&](const MapParams& m) {
    const auto count = std::uint64_t(thresholdCount(m.values[p_max], m.values[p_min], g.p_t_step));
    if (count == 0) return;
    if (ordinal >= begin && ordinal < end) n += count;
    ++ordinal;
  });
  return n;
}

GridEnumeration enumerateMapRange(const GridSpec& g, std::uint64_t begin, std::uint64_t end) {
  // Counted before anything is allocated: the window's memory is what the limit bounds (a shard's, not the grid's).
  const bool whole = begin == 0 && end >= thresholdedMapCount(g);
  checkLimit("grid " + g.name + ": combinations" +
                 (whole ? "" : " of its maps " + std::to_string(begin) + " to " + std::to_string(end) + " (a shard)"),
             windowCombinations(g, begin, end, whole), limits().combinations, "--max-combinations");
  GridEnumeration e;
  const std::size_t p_max = g.layout.index("p_max"), p_min = g.layout.index("p_min");
  forEachMap(g, [&](const MapParams& m) {
    const auto count = std::uint64_t(thresholdCount(m.values[p_max], m.values[p_min], g.p_t_step));
    const std::uint64_t ordinal = e.thresholded_maps;  // among the maps with p_t
    const bool inside = count > 0 ? ordinal >= begin && ordinal < end : !e.maps.empty() && ordinal < end;
    if (inside) {
      if (e.maps.empty()) e.first_map = e.map_count, e.thresholded_before = ordinal;
      e.maps.push_back(m);
      e.first_id.push_back(e.combinations);
      e.thresholds.push_back(thresholdValues(m.values[p_min], m.values[p_max], g.p_t_step));
    }
    e.combinations += count;
    e.thresholded_maps += count > 0 ? 1 : 0;
    ++e.map_count;
  });
  if (e.maps.empty()) e.first_map = e.map_count, e.thresholded_before = e.thresholded_maps;
  return e;
}

namespace {

// Maps before the relations prune any: a bound on the work of walking them one by one (no closed form).
void checkWalkable(const GridSpec& g) {
  std::uint64_t product = 1;
  for (const ParamRange& r : g.ranges) product = std::min<std::uint64_t>(product * std::uint64_t(r.count()), kCountCeiling);
  checkLimit("grid " + g.name + ": parameter combinations before the relations", product, limits().combinations,
             "--max-combinations");
}

}  // namespace

std::uint64_t combinationCount(const GridSpec& g) {
  if (const auto closed = closedFormCount(g)) return *closed;
  checkWalkable(g);
  std::uint64_t n = 0;
  const std::size_t p_max = g.layout.index("p_max"), p_min = g.layout.index("p_min");
  forEachMap(g, [&](const MapParams& m) {
    n += std::uint64_t(thresholdCount(m.values[p_max], m.values[p_min], g.p_t_step));
  });
  return n;
}

namespace {

// Eq. 15 for any method whose relations form a forest (no two paths between two parameters): the maps' count
// factors over the forest's trees, and a tree's count is a sum over its root's values of the product over its
// children of how many of each child's values keep the relation with the parent's value (Eq. 13-14, h, exact for
// any steps). The p_t factor g(p_max, p_min) of Eq. 13 ties p_max and p_min: each tree holding one of them is
// counted once per value of it (rooted there), a tree holding both once per pair, and the products summed over the
// pairs (docs/grids.md, "Counting"). Counts saturate at kCountCeiling.
class ForestCount {
 public:
  ForestCount(const GridSpec& g, const std::vector<ParameterRelation>& relations)
      : edges_(g.ranges.size()), p_max_(g.layout.index("p_max")), p_min_(g.layout.index("p_min")) {
    for (const ParamRange& r : g.ranges) {
      // The values are held: bounded as the combinations are (a range of 10^12 values would take 8 TB).
      checkLimit("grid " + g.name + ": values of one parameter", std::uint64_t(r.count()), limits().combinations,
                 "--max-combinations");
      values_.push_back(r.values());
    }
    for (const ParameterRelation& r : relations) {
      const std::size_t a = g.layout.index(r.larger), b = g.layout.index(r.smaller);
      edges_[a].push_back({b, true, r.strict});
      edges_[b].push_back({a, false, r.strict});
    }
  }

  /// False when two parameters are joined by more than one path: no closed form then.
  [[nodiscard]] bool isForest() const {
    std::vector<int> seen(values_.size(), 0);
    for (std::size_t root = 0; root < values_.size(); ++root)
      if (!seen[root] && !acyclicFrom(root, values_.size(), seen)) return false;
    return true;
  }

  /// The sum over the grid's maps of weight(p_max, p_min), saturated at kCountCeiling.
  template <class Weight>
  [[nodiscard]] std::uint64_t sum(const GridSpec& g, Weight weight) const {
    const std::size_t A = values_[p_max_].size(), B = values_[p_min_].size();
    if (A * B > kMaxPairs)
      throw std::invalid_argument("grid " + g.name + ": p_max and p_min take " + std::to_string(A) + " and " +
                                  std::to_string(B) + " values, more than " + std::to_string(kMaxPairs) +
                                  " pairs to count (docs/grids.md, \"Counting\"): use coarser steps");
    std::vector<unsigned __int128> by_max(A, 1), by_min(B, 1), by_pair;  // the trees of p_max, of p_min, of both
    unsigned __int128 others = 1;
    std::vector<int> seen(values_.size(), 0);
    for (std::size_t root = 0; root < values_.size(); ++root) {
      if (seen[root]) continue;
      const std::vector<int> tree = treeOf(root);
      const bool has_max = tree[p_max_] != 0, has_min = tree[p_min_] != 0;
      for (std::size_t i = 0; i < tree.size(); ++i) seen[i] |= tree[i];
      if (has_max && has_min) by_pair = pairCounts();
      else if (has_max) by_max = rootedCounts(p_max_, kNone);
      else if (has_min) by_min = rootedCounts(p_min_, kNone);
      else others = saturated(others * saturated(total(rootedCounts(root, kNone))));
    }
    unsigned __int128 n = 0;
    for (std::size_t a = 0; a < A; ++a)
      for (std::size_t b = 0; b < B; ++b) {
        const std::uint64_t w = weight(values_[p_max_][a], values_[p_min_][b]);
        if (w == 0) continue;
        const unsigned __int128 pair = by_pair.empty() ? 1 : by_pair[a * B + b];
        n = saturated(n + saturated(saturated(saturated(by_max[a] * by_min[b]) * pair) * w));
      }
    return std::uint64_t(saturated(n * others));
  }

 private:
  struct Edge {
    std::size_t other;
    bool larger;  ///< this parameter is the relation's larger one
    bool strict;
  };
  static constexpr std::size_t kNone = ~std::size_t(0);
  static constexpr std::size_t kMaxPairs = 100'000'000;  // a few seconds of multiplications

  static unsigned __int128 saturated(unsigned __int128 n) { return std::min<unsigned __int128>(n, kCountCeiling); }
  static unsigned __int128 total(const std::vector<unsigned __int128>& counts) {
    unsigned __int128 t = 0;
    for (unsigned __int128 c : counts) t = saturated(t + c);
    return t;
  }

  bool acyclicFrom(std::size_t node, std::size_t parent, std::vector<int>& seen) const {
    seen[node] = 1;
    bool parent_skipped = false;  // one edge back to the parent is the tree's; a second is a cycle
    for (const Edge& e : edges_[node]) {
      if (e.other == parent && !parent_skipped) {
        parent_skipped = true;
        continue;
      }
      if (seen[e.other] || !acyclicFrom(e.other, node, seen)) return false;
    }
    return true;
  }

  // The parameters of the tree holding `root`, as 0/1 flags.
  std::vector<int> treeOf(std::size_t root) const {
    std::vector<int> in(values_.size(), 0);
    std::vector<std::size_t> todo{root};
    in[root] = 1;
    while (!todo.empty()) {
      const std::size_t node = todo.back();
      todo.pop_back();
      for (const Edge& e : edges_[node])
        if (!in[e.other]) in[e.other] = 1, todo.push_back(e.other);
    }
    return in;
  }

  // For each value of `root`, the assignments of its tree rooted there; `fixed` (p_min in a tree with p_max) held
  // at fixed_value_.
  std::vector<unsigned __int128> rootedCounts(std::size_t root, std::size_t fixed) const {
    fixed_ = fixed;
    memo_.assign(values_.size(), {});
    for (std::size_t p = 0; p < values_.size(); ++p) memo_[p].assign(values_[p].size(), kUnknown);
    std::vector<unsigned __int128> counts(values_[root].size());
    for (std::size_t v = 0; v < counts.size(); ++v) counts[v] = allowed(root, v) ? subtree(root, v, kNone) : 0;
    return counts;
  }

  // The tree holding both: for each value of p_min, its counts rooted at p_max; [a * B + b].
  std::vector<unsigned __int128> pairCounts() const {
    const std::size_t A = values_[p_max_].size(), B = values_[p_min_].size();
    std::vector<unsigned __int128> counts(A * B);
    for (std::size_t b = 0; b < B; ++b) {
      fixed_value_ = b;
      const std::vector<unsigned __int128> rooted = rootedCounts(p_max_, p_min_);
      for (std::size_t a = 0; a < A; ++a) counts[a * B + b] = rooted[a];
    }
    return counts;
  }

  bool allowed(std::size_t parameter, std::size_t i) const { return parameter != fixed_ || i == fixed_value_; }

  static bool holds(const Edge& e, Fixed mine, Fixed theirs) {
    const Fixed larger = e.larger ? mine : theirs, smaller = e.larger ? theirs : mine;
    return e.strict ? larger > smaller : larger >= smaller;
  }

  // Assignments of `node`'s subtree (away from `parent`) with `node` at its i-th value; each computed once per
  // rootedCounts call (rooted at one parameter, a node's subtree is the same whichever of its parent's values asks).
  unsigned __int128 subtree(std::size_t node, std::size_t i, std::size_t parent) const {
    if (memo_[node][i] != kUnknown) return memo_[node][i];
    unsigned __int128 product = 1;
    for (const Edge& e : edges_[node]) {
      if (e.other == parent) continue;
      unsigned __int128 sum = 0;
      for (std::size_t j = 0; j < values_[e.other].size(); ++j)
        if (allowed(e.other, j) && holds(e, values_[node][i], values_[e.other][j]))
          sum = saturated(sum + subtree(e.other, j, node));
      product = saturated(product * sum);
    }
    return memo_[node][i] = product;
  }

  static constexpr unsigned __int128 kUnknown = ~(unsigned __int128)0;
  std::vector<std::vector<Fixed>> values_;
  std::vector<std::vector<Edge>> edges_;
  std::size_t p_max_, p_min_;
  mutable std::size_t fixed_ = kNone, fixed_value_ = 0;
  mutable std::vector<std::vector<unsigned __int128>> memo_;
};

// The sum over the grid's maps of weight(p_max, p_min), by the forest count; none when the relations are no forest.
template <class Weight>
std::optional<std::uint64_t> forestSum(const GridSpec& g, Weight weight) {
  const ForestCount forest(g, findMethod(g.method).relations());
  if (!forest.isForest()) return std::nullopt;
  return forest.sum(g, weight);
}

}  // namespace

std::optional<std::uint64_t> closedFormCount(const GridSpec& g) {
  return forestSum(g, [&](Fixed p_max, Fixed p_min) { return std::uint64_t(thresholdCount(p_max, p_min, g.p_t_step)); });
}

std::uint64_t thresholdedMapCount(const GridSpec& g) {
  const auto has_thresholds = [&](Fixed p_max, Fixed p_min) { return thresholdCount(p_max, p_min, g.p_t_step) > 0; };
  if (const auto closed = forestSum(g, [&](Fixed a, Fixed b) { return std::uint64_t(has_thresholds(a, b)); }))
    return *closed;
  checkWalkable(g);
  std::uint64_t n = 0;
  const std::size_t p_max = g.layout.index("p_max"), p_min = g.layout.index("p_min");
  forEachMap(g, [&](const MapParams& m) { n += has_thresholds(m.values[p_max], m.values[p_min]) ? 1 : 0; });
  return n;
}

}  // namespace occsweep
