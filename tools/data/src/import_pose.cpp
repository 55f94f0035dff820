#include "occsweep/data/import_pose.hpp"

#include <cmath>
#include <string>

#include "occsweep/data/import_bytes.hpp"

namespace occsweep {
namespace fs = std::filesystem;

namespace {

[[nodiscard]] bool isRotation(const std::array<double, 9>& r) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      double dot = 0;
      for (int k = 0; k < 3; ++k) dot += r[std::size_t(k * 3 + i)] * r[std::size_t(k * 3 + j)];
      if (std::abs(dot - (i == j ? 1.0 : 0.0)) > kRotationTolerance) return false;
    }
  const double det = r[0] * (r[4] * r[8] - r[5] * r[7]) - r[1] * (r[3] * r[8] - r[5] * r[6]) +
                     r[2] * (r[3] * r[7] - r[4] * r[6]);
  return std::abs(det - 1.0) <= kRotationTolerance;  // det -1 is a reflection: a left-handed frame, refused
}

RigidPose quaternionLine(const TextLines& lines, const std::vector<std::string_view>& tok) {
  if (tok.size() != 7)
    lines.fail("has " + std::to_string(tok.size()) + " values, expected 7: tx ty tz qx qy qz qw");
  static const char* names[] = {"tx", "ty", "tz", "qx", "qy", "qz", "qw"};
  double v[7];
  for (std::size_t i = 0; i < 7; ++i) v[i] = lines.number(tok[i], i, names[i]);
  bool ok = false;
  const RigidPose pose = poseFromQuaternion(v[0], v[1], v[2], v[6], v[3], v[4], v[5], ok);
  if (!ok) {
    const double norm = std::sqrt(v[3] * v[3] + v[4] * v[4] + v[5] * v[5] + v[6] * v[6]);
    lines.fail("quaternion norm is " + std::to_string(norm) + ", more than " +
               std::to_string(kQuaternionNormTolerance) + " from 1: not a rotation (wrong column order?)");
  }
  return pose;
}

}  // namespace

octomap::point3d RigidPose::apply(double x, double y, double z) const {
  const auto& r = rotation;
  return octomap::point3d(float(r[0] * x + r[1] * y + r[2] * z + translation[0]),
                          float(r[3] * x + r[4] * y + r[5] * z + translation[1]),
                          float(r[6] * x + r[7] * y + r[8] * z + translation[2]));
}

octomap::point3d RigidPose::origin() const {
  return octomap::point3d(float(translation[0]), float(translation[1]), float(translation[2]));
}

RigidPose poseFromQuaternion(double tx, double ty, double tz, double w, double x, double y, double z, bool& ok) {
  const double norm = std::sqrt(w * w + x * x + y * y + z * z);
  ok = std::isfinite(norm) && std::abs(norm - 1.0) <= kQuaternionNormTolerance;
  RigidPose p;
  p.translation = {tx, ty, tz};
  if (!ok) return p;
  w /= norm, x /= norm, y /= norm, z /= norm;
  p.rotation = {1 - 2 * (y * y + z * z), 2 * (x * y - w * z),     2 * (x * z + w * y),
                2 * (x * y + w * z),     1 - 2 * (x * x + z * z), 2 * (y * z - w * x),
                2 * (x * z - w * y),     2 * (y * z + w * x),     1 - 2 * (x * x + y * y)};
  return p;
}

std::vector<RigidPose> decodePoses(std::string_view text, const fs::path& file, PoseFormat format) {
  TextLines lines(text, file);
  std::vector<std::string_view> tok;
  std::vector<RigidPose> poses;
  if (format == PoseFormat::Quaternion) {
    while (lines.nextData(tok)) poses.push_back(quaternionLine(lines, tok));
  } else {
    std::vector<double> values;  // numbers of the pose being read
    std::size_t first_line = 0;
    while (lines.nextData(tok)) {
      if (values.empty()) first_line = lines.line();
      for (std::size_t i = 0; i < tok.size(); ++i) {
        values.push_back(lines.number(tok[i], i, "matrix entry"));
        if (values.size() < 16) continue;
        if (i + 1 != tok.size()) lines.fail("a 4x4 pose ends inside this line: 16 numbers a pose expected");
        if (values[12] != 0 || values[13] != 0 || values[14] != 0 || values[15] != 1)
          lines.fail("pose " + std::to_string(poses.size() + 1) + " (from line " + std::to_string(first_line) +
                     "): last row must be 0 0 0 1");
        RigidPose p;
        p.rotation = {values[0], values[1], values[2], values[4], values[5], values[6], values[8], values[9], values[10]};
        p.translation = {values[3], values[7], values[11]};
        if (!isRotation(p.rotation))
          lines.fail("pose " + std::to_string(poses.size() + 1) + " (from line " + std::to_string(first_line) +
                     "): upper-left 3x3 is not a rotation (orthonormal, det +1, tolerance 1e-3)");
        poses.push_back(p);
        values.clear();
      }
    }
    if (!values.empty())
      throw DataError(file, "end of file", "the last pose has " + std::to_string(values.size()) +
                                               " numbers, expected 16: truncated file");
  }
  if (poses.empty()) throw DataError(file, "", "holds no pose");
  return poses;
}

std::vector<RigidPose> readPoses(const fs::path& file, PoseFormat format) {
  return decodePoses(readFileBytes(file, std::uint64_t(1) << 30), file, format);
}

}  // namespace occsweep
