#include "occsweep/stereo/generate.hpp"

#include <atomic>
#include <chrono>
#include <exception>
#include <cstdio>
#include <iostream>
#include <mutex>

#include <tbb/parallel_for.h>

#include "occsweep/core/splitmix64.hpp"
#include "occsweep/eval/dataset.hpp"
#include "occsweep/eval/fnv1a.hpp"
#include "occsweep/eval/naive.hpp"
#include "occsweep/stereo/cloud.hpp"
#include "occsweep/stereo/ranking.hpp"
#include "occsweep/stereo/raycast.hpp"

namespace occsweep::stereo {
namespace {

double secondsSince(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

std::string folderName(std::int64_t id) {
  if (id < 0) return "pcs-custom";
  char buf[32];
  std::snprintf(buf, sizeof buf, "pcs-%04lld", static_cast<long long>(id));
  return buf;
}

namespace fs = std::filesystem;

// The data set's seed: the configured seed mixed with its name, so that data sets differ.
std::uint64_t datasetSeed(const DatasetName& name, const GenerateConfig& c) {
  Fnv1a name_hash;
  name_hash.feed(name.str());
  return SplitMix64(c.seed ^ std::stoull(name_hash.hex(), nullptr, 16)).next();
}

// The point cloud parameter sets to run, with their grid ids (-1: --sgbm).
std::vector<std::pair<std::int64_t, SgbmParams>> chosenSets(const GenerateConfig& c, const PointCloudGrid& grid) {
  std::vector<std::pair<std::int64_t, SgbmParams>> sets;
  if (c.custom) sets.push_back({-1, *c.custom});
  else
    for (std::uint64_t id : c.pcs_ids.empty() ? evenSubset(grid.size(), c.scale.subset ? c.scale.subset : grid.size())
                                              : c.pcs_ids)
      sets.push_back({std::int64_t(id), grid.at(id)});
  return sets;
}

// A generation that fails (a full disk) removes the folders this run made: no half data-set folder is left.
struct RemoveMadeOnFailure {
  fs::path first_made;  ///< the outermost folder of `dir` that did not exist; empty if none
  explicit RemoveMadeOnFailure(const fs::path& dir) {
    for (fs::path p = dir; !p.empty() && !fs::exists(p); p = p.parent_path()) {
      first_made = p;
      if (p == p.parent_path()) break;
    }
  }
  RemoveMadeOnFailure(const RemoveMadeOnFailure&) = delete;
  RemoveMadeOnFailure& operator=(const RemoveMadeOnFailure&) = delete;
  ~RemoveMadeOnFailure() {
    std::error_code ec;
    if (!first_made.empty() && std::uncaught_exceptions() > 0) fs::remove_all(first_made, ec);
  }
};

// What every point cloud set of one data set shares.
struct DatasetContext {
  const DatasetName& name;
  const GenerateConfig& c;
  const PointCloudGrid& grid;
  const Scene& scene;
  const GroundTruth& truth;
  const StereoCamera& cam;
  const Keyframes& key;
  const fs::path& dir;
};

// One point cloud set's scans (one per keyframe, possibly empty) and the counts of target pixels per keyframe.
struct StereoScans {
  std::vector<Scan> scans;
  std::vector<std::uint64_t> target_pixels, target_valid;
  std::vector<std::int16_t> preview_disparity;  ///< keyframe 0's, with previews
};

StereoScans stereoScans(const DatasetContext& x, const SgbmParams& params) {
  const Keyframes& key = x.key;
  const GenerateConfig& c = x.c;
  StereoScans out;
  out.scans.resize(key.frames.size());
  out.target_pixels.resize(key.frames.size());
  out.target_valid.resize(key.frames.size());
  tbb::parallel_for(std::size_t(0), key.frames.size(), [&](std::size_t i) {
    const auto disparity = computeDisparity(key.frames[i], params, c.scale.num_disparities);
    for (std::size_t p = 0; p < disparity.size(); ++p)
      if (key.frames[i].target_mask[p]) out.target_pixels[i] += 1, out.target_valid[i] += disparity[p] > 0;
    out.scans[i].origin = octomap::point3d(float(key.mapping[i].position.x()), float(key.mapping[i].position.y()),
                                           float(key.mapping[i].position.z()));
    const auto points = reprojectDisparity(disparity, x.cam, key.mapping[i], c.max_depth);
    out.scans[i].points = c.voxel_filter ? voxelFilter(points, c.leaf) : toPoint3d(points);
    if (i == 0 && c.preview) out.preview_disparity = disparity;
  });
  return out;
}

// Of the points within kNearRange of their camera, those more than kOffSurface from the scene's surfaces.
double offSurfaceFraction(const std::vector<Scan>& scans, const Scene& scene) {
  std::uint64_t off = 0, near = 0;
  for (const Scan& scan : scans)
    for (const auto& p : scan.points) {
      if (rangeFromOrigin(p, scan.origin) > kNearRange) continue;
      near += 1;
      off += surfaceDistance(scene, Eigen::Vector3d(p.x(), p.y(), p.z())) > kOffSurface;
    }
  return near ? double(off) / double(near) : 0.0;
}

// Moves the non-empty scans into `d` and returns the indices of the others (the data-set format refuses empty
// scans); the fraction of target pixels with a valid disparity counts every keyframe.
std::vector<int> keepNonEmpty(StereoScans& s, Dataset& d, PointCloudSetSummary& pcs) {
  std::vector<int> dropped;
  std::uint64_t pixels = 0, valid = 0;
  for (std::size_t i = 0; i < s.scans.size(); ++i) {
    pixels += s.target_pixels[i], valid += s.target_valid[i];
    if (s.scans[i].points.empty()) dropped.push_back(int(i));
    else d.scans.push_back(std::move(s.scans[i]));
  }
  pcs.target_valid_fraction = pixels ? double(valid) / double(pixels) : 0.0;
  return dropped;
}

// SGBM on every keyframe, the clouds and their quality, written to DIR/pcs-NNNN.
PointCloudSetSummary generateSet(const DatasetContext& x, std::int64_t id, const SgbmParams& params) {
  const auto start = std::chrono::steady_clock::now();
  StereoScans s = stereoScans(x, params);
  if (x.c.preview)
    writeDisparityPng(s.preview_disparity, x.cam.width, x.cam.height, x.c.scale.num_disparities,
                      x.dir / "preview" / ("disparity-" + folderName(id) + ".png"));
  PointCloudSetSummary pcs;
  pcs.folder = folderName(id);
  pcs.id = id;
  pcs.params = params;
  Dataset d;
  d.name = x.name.str() + "/" + pcs.folder;
  const std::vector<int> dropped = keepNonEmpty(s, d, pcs);
  pcs.points = pointCount(d.scans);
  pcs.scans = d.scans.size();
  pcs.off_surface_fraction = offSurfaceFraction(d.scans, x.scene);
  pcs.naive = naiveConfusion(d.scans, x.truth);
  d.truth.boxes = x.scene.boxes;
  d.region = x.scene.region;
  d.source = sourceJson(x.name, x.c, x.cam, x.grid, id, params);
  d.source["keyframes_dropped_empty"] = dropped;
  if (d.scans.empty()) throw std::runtime_error(x.name.str() + " " + pcs.folder + ": no keyframe produced a point");
  checkOutputTarget(x.dir / pcs.folder, true, datasetOutput());  // a regenerated set replaces only its own folder
  writeDataset(d, x.dir / pcs.folder);
  pcs.seconds = secondsSince(start);
  return pcs;
}

void printSet(const std::string& name, const PointCloudSetSummary& pcs, std::size_t s, std::size_t sets) {
  std::cerr << "  " << name << " " << pcs.folder << " (" << s + 1 << "/" << sets << "): " << pcs.points
            << " points, valid on targets " << pcs.target_valid_fraction << ", off-surface " << pcs.off_surface_fraction << ", naive TPR " << pcs.naive.tpr()
            << " FDR " << pcs.naive.fdr() << ", " << pcs.seconds << " s\n";
}

}  // namespace

Keyframes renderKeyframes(const Scene& scene, const StereoCamera& cam, const GenerateConfig& c, std::uint64_t base_seed) {
  Keyframes k;
  OrbitConfig orbit = c.orbit;
  orbit.keyframes = c.scale.keyframes;
  k.truth = orbitPoses(orbit, scene.centre);
  PoseDrift drift = c.drift;
  drift.seed = base_seed ^ 0xD81F7ull;
  k.mapping = driftedPoses(k.truth, drift);
  k.frames.resize(k.truth.size());
  std::atomic<int> done{0};
  std::mutex print;
  tbb::parallel_for(std::size_t(0), k.truth.size(), [&](std::size_t i) {
    k.frames[i] = renderFrame(scene, cam, k.truth[i], c.render, base_seed + 0x1000 * (i + 1));
    const int n = ++done;
    if (c.progress && (n % 8 == 0 || n == int(k.truth.size()))) {
      std::lock_guard lock(print);
      std::cerr << "  " << scene.name.str() << ": rendered " << n << "/" << k.truth.size() << " keyframes\n";
    }
  });
  return k;
}

DatasetSummary generateDataset(const DatasetName& name, const GenerateConfig& c, const PointCloudGrid& grid,
                               const std::filesystem::path& out_root) {
  const Scene scene = makeScene(name, c.scene);
  const GroundTruth truth = sceneGroundTruth(scene, c.leaf);
  const StereoCamera cam = zedLikeCamera(c.scale.width, c.scale.height);
  const std::uint64_t base_seed = datasetSeed(name, c);
  const auto sets = chosenSets(c, grid);

  const fs::path dir = out_root / name.str();
  const RemoveMadeOnFailure cleanup(dir);
  fs::create_directories(dir);
  DatasetSummary summary{name.str(), c.scale.name, {}, 0};
  const auto start = std::chrono::steady_clock::now();
  const Keyframes key = renderKeyframes(scene, cam, c, base_seed);
  summary.render_seconds = secondsSince(start);
  if (c.preview) {
    fs::create_directories(dir / "preview");
    writeGreyPng(key.frames[0].left, dir / "preview" / "left.png");
    writeGreyPng(key.frames[0].right, dir / "preview" / "right.png");
  }

  const DatasetContext context{name, c, grid, scene, truth, cam, key, dir};
  for (std::size_t s = 0; s < sets.size(); ++s) {
    summary.sets.push_back(generateSet(context, sets[s].first, sets[s].second));
    if (c.progress) printSet(name.str(), summary.sets.back(), s, sets.size());
  }
  rankSets(summary.sets);
  writeRanking(summary, c, grid, dir);
  return summary;
}

}  // namespace occsweep::stereo
