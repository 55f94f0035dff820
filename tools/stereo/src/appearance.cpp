#include "occsweep/stereo/appearance.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "occsweep/core/splitmix64.hpp"

namespace occsweep::stereo {
namespace {

std::uint64_t hash3(std::int64_t a, std::int64_t b, std::uint64_t seed) {
  SplitMix64 m(seed ^ (std::uint64_t(a) * 0x9E3779B97F4A7C15ull) ^ (std::uint64_t(b) * 0xC2B2AE3D27D4EB4Full));
  return m.next();
}
double unitHash(std::int64_t a, std::int64_t b, std::uint64_t seed) { return double(hash3(a, b, seed) >> 11) * 0x1.0p-53; }

double smooth(double t) { return t * t * (3 - 2 * t); }
double clamp01(double v) { return std::clamp(v, 0.0, 1.0); }

/// Weight of detail with wavelength `scale` seen with `footprint`: 1 at 4 samples per wavelength, 0 at Nyquist.
double fade(double scale, double footprint) { return clamp01(0.5 * scale / footprint - 1.0); }

/// Fraction of a sample of width `footprint` covered by a line of half-width `half` at distance `dist`.
double lineCoverage(double dist, double half, double footprint) { return clamp01((half - dist) / footprint + 0.5); }

// Sun high on one side, weak fill from the other: every box face gets a different brightness.
const Eigen::Vector3d kSun = Eigen::Vector3d(0.45, 0.25, 0.86).normalized();
const Eigen::Vector3d kFill = Eigen::Vector3d(-0.3, -0.75, 0.6).normalized();

double shade(const Eigen::Vector3d& n) {
  return 0.22 + 0.62 * std::max(0.0, n.dot(kSun)) + 0.16 * std::max(0.0, n.dot(kFill));
}

/// Face coordinates: the two world axes in the face's plane.
void faceCoords(const Eigen::Vector3d& p, const Eigen::Vector3d& n, double& u, double& v, int& axis) {
  axis = std::abs(n.x()) > 0.5 ? 0 : (std::abs(n.y()) > 0.5 ? 1 : 2);
  u = p[(axis + 1) % 3];
  v = p[(axis + 2) % 3];
}

double cardboard(const Eigen::Vector3d& p, const Eigen::Vector3d& n, double fp, std::uint64_t seed) {
  double u, v;
  int axis;
  faceCoords(p, n, u, v, axis);
  const std::uint64_t s = seed + 101 + axis;
  // Slight, low-contrast fibre and stain variation: real cardboard, and not enough to match on under noise.
  return 0.42 * (1.0 + 0.03 * fade(0.15, fp) * valueNoise(u / 0.15, v / 0.15, s) +
                 0.02 * fade(0.03, fp) * valueNoise(u / 0.03, v / 0.03, s + 7));
}

double voronoiPaper(const Eigen::Vector3d& p, const Eigen::Vector3d& n, double fp, std::uint64_t seed) {
  double u, v;
  int axis;
  faceCoords(p, n, u, v, axis);
  constexpr double kCell = 0.09, kHalfLine = 0.006;
  const double dist = voronoiBorderDistance(u / kCell, v / kCell, seed + 201 + axis) * kCell;
  const double line = lineCoverage(dist, kHalfLine, fp);
  return 0.8 * (1 - line) + 0.08 * line;
}

double asphalt(const Eigen::Vector3d& p, double fp, std::uint64_t seed) {
  double a = 0.22;
  const double scales[3] = {0.4, 0.08, 0.02}, amps[3] = {0.04, 0.05, 0.06};
  for (int i = 0; i < 3; ++i) a += amps[i] * fade(scales[i], fp) * valueNoise(p.x() / scales[i], p.y() / scales[i], seed + 301 + i);
  return a;
}

/// Parking: two rows of stalls 4-9 m from the targets on both sides, lines 0.1 m wide every 2.5 m.
double parkingMarking(const Eigen::Vector3d& p, const Scene& s, double fp) {
  const double x = p.x() - s.centre.x(), y = std::abs(p.y() - s.centre.y());
  if (std::abs(x) > 12.0 || y > 9.2) return 0.0;
  double cover = lineCoverage(std::abs(y - 9.0), 0.05, fp);
  if (y > 4.0 && y < 9.0) cover = std::max(cover, lineCoverage(std::abs(x - 2.5 * std::round(x / 2.5)), 0.05, fp));
  return cover;
}

double brickFacade(const Eigen::Vector3d& p, const Hit& hit, double fp, std::uint64_t seed) {
  const double s = hit.index / 2 == 0 ? p.y() : p.x(), z = p.z();
  // Windows: 1.0 x 1.3 m every 2 m, one row a floor of 2.6 m, with a light frame.
  const double ws = s - 2.0 * std::floor(s / 2.0), wz = z - 2.6 * std::floor(z / 2.6);
  const double dx = std::abs(ws - 1.0), dz = std::abs(wz - 1.55);
  if (dx < 0.5 && dz < 0.65) {
    const double frame = std::max(lineCoverage(0.5 - dx, 0.04, fp), lineCoverage(0.65 - dz, 0.04, fp));
    const double cross = std::max(lineCoverage(dx, 0.02, fp), lineCoverage(dz, 0.02, fp));
    const double f = std::max(frame, cross);
    return 0.7 * f + 0.06 * (1 - f);
  }
  constexpr double kW = 0.24, kH = 0.075, kMortar = 0.006;
  const double row = std::floor(z / kH);
  const double shifted = s / kW + 0.5 * std::fmod(std::abs(row), 2.0);
  const double col = std::floor(shifted);
  const double bu = (shifted - col) * kW, bv = z - row * kH;
  const double edge = std::min({bu, kW - bu, bv, kH - bv});
  const double mortar = lineCoverage(edge, kMortar, fp);
  const double brick = 0.3 + 0.15 * fade(kW, fp) * unitHash(std::int64_t(col), std::int64_t(row), seed + 401 + hit.index);
  return 0.55 * mortar + brick * (1 - mortar);
}

/// Far clutter: buildings with a grid of windows (2 x 3 m, 1.0 x 1.4 m panes), tree rows of mottled foliage.
double farClutter(const Eigen::Vector3d& p, const Scene& scene, const Hit& hit, double fp) {
  const ClutterSector sector = clutterSector(scene, hit.index, p);
  const double along = kClutterRings[hit.index] * std::atan2(p.y() - scene.centre.y(), p.x() - scene.centre.x());
  const std::uint64_t seed = scene.seed + 601 + std::uint64_t(hit.index);
  if (sector.kind == ClutterSector::Trees)
    return 0.1 + 0.05 * fade(0.6, fp) * valueNoise(along / 0.6, p.z() / 0.6, seed) +
           0.04 * fade(2.5, fp) * valueNoise(along / 2.5, p.z() / 2.5, seed + 1);
  const double ws = along - 2.0 * std::floor(along / 2.0), wz = p.z() - 3.0 * std::floor(p.z() / 3.0);
  const double pane = lineCoverage(std::abs(ws - 1.0), 0.5, fp) * lineCoverage(std::abs(wz - 1.5), 0.7, fp);
  const double wall = 0.22 + 0.3 * sector.shade + 0.04 * fade(1.0, fp) * valueNoise(along, p.z(), seed + 2);
  return 0.08 * pane + wall * (1 - pane);
}

/// Sky: brighter at the horizon; with far clutter, soft clouds (directional only: they are at infinity).
double sky(const Scene& scene, const Eigen::Vector3d& d) {
  const double base = 0.62 + 0.2 * std::clamp(1.0 - d.z(), 0.0, 1.0);
  if (!scene.config.far_clutter || d.z() <= 0) return base;
  const double u = d.x() / (d.z() + 0.15), v = d.y() / (d.z() + 0.15);
  return base + 0.05 * valueNoise(3 * u, 3 * v, scene.seed + 701) + 0.025 * valueNoise(7 * u, 7 * v, scene.seed + 702);
}

}  // namespace

double valueNoise(double x, double y, std::uint64_t seed) {
  const double fx = std::floor(x), fy = std::floor(y);
  const auto ix = std::int64_t(fx), iy = std::int64_t(fy);
  const double tx = smooth(x - fx), ty = smooth(y - fy);
  auto at = [&](std::int64_t a, std::int64_t b) { return 2.0 * unitHash(a, b, seed) - 1.0; };
  const double top = at(ix, iy) + tx * (at(ix + 1, iy) - at(ix, iy));
  const double bottom = at(ix, iy + 1) + tx * (at(ix + 1, iy + 1) - at(ix, iy + 1));
  return top + ty * (bottom - top);
}

double voronoiBorderDistance(double x, double y, std::uint64_t seed) {
  const auto cx = std::int64_t(std::floor(x)), cy = std::int64_t(std::floor(y));
  double fx[25], fy[25], best = std::numeric_limits<double>::infinity();
  int nearest = 0, n = 0;
  for (std::int64_t j = cy - 2; j <= cy + 2; ++j)
    for (std::int64_t i = cx - 2; i <= cx + 2; ++i, ++n) {
      const std::uint64_t h = hash3(i, j, seed);
      fx[n] = double(i) + 0.1 + 0.8 * double(h & 0xFFFFFFFFull) * 0x1.0p-32;
      fy[n] = double(j) + 0.1 + 0.8 * double(h >> 32) * 0x1.0p-32;
      const double d2 = (fx[n] - x) * (fx[n] - x) + (fy[n] - y) * (fy[n] - y);
      if (d2 < best) best = d2, nearest = n;
    }
  // Distance to the bisector between the nearest feature and each other one; the border is the nearest bisector.
  double border = std::numeric_limits<double>::infinity();
  for (int k = 0; k < n; ++k) {
    if (k == nearest) continue;
    const double ex = fx[k] - fx[nearest], ey = fy[k] - fy[nearest], len = std::hypot(ex, ey);
    const double mx = 0.5 * (fx[k] + fx[nearest]), my = 0.5 * (fy[k] + fy[nearest]);
    border = std::min(border, ((mx - x) * ex + (my - y) * ey) / len);
  }
  return border;
}

double radiance(const Scene& scene, const Hit& hit, const Eigen::Vector3d& o, const Eigen::Vector3d& d, double fp) {
  if (hit.surface == Surface::Sky) return sky(scene, d);
  const Eigen::Vector3d p = o + hit.t * d;
  double albedo = 0;
  switch (hit.surface) {
    case Surface::Box:
      albedo = scene.name.texture == Texture::Plain ? cardboard(p, hit.normal, fp, scene.seed)
                                                    : voronoiPaper(p, hit.normal, fp, scene.seed);
      break;
    case Surface::Ground: {
      albedo = asphalt(p, fp, scene.seed);
      if (scene.name.environment == Environment::Parking) {
        const double m = parkingMarking(p, scene, fp);
        albedo = 0.75 * m + albedo * (1 - m);
      }
      break;
    }
    case Surface::Facade: albedo = brickFacade(p, hit, fp, scene.seed); break;
    case Surface::Clutter: albedo = farClutter(p, scene, hit, fp); break;
    case Surface::Sky: break;
  }
  return albedo * shade(hit.normal);
}

}  // namespace occsweep::stereo
