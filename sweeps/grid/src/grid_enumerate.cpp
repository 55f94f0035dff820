// The canonical enumeration of a grid and Eq. 15's closed form for its size.
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

// h(T, T', n) of Eq. 14 as "how many values of T' are <= t", floor instead of the paper's ceiling so it is
// exact when steps do not line up.
std::int64_t countAtMost(const ParamRange& r, Fixed t) {
  if (t < r.min) return 0;
  if (r.step == 0) return 1;
  return std::min((t - r.min) / r.step, r.count() - 1) + 1;
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
  });
  return e;
}

std::uint64_t combinationCount(const GridSpec& g) {
  if (const auto closed = closedFormCount(g)) return *closed;
  // Maps before the relations prune any: a bound on the work of counting them one by one.
  std::uint64_t product = 1;
  for (const ParamRange& r : g.ranges) product = std::min<std::uint64_t>(product * std::uint64_t(r.count()), 1ULL << 62);
  checkLimit("grid " + g.name + ": parameter combinations before the relations", product, limits().combinations,
             "--max-combinations");
  std::uint64_t n = 0;
  const std::size_t p_max = g.layout.index("p_max"), p_min = g.layout.index("p_min");
  forEachMap(g, [&](const MapParams& m) {
    n += std::uint64_t(thresholdCount(m.values[p_max], m.values[p_min], g.p_t_step));
  });
  return n;
}

std::optional<std::uint64_t> closedFormCount(const GridSpec& g) {
  if (g.method != "knn" && g.method != "octomap") return std::nullopt;
  const auto p_max = g.range("p_max").values();
  const auto p_min = g.range("p_min").values();
  const auto p_m = g.range("p_m").values();
  std::uint64_t n = 0;
  if (g.method == "knn") {
    // Eq. 15: g(k) * sum_i h(p_u, p_l, i) * sum_i sum_j sum_{q <= h(p'_m, p_m, j)} sum_{w <= h(p_m, p_min, q)} g(p_t)
    std::uint64_t pairs = 0;
    for (Fixed u : g.range("p_u").values()) pairs += std::uint64_t(countAtMost(g.range("p_l"), u));
    std::uint64_t nested = 0;
    for (Fixed max : p_max)
      for (Fixed out : g.range("p_m_out").values())
        for (std::int64_t q = 0; q < countAtMost(g.range("p_m"), out); ++q)
          for (std::int64_t w = 0; w < countAtMost(g.range("p_min"), p_m[std::size_t(q)]); ++w)
            nested += std::uint64_t(thresholdCount(max, p_min[std::size_t(w)], g.p_t_step));
    n = std::uint64_t(g.range("k").count()) * pairs * nested;
  } else {
    // The same structure for OctoMap: sum_i h(p_max, p_h, i) * sum_j sum_{w <= h(p_m, p_min, j)} g(p_t)
    for (Fixed max : p_max) {
      std::uint64_t nested = 0;
      for (Fixed m : p_m)
        for (std::int64_t w = 0; w < countAtMost(g.range("p_min"), m); ++w)
          nested += std::uint64_t(thresholdCount(max, p_min[std::size_t(w)], g.p_t_step));
      // p_h >= 0.5 holds for the whole range (checked on reading); count those <= p_max.
      n += std::uint64_t(countAtMost(g.range("p_h"), max)) * nested;
    }
  }
  return n;
}

}  // namespace occsweep
