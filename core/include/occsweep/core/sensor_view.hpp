// What a scan's sensor could see: a pinhole camera's image, a range sensor's cone, or every direction, placed at the
// scan's origin (docs/dataset-format.md, "Sensor views"). Observable truth counts a truth voxel only inside some
// scan's view (docs/results-format.md, "Truth"): a depth camera sees a pyramid, not the whole sphere around it.
#pragma once

#include <array>
#include <cmath>
#include <optional>
#include <string>
#include <variant>

#include <octomap/octomap_types.h>

namespace occsweep {

/// A pinhole camera, camera frame x right, y down, z forward (as `import depth` back-projects). A point at p_cam
/// is in the image when z > 0 and its pixel (fx x / z + cx, fy y / z + cy) lies on the image: pixel centres at
/// integer coordinates, so u in [-0.5, width - 0.5] and v in [-0.5, height - 0.5].
struct PinholeView {
  double fx = 0, fy = 0, cx = 0, cy = 0;                  ///< pixels; fx, fy > 0
  int width = 0, height = 0;                               ///< pixels, >= 1
  std::array<double, 9> rotation{1, 0, 0, 0, 1, 0, 0, 0, 1};  ///< camera -> world, row-major: p_world = R p_cam + origin
};

/// A range sensor's cone: the directions within half_angle_deg of `axis` (world frame).
struct ConeView {
  std::array<double, 3> axis{0, 0, 1};  ///< non-zero; need not be a unit vector
  double half_angle_deg = 90;           ///< in (0, 180]; 180 is every direction
};

/// Every direction: a spinning lidar, or a sensor whose view nobody recorded.
struct SphereView {};

using SensorView = std::variant<PinholeView, ConeView, SphereView>;

/// How far R^T R may be from I (max abs entry) and det R from 1: the tolerance pose files get (docs/import.md).
inline constexpr double kViewRotationTolerance = 1e-3;

/// A rule a view breaks: the field (as in the manifest: "fx", "rotation", "half_angle_deg") and why.
struct BrokenViewRule {
  std::string field, rule;
};

namespace detail {

inline std::optional<BrokenViewRule> brokenPinholeRule(const PinholeView& v) {
  for (const auto& [name, value] : {std::pair{"fx", v.fx}, {"fy", v.fy}})
    if (!(std::isfinite(value) && value > 0)) return BrokenViewRule{name, "must be a finite number > 0"};
  for (const auto& [name, value] : {std::pair{"cx", v.cx}, {"cy", v.cy}})
    if (!std::isfinite(value)) return BrokenViewRule{name, "must be finite"};
  if (v.width < 1) return BrokenViewRule{"width", "must be an integer >= 1"};
  if (v.height < 1) return BrokenViewRule{"height", "must be an integer >= 1"};
  const auto& r = v.rotation;
  for (double e : r)
    if (!std::isfinite(e)) return BrokenViewRule{"rotation", "must be 9 finite numbers"};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      const double dot = r[i] * r[j] + r[3 + i] * r[3 + j] + r[6 + i] * r[6 + j];  // (R^T R)_ij
      if (std::abs(dot - (i == j)) > kViewRotationTolerance)
        return BrokenViewRule{"rotation", "must be a rotation (R^T R = I within 1e-3)"};
    }
  const double det = r[0] * (r[4] * r[8] - r[5] * r[7]) - r[1] * (r[3] * r[8] - r[5] * r[6]) +
                     r[2] * (r[3] * r[7] - r[4] * r[6]);
  if (std::abs(det - 1) > kViewRotationTolerance)
    return BrokenViewRule{"rotation", "must be a rotation (det R = 1 within 1e-3; a reflection is not)"};
  return std::nullopt;
}

inline std::optional<BrokenViewRule> brokenConeRule(const ConeView& v) {
  const auto& a = v.axis;
  if (!(std::isfinite(a[0]) && std::isfinite(a[1]) && std::isfinite(a[2])))
    return BrokenViewRule{"axis", "must be 3 finite numbers"};
  if (a[0] == 0 && a[1] == 0 && a[2] == 0) return BrokenViewRule{"axis", "must not be the zero vector"};
  // The cone test squares the axis: a length whose square underflows or overflows would see nothing.
  const double squared = a[0] * a[0] + a[1] * a[1] + a[2] * a[2];
  if (!(squared >= 1e-300 && squared <= 1e300))
    return BrokenViewRule{"axis", "must have a length from 1e-150 to 1e150"};
  if (!(v.half_angle_deg > 0 && v.half_angle_deg <= 180))
    return BrokenViewRule{"half_angle_deg", "must be in (0, 180] degrees"};
  return std::nullopt;
}

}  // namespace detail

/// The first rule `view` breaks, or nothing: focal lengths > 0, an image of at least one pixel, a rotation; a
/// non-zero axis and a half-angle in (0, 180].
[[nodiscard]] inline std::optional<BrokenViewRule> brokenViewRule(const SensorView& view) {
  if (const auto* p = std::get_if<PinholeView>(&view)) return detail::brokenPinholeRule(*p);
  if (const auto* c = std::get_if<ConeView>(&view)) return detail::brokenConeRule(*c);
  return std::nullopt;
}

/// True when `p` lies inside `view` of a sensor at `origin` (the view's rules hold). In double: the image's
/// border and the cone's surface count as inside. The origin itself has no direction: inside a sphere only.
[[nodiscard]] inline bool inView(const SensorView& view, const octomap::point3d& origin, const octomap::point3d& p) {
  const double d[3] = {double(p.x()) - origin.x(), double(p.y()) - origin.y(), double(p.z()) - origin.z()};
  if (const auto* c = std::get_if<PinholeView>(&view)) {
    const auto& r = c->rotation;  // p_cam = R^T d
    const double x = r[0] * d[0] + r[3] * d[1] + r[6] * d[2], y = r[1] * d[0] + r[4] * d[1] + r[7] * d[2],
                 z = r[2] * d[0] + r[5] * d[1] + r[8] * d[2];
    if (!(z > 0)) return false;
    const double u = c->fx * x / z + c->cx, v = c->fy * y / z + c->cy;
    return u >= -0.5 && u <= c->width - 0.5 && v >= -0.5 && v <= c->height - 0.5;
  }
  if (const auto* c = std::get_if<ConeView>(&view)) {
    if (c->half_angle_deg >= 180) return true;
    const auto& a = c->axis;
    const double along = a[0] * d[0] + a[1] * d[1] + a[2] * d[2];
    const double norms = std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]) * std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    return norms > 0 && along >= norms * std::cos(c->half_angle_deg * M_PI / 180.0);
  }
  return true;
}

}  // namespace occsweep
