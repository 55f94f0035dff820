// Map-level parameters of one grid combination as the core's mapper structs (sweep.hpp).
#include "occsweep/sweeps/sweep.hpp"

namespace occsweep {

KnnParams knnParams(const MapParams& m, const SweepConfig& c, Fixed p_t) {
  KnnParams p;
  p.p_u = toDouble(m.p_u);
  p.p_l = toDouble(m.p_l);
  p.p_m = toDouble(m.p_m);
  p.p_m_out = toDouble(m.p_m_out);
  p.p_max = toDouble(m.p_max);
  p.p_min = toDouble(m.p_min);
  p.p_t = toDouble(p_t);
  p.k = m.k;
  p.resolution = c.resolution;
  p.s_c = c.s_c;
  p.variant = c.variant;
  p.stats = c.stats;
  return p;
}

OctoMapParams octomapParams(const MapParams& m, const SweepConfig& c, Fixed p_t) {
  return {toDouble(m.p_h), toDouble(m.p_m), toDouble(m.p_max), toDouble(m.p_min), toDouble(p_t), c.resolution, c.s_c};
}

}  // namespace occsweep
