#include "occsweep/data/import_pose.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include "occsweep/io/bounded_read.hpp"
#include "occsweep/data/byte_reader.hpp"

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

/// What a line of `values` numbers looks like, when it is another format's: the flag that reads it.
std::string otherFormatHint(std::size_t values, bool timestamp) {
  if (values == 4) return " (four numbers a line: a row of a 4x4 matrix? --pose-format matrix)";
  if (values == 16) return " (16 numbers: a 4x4 matrix on one line? --pose-format matrix)";
  if (values == 12) return " (12 numbers: KITTI's 3x4 [R|t]? --pose-format kitti)";
  if (!timestamp && values == 8) return " (a TUM file starts with a timestamp: --pose-format tum)";
  if (timestamp && values == 7) return " (no timestamp: --pose-format quaternion)";
  return "";
}

/// tx ty tz qx qy qz qw, after TUM's timestamp when `timestamp`.
RigidPose quaternionLine(const TextLines& lines, const std::vector<std::string_view>& tok, bool timestamp) {
  static const char* names[] = {"timestamp", "tx", "ty", "tz", "qx", "qy", "qz", "qw"};
  const std::size_t skip = timestamp ? 1 : 0, expected = 7 + skip;
  if (tok.size() != expected)
    lines.fail("has " + std::to_string(tok.size()) + " values, expected " + std::to_string(expected) + ": " +
               (timestamp ? "timestamp " : "") + "tx ty tz qx qy qz qw" + otherFormatHint(tok.size(), timestamp));
  double v[8];
  for (std::size_t i = 0; i < expected; ++i) v[i] = lines.number(tok[i], i, names[i + 1 - skip]);
  const double* q = v + skip;
  bool ok = false;
  const RigidPose pose = poseFromQuaternion(q[0], q[1], q[2], q[6], q[3], q[4], q[5], ok);
  if (!ok) {
    const double norm = std::sqrt(q[3] * q[3] + q[4] * q[4] + q[5] * q[5] + q[6] * q[6]);
    lines.fail("quaternion norm is " + std::to_string(norm) + ", more than " +
               std::to_string(kQuaternionNormTolerance) + " from 1: not a rotation (wrong column order?)");
  }
  return pose;
}

/// The rows [R|t] of a rigid transform (12 numbers, row-major), refused unless R is a rotation.
RigidPose rigidFromRows(const TextLines& lines, const std::vector<double>& v, std::size_t pose_number,
                        std::size_t first_line) {
  RigidPose p;
  p.rotation = {v[0], v[1], v[2], v[4], v[5], v[6], v[8], v[9], v[10]};
  p.translation = {v[3], v[7], v[11]};
  if (!isRotation(p.rotation))
    lines.fail("pose " + std::to_string(pose_number) + " (from line " + std::to_string(first_line) +
               "): upper-left 3x3 is not a rotation (orthonormal, det +1, tolerance 1e-3)");
  return p;
}

/// KITTI odometry: r11 r12 r13 tx r21 r22 r23 ty r31 r32 r33 tz, one pose a line.
RigidPose kittiLine(const TextLines& lines, const std::vector<std::string_view>& tok, std::size_t pose_number) {
  if (tok.size() != 12)
    lines.fail("has " + std::to_string(tok.size()) + " values, expected 12: the 3x4 [R|t] row-major (KITTI)");
  std::vector<double> v;
  for (std::size_t i = 0; i < 12; ++i) v.push_back(lines.number(tok[i], i, "matrix entry"));
  return rigidFromRows(lines, v, pose_number, lines.line());
}

std::vector<RigidPose> matrixPoses(TextLines& lines, const std::filesystem::path& file) {
  std::vector<std::string_view> tok;
  std::vector<RigidPose> poses;
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
      poses.push_back(rigidFromRows(lines, values, poses.size() + 1, first_line));
      values.clear();
    }
  }
  if (!values.empty())
    throw DataError(file, "end of file", "the last pose has " + std::to_string(values.size()) +
                                             " numbers, expected 16: truncated file");
  return poses;
}

}  // namespace

std::array<double, 3> RigidPose::applyExact(double x, double y, double z) const {
  const auto& r = rotation;
  return {r[0] * x + r[1] * y + r[2] * z + translation[0], r[3] * x + r[4] * y + r[5] * z + translation[1],
          r[6] * x + r[7] * y + r[8] * z + translation[2]};
}

octomap::point3d RigidPose::apply(double x, double y, double z) const {
  const auto p = applyExact(x, y, z);
  return octomap::point3d(float(p[0]), float(p[1]), float(p[2]));
}

octomap::point3d CloudPlacement::place(double x, double y, double z) const {
  const auto p = pose.applyExact(x, y, z);
  return octomap::point3d(float(p[0] + shift[0]), float(p[1] + shift[1]), float(p[2] + shift[2]));
}

octomap::point3d RigidPose::origin() const {
  return octomap::point3d(float(translation[0]), float(translation[1]), float(translation[2]));
}

RigidPose RigidPose::inverse() const {
  const auto& r = rotation;
  RigidPose p;
  p.rotation = {r[0], r[3], r[6], r[1], r[4], r[7], r[2], r[5], r[8]};
  p.translation = p.applyExact(-translation[0], -translation[1], -translation[2]);  // -R^T t
  return p;
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
  if (format == PoseFormat::Matrix) poses = matrixPoses(lines, file);
  while (format == PoseFormat::Quaternion && lines.nextData(tok)) poses.push_back(quaternionLine(lines, tok, false));
  while (format == PoseFormat::Tum && lines.nextData(tok)) poses.push_back(quaternionLine(lines, tok, true));
  while (format == PoseFormat::Kitti && lines.nextData(tok)) poses.push_back(kittiLine(lines, tok, poses.size() + 1));
  if (poses.empty()) throw DataError(file, "", "holds no pose");
  return poses;
}

const char* poseFormatName(PoseFormat format) {
  switch (format) {
    case PoseFormat::Matrix: return "matrix";
    case PoseFormat::Tum: return "tum";
    case PoseFormat::Kitti: return "kitti";
    case PoseFormat::Quaternion: break;
  }
  return "quaternion";
}

PoseFormat poseFormatNamed(const std::string& name) {
  for (auto f : {PoseFormat::Quaternion, PoseFormat::Matrix, PoseFormat::Tum, PoseFormat::Kitti})
    if (name == poseFormatName(f)) return f;
  throw std::invalid_argument("pose format '" + name + "': expected quaternion, matrix, tum or kitti");
}

const char* poseConventionName(PoseConvention convention) {
  return convention == PoseConvention::WorldToCamera ? "world-to-camera" : "camera-to-world";
}

PoseConvention poseConventionNamed(const std::string& name) {
  for (auto c : {PoseConvention::CameraToWorld, PoseConvention::WorldToCamera})
    if (name == poseConventionName(c)) return c;
  throw std::invalid_argument("pose convention '" + name + "': expected camera-to-world or world-to-camera");
}

std::vector<RigidPose> readPoses(const fs::path& file, PoseFormat format) {
  return decodePoses(readFileBytes(file, std::uint64_t(1) << 30), file, format);
}

}  // namespace occsweep
