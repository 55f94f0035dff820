#include "occsweep/eval/builtin_scene.hpp"

#include <cmath>
#include <limits>

#include "occsweep/core/splitmix64.hpp"
#include "occsweep/eval/provenance.hpp"

namespace occsweep {
namespace {

struct Vec {
  double x, y, z;
  Vec operator+(const Vec& o) const { return {x + o.x, y + o.y, z + o.z}; }
  Vec operator-(const Vec& o) const { return {x - o.x, y - o.y, z - o.z}; }
  Vec operator*(double s) const { return {x * s, y * s, z * s}; }
  [[nodiscard]] double dot(const Vec& o) const { return x * o.x + y * o.y + z * o.z; }
  [[nodiscard]] Vec cross(const Vec& o) const { return {y * o.z - z * o.y, z * o.x - x * o.z, x * o.y - y * o.x}; }
  [[nodiscard]] Vec unit() const { return *this * (1.0 / std::sqrt(dot(*this))); }
};

// Slab test: distance along a unit ray to an axis-aligned box, +inf when missed.
double rayBox(const Vec& o, const Vec& d, const AxisBox& b) {
  double t0 = 0.0, t1 = std::numeric_limits<double>::infinity();
  const double oo[3] = {o.x, o.y, o.z}, dd[3] = {d.x, d.y, d.z};
  for (int a = 0; a < 3; ++a) {
    if (std::abs(dd[a]) < 1e-15) {
      if (oo[a] < b.min[a] || oo[a] > b.max[a]) return std::numeric_limits<double>::infinity();
      continue;
    }
    double ta = (b.min[a] - oo[a]) / dd[a], tb = (b.max[a] - oo[a]) / dd[a];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
    if (t0 > t1) return std::numeric_limits<double>::infinity();
  }
  return t0;
}

// What the simulated camera sees: its rays leave through pixel centres u + 0.5 - width / 2 to the right and
// v + 0.5 - height / 2 down at `focal` forward, so in camera axes (x right, y down, z forward) it is a pinhole with
// fx = fy = focal and the principal point between the middle pixels (docs/dataset-format.md, "Sensor views").
PinholeView cameraView(const BuiltinSceneConfig& c, double focal, const Vec& right, const Vec& up, const Vec& forward) {
  const Vec down = up * -1.0;
  return PinholeView{focal, focal, c.width / 2.0 - 0.5, c.height / 2.0 - 0.5, c.width, c.height,
                     {right.x, down.x, forward.x, right.y, down.y, forward.y, right.z, down.z, forward.z}};
}

}  // namespace

Dataset makeBuiltinScene(const BuiltinSceneConfig& c) {
  Dataset d;
  d.name = "builtin-O";
  // O tetromino: a 2x2 block of boxes, shifted off the voxel grid so faces cut voxels as real ones would.
  const double e = c.box_edge, ox = 0.02, oy = 0.03;
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j)
      d.truth.boxes.push_back(AxisBox{{ox + (i - 1) * e, oy + (j - 1) * e, 0.0}, {ox + i * e, oy + j * e, e}});
  // Region around the targets, above the ground layer (voxel centres from 0.15 m up).
  d.region = AxisBox{{-1.5, -1.5, 0.1}, {1.5, 1.5, 1.0}};

  SplitMix64 rng(c.seed);
  const Vec target{ox, oy, e / 2};
  const double fov = c.fov_horizontal_deg * M_PI / 180.0;
  const double focal = (c.width / 2.0) / std::tan(fov / 2.0);
  for (int s = 0; s < c.scans; ++s) {
    const int orbit = s * 2 / c.scans;  // two orbits
    const double angle = 2.0 * M_PI * (2.0 * s / c.scans) + orbit * M_PI / c.scans;
    const Vec origin{target.x + c.orbit_radius * std::cos(angle), target.y + c.orbit_radius * std::sin(angle),
                     c.sensor_height + 0.3 * orbit};
    const Vec forward = (target - origin).unit();
    const Vec right = forward.cross(Vec{0, 0, 1}).unit();
    const Vec up = right.cross(forward);
    Scan scan;
    scan.origin = octomap::point3d(float(origin.x), float(origin.y), float(origin.z));
    scan.view = cameraView(c, focal, right, up, forward);
    for (int v = 0; v < c.height; ++v)
      for (int u = 0; u < c.width; ++u) {
        const Vec dir = (forward * focal + right * (u + 0.5 - c.width / 2.0) - up * (v + 0.5 - c.height / 2.0)).unit();
        double t = dir.z < 0 ? -origin.z / dir.z : std::numeric_limits<double>::infinity();  // ground z = 0
        for (const auto& b : d.truth.boxes) t = std::min(t, rayBox(origin, dir, b));
        // Draw the random numbers for every ray, hit or not, so one ray's outcome never shifts another's.
        const double noise = rng.gaussian() * c.noise_sigma;
        const bool outlier = rng.uniform() < c.outlier_fraction;
        const double outlier_u = rng.uniform();
        if (!(t <= c.max_return)) continue;
        const double range = outlier ? 0.3 + outlier_u * (t - 0.3) : t + noise;
        if (!(range > 0.05)) continue;
        const Vec p = origin + dir * range;
        scan.points.emplace_back(float(p.x), float(p.y), float(p.z));
      }
    d.scans.push_back(std::move(scan));
  }
  d.source = {{"generator", "occsweep builtin scene"},
              {"seed", c.seed},
              {"scans", c.scans},
              {"width", c.width},
              {"height", c.height},
              {"fov_horizontal_deg", c.fov_horizontal_deg},
              {"orbit_radius", c.orbit_radius},
              {"sensor_height", c.sensor_height},
              {"noise_sigma", c.noise_sigma},
              {"outlier_fraction", c.outlier_fraction},
              {"max_return", c.max_return},
              {"box_edge", c.box_edge}};
  // The scene's geometry (the boxes' edge; ground and region are fixed), not the trajectory (scans, camera, orbit) or
  // the noise draws: every recording of the one room is one unit of compare's tests (docs/statistics.md, "Verdicts").
  const nlohmann::json scene = {"occsweep builtin scene", c.box_edge};
  d.source["provenance"] = {{"scene", contentHash(scene.dump())}};
  return d;
}

}  // namespace occsweep
