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
  namespace fs = std::filesystem;
  const Scene scene = makeScene(name, c.scene);
  const GroundTruth truth = sceneGroundTruth(scene, c.leaf);
  const StereoCamera cam = zedLikeCamera(c.scale.width, c.scale.height);
  Fnv1a name_hash;
  name_hash.feed(name.str());
  const std::uint64_t base_seed = SplitMix64(c.seed ^ std::stoull(name_hash.hex(), nullptr, 16)).next();

  std::vector<std::pair<std::int64_t, SgbmParams>> sets;
  if (c.custom) sets.push_back({-1, *c.custom});
  else
    for (std::uint64_t id : c.pcs_ids.empty() ? evenSubset(grid.size(), c.scale.subset ? c.scale.subset : grid.size())
                                              : c.pcs_ids)
      sets.push_back({std::int64_t(id), grid.at(id)});

  const fs::path dir = out_root / name.str();
  // A generation that fails (a full disk) removes the folders this run made: no half data-set folder is left.
  struct RemoveMadeOnFailure {
    fs::path first_made;
    ~RemoveMadeOnFailure() {
      std::error_code ec;
      if (!first_made.empty() && std::uncaught_exceptions() > 0) fs::remove_all(first_made, ec);
    }
  } cleanup;
  for (fs::path p = dir; !p.empty() && !fs::exists(p); p = p.parent_path()) {
    cleanup.first_made = p;
    if (p == p.parent_path()) break;
  }
  fs::create_directories(dir);
  DatasetSummary summary{name.str(), c.scale.name, {}, 0};
  auto start = std::chrono::steady_clock::now();
  const Keyframes key = renderKeyframes(scene, cam, c, base_seed);
  summary.render_seconds = secondsSince(start);
  if (c.preview) {
    fs::create_directories(dir / "preview");
    writeGreyPng(key.frames[0].left, dir / "preview" / "left.png");
    writeGreyPng(key.frames[0].right, dir / "preview" / "right.png");
  }

  for (std::size_t s = 0; s < sets.size(); ++s) {
    start = std::chrono::steady_clock::now();
    const auto& id = sets[s].first;
    const auto& params = sets[s].second;  // not a structured binding: clang 14 cannot capture one in a lambda
    std::vector<Scan> scans(key.frames.size());
    std::vector<std::uint64_t> target_pixels(key.frames.size()), target_valid(key.frames.size());
    std::vector<std::int16_t> preview_disparity;
    tbb::parallel_for(std::size_t(0), key.frames.size(), [&](std::size_t i) {
      const auto disparity = computeDisparity(key.frames[i], params, c.scale.num_disparities);
      for (std::size_t p = 0; p < disparity.size(); ++p)
        if (key.frames[i].target_mask[p]) target_pixels[i] += 1, target_valid[i] += disparity[p] > 0;
      scans[i].origin = octomap::point3d(float(key.mapping[i].position.x()), float(key.mapping[i].position.y()),
                                         float(key.mapping[i].position.z()));
      const auto points = reprojectDisparity(disparity, cam, key.mapping[i], c.max_depth);
      scans[i].points = c.voxel_filter ? voxelFilter(points, c.leaf) : toPoint3d(points);
      if (i == 0 && c.preview) preview_disparity = disparity;
    });
    if (c.preview)
      writeDisparityPng(preview_disparity, cam.width, cam.height, c.scale.num_disparities,
                        dir / "preview" / ("disparity-" + folderName(id) + ".png"));
    PointCloudSetSummary pcs;
    pcs.folder = folderName(id);
    pcs.id = id;
    pcs.params = params;
    Dataset d;
    d.name = name.str() + "/" + pcs.folder;
    std::vector<int> dropped;  // a keyframe without one valid point: the data-set format refuses empty scans
    std::uint64_t pixels = 0, valid = 0;
    for (std::size_t i = 0; i < scans.size(); ++i) {
      pixels += target_pixels[i], valid += target_valid[i];
      if (scans[i].points.empty()) dropped.push_back(int(i));
      else d.scans.push_back(std::move(scans[i]));
    }
    pcs.points = pointCount(d.scans);
    pcs.scans = d.scans.size();
    pcs.target_valid_fraction = pixels ? double(valid) / double(pixels) : 0.0;
    std::uint64_t off = 0, near = 0;
    for (const Scan& scan : d.scans)
      for (const auto& p : scan.points) {
        if (rangeFromOrigin(p, scan.origin) > kNearRange) continue;
        near += 1;
        off += surfaceDistance(scene, Eigen::Vector3d(p.x(), p.y(), p.z())) > kOffSurface;
      }
    pcs.off_surface_fraction = near ? double(off) / double(near) : 0.0;
    pcs.naive = naiveConfusion(d.scans, truth);
    d.truth.boxes = scene.boxes;
    d.region = scene.region;
    d.source = sourceJson(name, c, cam, grid, id, params);
    d.source["keyframes_dropped_empty"] = dropped;
    if (d.scans.empty()) throw std::runtime_error(name.str() + " " + pcs.folder + ": no keyframe produced a point");
    checkOutputTarget(dir / pcs.folder, true, datasetOutput());  // a regenerated set replaces only its own folder
    writeDataset(d, dir / pcs.folder);
    pcs.seconds = secondsSince(start);
    if (c.progress)
      std::cerr << "  " << name.str() << " " << pcs.folder << " (" << s + 1 << "/" << sets.size() << "): " << pcs.points
              << " points, valid on targets " << pcs.target_valid_fraction << ", off-surface " << pcs.off_surface_fraction << ", naive TPR " << pcs.naive.tpr()
              << " FDR " << pcs.naive.fdr() << ", " << pcs.seconds << " s\n";
    summary.sets.push_back(std::move(pcs));
  }
  rankSets(summary.sets);
  writeRanking(summary, c, grid, dir);
  return summary;
}

}  // namespace occsweep::stereo
