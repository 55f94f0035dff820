// The canonical enumeration of a grid and Eq. 15's closed form for its size.
#include "occsweep/sweeps/grid.hpp"

#include "occsweep/core/limits.hpp"

namespace occsweep {
namespace {

// p_t from p_min to p_max by its step (docs/definitions.md, Parameter grids).
std::vector<Fixed> thresholdValues(Fixed p_min, Fixed p_max, Fixed step) {
  return ParamRange{p_min, p_max, step}.values();
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
  std::vector<Fixed> v;
  if (step == 0) {
    if (min <= max) v.push_back(min);
    return v;
  }
  for (Fixed x = min; x <= max; x += step) v.push_back(x);
  return v;
}

std::int64_t ParamRange::count() const {
  if (min > max) return 0;
  return step == 0 ? 1 : (max - min) / step + 1;
}

GridEnumeration enumerateGrid(const GridSpec& g) {
  // Counted by Eq. 15 before anything is allocated (issue 13: a p_t step of 1e-6 took 3.9 GB, then aborted).
  checkLimit("grid " + g.name + ": combinations (Eq. 15)", closedFormCount(g), limits().combinations,
             "--max-combinations");
  GridEnumeration e;
  auto add = [&](const MapParams& m) {
    e.maps.push_back(m);
    e.first_id.push_back(e.combinations);
    e.thresholds.push_back(thresholdValues(m.p_min, m.p_max, g.p_t_step));
    e.combinations += e.thresholds.back().size();
  };
  if (g.method == GridMethod::Knn) {
    for (int k : g.k)
      for (Fixed p_u : g.p_u.values())
        for (Fixed p_l : g.p_l.values()) {
          if (p_l > p_u) continue;  // Eq. 12: p_u >= p_l
          for (Fixed p_max : g.p_max.values())
            for (Fixed p_min : g.p_min.values())
              for (Fixed p_m : g.p_m.values()) {
                if (p_m < p_min) continue;  // Eq. 12: p_m >= p_min
                for (Fixed p_m_out : g.p_m_out.values()) {
                  if (p_m_out < p_m) continue;  // Eq. 12: p'_m >= p_m
                  MapParams m;
                  m.k = k, m.p_u = p_u, m.p_l = p_l, m.p_max = p_max, m.p_min = p_min, m.p_m = p_m;
                  m.p_m_out = p_m_out;
                  add(m);
                }
              }
        }
  } else {
    for (Fixed p_max : g.p_max.values())
      for (Fixed p_min : g.p_min.values())
        for (Fixed p_h : g.p_h.values()) {
          if (p_h > p_max) continue;  // Eq. 12: p_max >= p_h
          for (Fixed p_m : g.p_m.values()) {
            if (p_m < p_min) continue;  // Eq. 12: p_m >= p_min
            MapParams m;
            m.p_max = p_max, m.p_min = p_min, m.p_h = p_h, m.p_m = p_m;
            add(m);
          }
        }
  }
  return e;
}

std::uint64_t closedFormCount(const GridSpec& g) {
  const auto p_max = g.p_max.values();
  const auto p_min = g.p_min.values();
  const auto p_m = g.p_m.values();
  std::uint64_t n = 0;
  if (g.method == GridMethod::Knn) {
    // Eq. 15: g(k) * sum_i h(p_u, p_l, i) * sum_i sum_j sum_{q <= h(p'_m, p_m, j)} sum_{w <= h(p_m, p_min, q)} g(p_t)
    std::uint64_t pairs = 0;
    for (Fixed u : g.p_u.values()) pairs += std::uint64_t(countAtMost(g.p_l, u));
    std::uint64_t nested = 0;
    for (Fixed max : p_max)
      for (Fixed out : g.p_m_out.values())
        for (std::int64_t q = 0; q < countAtMost(g.p_m, out); ++q)
          for (std::int64_t w = 0; w < countAtMost(g.p_min, p_m[std::size_t(q)]); ++w)
            nested += std::uint64_t(thresholdCount(max, p_min[std::size_t(w)], g.p_t_step));
    n = std::uint64_t(g.k.size()) * pairs * nested;
  } else {
    // The same structure for OctoMap: sum_i h(p_max, p_h, i) * sum_j sum_{w <= h(p_m, p_min, j)} g(p_t)
    for (Fixed max : p_max) {
      std::uint64_t nested = 0;
      for (Fixed m : p_m)
        for (std::int64_t w = 0; w < countAtMost(g.p_min, m); ++w)
          nested += std::uint64_t(thresholdCount(max, p_min[std::size_t(w)], g.p_t_step));
      // p_h >= 0.5 holds for the whole range (checked on reading); count those <= p_max.
      n += std::uint64_t(countAtMost(g.p_h, max)) * nested;
    }
  }
  return n;
}

}  // namespace occsweep
