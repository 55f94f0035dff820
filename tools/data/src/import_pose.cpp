#include "occsweep/data/import_pose.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
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

std::vector<RigidPose> readPoses(const fs::path& file, PoseFormat format) {
  return decodePoses(readFileBytes(file, std::uint64_t(1) << 30), file, format);
}

namespace {

std::string seconds(double s) {
  char text[32];
  std::snprintf(text, sizeof text, "%.6g s", s);
  return text;
}

/// The timestamps of a TUM pose file (its first column), in file order; decodePoses has checked the lines.
std::vector<double> tumTimestamps(const fs::path& file) {
  const std::string text = readFileBytes(file, std::uint64_t(1) << 30);
  TextLines lines(text, file);
  std::vector<std::string_view> tok;
  std::vector<double> stamps;
  while (lines.nextData(tok)) stamps.push_back(lines.number(tok[0], 0, "timestamp"));
  return stamps;
}

/// A frame's timestamp when its file name (without extension) is one, as TUM names its images.
std::optional<double> frameTimestamp(const fs::path& frame) {
  double t = 0;
  return parseFiniteDouble(frame.stem().string(), t) ? std::optional<double>(t) : std::nullopt;
}

/// Each frame's pose: the TUM pose nearest its timestamp, within kTumMaxTimeDifference.
std::vector<RigidPose> associateByTimestamp(const fs::path& file, const std::vector<RigidPose>& poses,
                                            const std::vector<fs::path>& frames) {
  const std::vector<double> stamps = tumTimestamps(file);
  std::vector<RigidPose> out;
  for (const fs::path& frame : frames) {
    const double t = *frameTimestamp(frame);
    std::size_t best = 0;
    for (std::size_t i = 1; i < stamps.size(); ++i)
      if (std::abs(stamps[i] - t) < std::abs(stamps[best] - t)) best = i;
    const double gap = std::abs(stamps[best] - t);
    if (gap > kTumMaxTimeDifference)
      throw DataError(file, "", "no pose within " + seconds(kTumMaxTimeDifference) + " of " +
                                    frame.filename().string() + " (the nearest is " + seconds(gap) +
                                    " away): is it the trajectory of these images?");
    out.push_back(poses[best]);
  }
  return out;
}

}  // namespace

nlohmann::json poseFileNames(const std::vector<fs::path>& pose_files) {
  if (pose_files.size() == 1) return pose_files[0].filename().string();
  nlohmann::json names = nlohmann::json::array();
  for (const fs::path& f : pose_files) names.push_back(f.filename().string());
  return names;
}

namespace {

/// Frame i's pose is pose start + i step of `poses` (PoseSelection), or a DataError naming the pose past the end.
std::vector<RigidPose> selectedPoses(const std::vector<RigidPose>& poses, const PoseSelection& s, const fs::path& file,
                                     std::size_t frames, const std::string& kind) {
  if (frames == 0) return {};
  // No overflow: start <= 10^9 and step <= 10^6 (their options), frames bounded by the command line's files.
  const std::size_t last = s.start + (frames - 1) * s.step;
  if (last >= poses.size())
    throw DataError(file, "", "holds " + std::to_string(poses.size()) + " poses: --pose-start " +
                                  std::to_string(s.start) + " --pose-step " + std::to_string(s.step) + " takes pose " +
                                  std::to_string(last) + " (counting from 0) for the last of " +
                                  std::to_string(frames) + " " + kind + "s");
  std::vector<RigidPose> out;
  for (std::size_t i = 0; i < frames; ++i) out.push_back(poses[s.start + i * s.step]);
  return out;
}

}  // namespace

std::vector<RigidPose> framePoses(const std::vector<fs::path>& pose_files, PoseFormat format,
                                  const std::vector<fs::path>& frames, const std::string& kind,
                                  const PoseSelection& selection) {
  if (selection.chosen && pose_files.size() > 1)
    throw std::invalid_argument("--pose-start and --pose-step take poses out of one file of a whole sequence, not "
                                "out of " + std::to_string(pose_files.size()) + " pose files");
  if (pose_files.size() > 1) {  // one file per frame
    if (pose_files.size() != frames.size())
      throw std::invalid_argument(std::to_string(pose_files.size()) + " pose files for " + std::to_string(frames.size()) +
                                  " " + kind + "s: give one pose file for all, or one per " + kind + ", in order");
    std::vector<RigidPose> out;
    for (const fs::path& file : pose_files) {
      const std::vector<RigidPose> poses = readPoses(file, format);
      if (poses.size() != 1)
        throw DataError(file, "", "holds " + std::to_string(poses.size()) + " poses: with one pose file per " + kind +
                                      ", each holds its " + kind + "'s pose alone");
      out.push_back(poses.front());
    }
    return out;
  }
  const fs::path& file = pose_files.at(0);
  std::vector<RigidPose> poses = readPoses(file, format);
  // Asked for by position: taken so, even from a TUM trajectory whose frames are named by numbers.
  if (selection.chosen) return selectedPoses(poses, selection, file, frames.size(), kind);
  const bool timestamped = std::all_of(frames.begin(), frames.end(), [](const fs::path& f) {
    return frameTimestamp(f).has_value();
  });
  // By timestamp whenever both sides have them, even at equal counts: a trajectory of as many poses as images need not
  // pair them in order.
  if (format == PoseFormat::Tum && timestamped) return associateByTimestamp(file, poses, frames);
  if (poses.size() == frames.size()) return poses;
  const std::string counts = "holds " + std::to_string(poses.size()) + " poses for " + std::to_string(frames.size()) +
                             " " + kind + "s: one pose per " + kind + " needed";
  if (poses.size() < frames.size()) throw DataError(file, "", counts);
  throw DataError(file, "", counts + ". A whole sequence's poses? Give --pose-start K --pose-step N: " + kind + " i takes "
                                "pose K + i N, counting from 0 (--pose-start 0 for the sequence's first " + kind +
                                "s, --pose-step 10 for every tenth); a TUM trajectory (--pose-format tum) is matched "
                                "by timestamp when each " + kind + " is named by its own, as TUM names them");
}

}  // namespace occsweep
