// Which pose of the pose files each frame takes (docs/import.md, "Poses"): in order, one file per frame, by
// --pose-start/--pose-step, by the frame's number (--pose-by-frame-number) or by TUM timestamps.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <tuple>

#include "occsweep/data/import_pose.hpp"
#include "occsweep/data/byte_reader.hpp"
#include "occsweep/io/bounded_read.hpp"

namespace occsweep {
namespace fs = std::filesystem;

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

/// The nearest of `stamps` to `t`, for the message of a frame without a pose.
double nearestGap(const std::vector<double>& stamps, double t) {
  double gap = INFINITY;
  for (double s : stamps) gap = std::min(gap, std::abs(s - t));
  return gap;
}

/// Frames paired with TUM poses as the benchmark's associate.py pairs them: every (frame, pose) pair closer in time
/// than kTumMaxTimeDifference, the closest first, each frame and each pose taken once.
std::vector<RigidPose> associateByTimestamp(const fs::path& file, const std::vector<RigidPose>& poses,
                                            const std::vector<fs::path>& frames) {
  const std::vector<double> stamps = tumTimestamps(file);
  std::vector<std::size_t> by_time(stamps.size());
  for (std::size_t i = 0; i < by_time.size(); ++i) by_time[i] = i;
  std::sort(by_time.begin(), by_time.end(), [&](std::size_t a, std::size_t b) { return stamps[a] < stamps[b]; });
  std::vector<std::tuple<double, std::size_t, std::size_t>> pairs;  // gap, frame, pose
  for (std::size_t f = 0; f < frames.size(); ++f) {
    const double t = *frameTimestamp(frames[f]);
    auto i = std::lower_bound(by_time.begin(), by_time.end(), t - kTumMaxTimeDifference,
                              [&](std::size_t p, double v) { return stamps[p] < v; });
    for (; i != by_time.end() && stamps[*i] < t + kTumMaxTimeDifference; ++i)
      if (std::abs(stamps[*i] - t) < kTumMaxTimeDifference) pairs.emplace_back(std::abs(stamps[*i] - t), f, *i);
  }
  std::sort(pairs.begin(), pairs.end());
  std::vector<std::optional<std::size_t>> pose_of(frames.size());
  std::vector<bool> taken(stamps.size(), false);
  for (const auto& [gap, f, p] : pairs)
    if (!pose_of[f] && !taken[p]) pose_of[f] = p, taken[p] = true;
  std::vector<RigidPose> out;
  for (std::size_t f = 0; f < frames.size(); ++f) {
    if (pose_of[f]) {
      out.push_back(poses[*pose_of[f]]);
      continue;
    }
    const double gap = nearestGap(stamps, *frameTimestamp(frames[f]));
    const std::string name = frames[f].filename().string();
    if (gap < kTumMaxTimeDifference)
      throw DataError(file, "", "every pose within " + seconds(kTumMaxTimeDifference) + " of " + name +
                                    " is paired with an image nearer to it in time (as associate.py pairs them, a "
                                    "pose serves one image): leave out one of the images that close together");
    throw DataError(file, "", "no pose within " + seconds(kTumMaxTimeDifference) + " of " + name +
                                  " (the nearest is " + seconds(gap) + " away): is it the trajectory of these images?");
  }
  return out;
}

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

/// The one number in a frame's file name (depth000120.png, frame-000120.depth.png: 120), or a DataError naming the
/// frame when its name has none, more than one (depth000005-cam2.png: which is the frame?) or one past 2^64.
std::uint64_t frameNumber(const fs::path& frame, const std::string& kind) {
  constexpr const char* digits = "0123456789";
  const std::string name = frame.filename().string();
  const std::string rule = "--pose-by-frame-number takes the pose numbered by the one number in each " + kind +
                           "'s file name (depth000120.png: pose 120), and this name has ";
  const std::size_t first = name.find_first_of(digits);
  if (first == std::string::npos) throw DataError(frame, "", rule + "no number");
  const std::size_t end = std::min(name.find_first_not_of(digits, first), name.size());
  if (name.find_first_of(digits, end) != std::string::npos)
    throw DataError(frame, "", rule + "more than one: rename the " + kind + "s, or give the poses in their order");
  std::uint64_t number = 0;
  if (!parseUnsigned(std::string_view(name).substr(first, end - first), number))
    throw DataError(frame, "", rule + "one too large for a pose number: " + name.substr(first, end - first));
  return number;
}

/// Each frame takes the pose its file name numbers, counting from 0, as Replica's results/ and traj.txt pair them;
/// two frames of one number (depth10.png, depth010.png) are refused: one of them is not the frame it seems.
std::vector<RigidPose> posesByFrameNumber(const std::vector<RigidPose>& poses, const fs::path& file,
                                          const std::vector<fs::path>& frames, const std::string& kind) {
  std::map<std::uint64_t, const fs::path*> frame_of;
  std::vector<RigidPose> out;
  for (const fs::path& frame : frames) {
    const std::uint64_t number = frameNumber(frame, kind);
    const std::string name = frame.filename().string();
    if (number >= poses.size())
      throw DataError(file, "", "holds " + std::to_string(poses.size()) + " poses (numbered 0 to " +
                                    std::to_string(poses.size() - 1) + "): " + name + " takes pose " +
                                    std::to_string(number) + " (--pose-by-frame-number): is it the trajectory of "
                                    "these " + kind + "s?");
    if (const auto [at, added] = frame_of.emplace(number, &frame); !added)
      throw DataError(frame, "", "is frame " + std::to_string(number) + ", as " + at->second->string() +
                                     " is (--pose-by-frame-number): give each frame once");
    out.push_back(poses[std::size_t(number)]);
  }
  return out;
}

std::vector<RigidPose> posesOneFilePerFrame(const std::vector<fs::path>& pose_files, PoseFormat format,
                                            std::size_t frames, const std::string& kind) {
  if (pose_files.size() != frames)
    throw std::invalid_argument(std::to_string(pose_files.size()) + " pose files for " + std::to_string(frames) +
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

}  // namespace

nlohmann::json poseFileNames(const std::vector<fs::path>& pose_files) {
  if (pose_files.size() == 1) return pose_files[0].filename().string();
  nlohmann::json names = nlohmann::json::array();
  for (const fs::path& f : pose_files) names.push_back(f.filename().string());
  return names;
}

void recordPoseReading(nlohmann::json& source, PoseFormat format, const PoseSelection& selection,
                       PoseConvention convention) {
  source["pose_format"] = poseFormatName(format);
  source["pose_convention"] = poseConventionName(convention);
  if (selection.chosen) source["pose_start_step"] = {selection.start, selection.step};
  if (selection.by_frame_number) source["pose_by_frame_number"] = true;
}

namespace {

/// framePoses of the poses as the files hold them.
std::vector<RigidPose> posesAsWritten(const std::vector<fs::path>& pose_files, PoseFormat format,
                                      const std::vector<fs::path>& frames, const std::string& kind,
                                      const PoseSelection& selection) {
  if ((selection.chosen || selection.by_frame_number) && pose_files.size() > 1)
    throw std::invalid_argument(std::string(selection.chosen ? "--pose-start and --pose-step take"
                                                             : "--pose-by-frame-number takes") +
                                " poses out of one file of a whole sequence, not out of " +
                                std::to_string(pose_files.size()) + " pose files");
  if (pose_files.size() > 1) return posesOneFilePerFrame(pose_files, format, frames.size(), kind);
  const fs::path& file = pose_files.at(0);
  std::vector<RigidPose> poses = readPoses(file, format);
  // Asked for by position or number: taken so, even from a TUM trajectory whose frames are named by numbers.
  if (selection.chosen) return selectedPoses(poses, selection, file, frames.size(), kind);
  if (selection.by_frame_number) return posesByFrameNumber(poses, file, frames, kind);
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
  throw DataError(file, "", counts + ". A whole sequence's poses? Give --pose-start K --pose-step N: " + kind +
                                " i takes pose K + i N, counting from 0 (--pose-start 0 for the sequence's first " +
                                kind + "s, --pose-step 10 for every tenth); --pose-by-frame-number when each " + kind +
                                "'s name numbers its pose (Replica's depth000120.png: pose 120); a TUM trajectory "
                                "(--pose-format tum) is matched by timestamp when each " + kind + " is named by its "
                                "own, as TUM names them");
}

}  // namespace

std::vector<RigidPose> framePoses(const std::vector<fs::path>& pose_files, PoseFormat format,
                                  const std::vector<fs::path>& frames, const std::string& kind,
                                  const PoseSelection& selection, PoseConvention convention) {
  std::vector<RigidPose> poses = posesAsWritten(pose_files, format, frames, kind, selection);
  if (convention == PoseConvention::WorldToCamera)
    for (RigidPose& pose : poses) pose = pose.inverse();
  return poses;
}

}  // namespace occsweep
