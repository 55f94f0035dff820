#include "occsweep/stereo/generate.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <exception>
#include <functional>
#include <cstdio>
#include <iostream>
#include <mutex>

#include <tbb/parallel_for.h>

#include "occsweep/core/splitmix64.hpp"
#include "occsweep/eval/dataset.hpp"
#include "occsweep/io/fnv1a.hpp"
#include "occsweep/eval/naive.hpp"
#include "occsweep/stereo/cloud.hpp"
#include "occsweep/stereo/ranking.hpp"
#include "occsweep/stereo/raycast.hpp"
#include "occsweep/io/output_target.hpp"

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

// A generation that fails (a full disk) leaves nothing of its own where it made the data set's folder: the sets
// and previews it wrote there, each proven occsweep's, then each folder it made, only when that leaves it empty. A
// folder that held anything before, or an entry someone else put in it meanwhile, stays (docs/io.md,
// "Ownership": a folder tree is never removed whole).
class RemoveMadeOnFailure {
 public:
  explicit RemoveMadeOnFailure(const fs::path& dir) : dir_(dir), made_(missingFolders(dir)) {}
  RemoveMadeOnFailure(const RemoveMadeOnFailure&) = delete;
  RemoveMadeOnFailure& operator=(const RemoveMadeOnFailure&) = delete;
  ~RemoveMadeOnFailure() {
    if (made_.empty() || std::uncaught_exceptions() == 0) return;
    std::error_code ec;
    for (fs::directory_iterator it(dir_, ec), end; !ec && it != end; it.increment(ec))
      if (fs::is_directory(fs::symlink_status(it->path(), ec)) && datasetOutput().is_own(it->path()))
        fs::remove_all(it->path(), ec);  // a set of this run's, whole: every entry its manifest's
    for (fs::directory_iterator it(dir_ / "preview", ec), end; !ec && it != end; it.increment(ec))
      if (previewOutput().is_own(it->path())) fs::remove(it->path(), ec);
    removeEmptyFolders({dir_ / "preview"});
    removeEmptyFolders(made_);
  }

 private:
  fs::path dir_;
  std::vector<fs::path> made_;  ///< the folders on the way to dir_ that did not exist, innermost first
};

// Every output of one data set, checked before any work (docs/io.md, "Ownership"): an existing one of
// occsweep's is refused unless --force, a user's file always, so that "nothing was changed" holds when refused.
// Each is checked again just before it is written.
void checkGenerationTargets(const fs::path& dir, const GenerateConfig& c,
                            const std::vector<std::pair<std::int64_t, SgbmParams>>& sets) {
  for (const auto& [id, params] : sets) checkOutputTarget(dir / folderName(id), c.force, datasetOutput());
  checkOutputTarget(dir / "ranking.json", c.force, rankingOutput());
  checkOutputTarget(dir / "timing.json", c.force, timingOutput());
  if (!c.preview) return;
  for (const char* png : {"left.png", "right.png"}) checkOutputTarget(dir / "preview" / png, c.force, previewOutput());
  for (const auto& [id, params] : sets)
    checkOutputTarget(dir / "preview" / ("disparity-" + folderName(id) + ".png"), c.force, previewOutput());
}

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

  explicit StereoScans(std::size_t keyframes) : scans(keyframes), target_pixels(keyframes), target_valid(keyframes) {}
};

// What keyframe i's disparity gives its set besides the points: the target pixel counts, the scan's origin and
// view, and (keyframe 0) the preview.
void recordDisparity(const DatasetContext& x, std::size_t i, const std::vector<std::int16_t>& disparity,
                     StereoScans& out) {
  const Keyframes& key = x.key;
  for (std::size_t p = 0; p < disparity.size(); ++p)
    if (key.frames[i].target_mask[p]) out.target_pixels[i] += 1, out.target_valid[i] += disparity[p] > 0;
  out.scans[i].origin = octomap::point3d(float(key.mapping[i].position.x()), float(key.mapping[i].position.y()),
                                         float(key.mapping[i].position.z()));
  out.scans[i].view = leftCameraView(x.cam, key.mapping[i]);  // the pose the clouds are placed with
  if (i == 0 && x.c.preview) out.preview_disparity = disparity;
}

// A keyframe's disparity for one point cloud set, by keyframe index.
using DisparityOf = std::function<std::vector<std::int16_t>(std::size_t keyframe)>;

// One set's scans from its disparities: reprojection and voxel filter per keyframe.
StereoScans stereoScans(const DatasetContext& x, const DisparityOf& disparity_of) {
  StereoScans out(x.key.frames.size());
  tbb::parallel_for(std::size_t(0), x.key.frames.size(), [&](std::size_t i) {
    const auto disparity = disparity_of(i);
    recordDisparity(x, i, disparity, out);
    const auto points = reprojectDisparity(disparity, x.cam, x.key.mapping[i], x.c.max_depth);
    out.scans[i].points = x.c.voxel_filter ? voxelFilter(points, x.c.leaf) : toPoint3d(points);
  });
  return out;
}

// The scans of every speckle variant of one matcher combination, keyframe by keyframe: the matcher once, its
// reprojection and voxel sort once (SharedVoxelFilter), then per variant compute's speckle filter on a copy and
// the kept points' centroids. Holds the variants' voxel-filtered scans (the paper's setting), not raw clouds.
std::vector<StereoScans> variantScansSharingVoxels(const DatasetContext& x, const std::vector<SgbmParams>& variants) {
  std::vector<StereoScans> out(variants.size(), StereoScans(x.key.frames.size()));
  tbb::parallel_for(std::size_t(0), x.key.frames.size(), [&](std::size_t i) {
    const auto matcher = computeMatcherDisparity(x.key.frames[i], variants.front(), x.c.scale.num_disparities);
    const SharedVoxelFilter voxels(matcher, x.cam, x.key.mapping[i], x.c.max_depth, x.c.leaf);
    std::vector<std::vector<std::int16_t>> disparities;  // this keyframe's, by variant
    for (std::size_t v = 0; v < variants.size(); ++v) {
      disparities.push_back(matcher);
      filterSpecklesAsCompute(disparities[v], x.cam.width, x.cam.height, variants[v]);
      recordDisparity(x, i, disparities[v], out[v]);
      // The same disparity gives the same points: speckleWindowSize 0 at every speckleRange, or a filter that
      // removed the same pixels.
      const auto same = std::find(disparities.begin(), disparities.begin() + long(v), disparities[v]);
      out[v].scans[i].points = same != disparities.begin() + long(v)
                                   ? out[std::size_t(same - disparities.begin())].scans[i].points
                                   : voxels.filtered(disparities[v]);
    }
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

// One set from its scans: the clouds' quality, written to DIR/pcs-NNNN. `scan_seconds`: the time its scans took
// (with sharing, its equal share of its group's).
PointCloudSetSummary generateSet(const DatasetContext& x, std::int64_t id, const SgbmParams& params, StereoScans s,
                                 double scan_seconds) {
  const auto start = std::chrono::steady_clock::now();
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
  pcs.seconds = scan_seconds + secondsSince(start);
  return pcs;
}

void printSet(const std::string& name, const PointCloudSetSummary& pcs, std::size_t s, std::size_t sets) {
  std::cerr << "  " << name << " " << pcs.folder << " (" << s + 1 << "/" << sets << "): " << pcs.points
            << " points, valid on targets " << pcs.target_valid_fraction << ", off-surface " << pcs.off_surface_fraction << ", naive TPR " << pcs.naive.tpr()
            << " FDR " << pcs.naive.fdr() << ", " << pcs.seconds << " s\n";
}

using ChosenSet = std::pair<std::int64_t, SgbmParams>;

// The chosen sets' positions grouped by their matcher combination (matcherParams), groups in order of first
// appearance, positions ascending in each.
std::vector<std::vector<std::size_t>> matcherGroups(const std::vector<ChosenSet>& sets) {
  std::vector<std::vector<std::size_t>> groups;
  std::vector<SgbmParams> keys;
  for (std::size_t s = 0; s < sets.size(); ++s) {
    const SgbmParams key = matcherParams(sets[s].second);
    const auto found = std::find(keys.begin(), keys.end(), key);
    if (found == keys.end()) keys.push_back(key), groups.push_back({s});
    else groups[std::size_t(found - keys.begin())].push_back(s);
  }
  return groups;
}

// Each set alone: StereoSGBM::compute with its full parameters on every keyframe (the path before sharing).
void generateEachAlone(const DatasetContext& x, const std::vector<ChosenSet>& sets,
                       std::vector<PointCloudSetSummary>& out) {
  for (std::size_t s = 0; s < sets.size(); ++s) {
    const SgbmParams& params = sets[s].second;
    const auto start = std::chrono::steady_clock::now();
    StereoScans scans = stereoScans(x, [&](std::size_t i) {
      return computeDisparity(x.key.frames[i], params, x.c.scale.num_disparities);
    });
    out[s] = generateSet(x, sets[s].first, params, std::move(scans), secondsSince(start));
    if (x.c.progress) printSet(x.name.str(), out[s], s, sets.size());
  }
}

// A matcher combination's speckle variants with the voxel filter (the paper's setting): their scans together
// (variantScansSharingVoxels), then each set's quality and files, the sets in parallel (each writes only its own
// folder). The group's scan time is charged to its sets in equal shares.
void generateVariantsSharingVoxels(const DatasetContext& x, const std::vector<ChosenSet>& sets,
                                   const std::vector<std::size_t>& group, std::vector<PointCloudSetSummary>& out,
                                   const std::function<void(std::size_t)>& report) {
  std::vector<SgbmParams> variants;
  for (const std::size_t s : group) variants.push_back(sets[s].second);
  const auto start = std::chrono::steady_clock::now();
  std::vector<StereoScans> scans = variantScansSharingVoxels(x, variants);
  const double scan_share = secondsSince(start) / double(group.size());
  tbb::parallel_for(std::size_t(0), group.size(), [&](std::size_t v) {
    const std::size_t s = group[v];
    out[s] = generateSet(x, sets[s].first, sets[s].second, std::move(scans[v]), scan_share);
    scans[v] = StereoScans(0);  // written: its memory goes now, not with the group
    report(s);
  });
}

// Without the voxel filter a set's clouds are as large as its images, so the variants are made and written one
// at a time, sharing only the matcher's disparities (one per keyframe, held for the group).
void generateVariantsSharingMatcher(const DatasetContext& x, const std::vector<ChosenSet>& sets,
                                    const std::vector<std::size_t>& group, std::vector<PointCloudSetSummary>& out,
                                    const std::function<void(std::size_t)>& report) {
  const auto start = std::chrono::steady_clock::now();
  std::vector<std::vector<std::int16_t>> matcher(x.key.frames.size());
  tbb::parallel_for(std::size_t(0), x.key.frames.size(), [&](std::size_t i) {
    matcher[i] = computeMatcherDisparity(x.key.frames[i], sets[group.front()].second, x.c.scale.num_disparities);
  });
  const double matcher_share = secondsSince(start) / double(group.size());
  for (const std::size_t s : group) {
    const auto set_start = std::chrono::steady_clock::now();
    StereoScans scans = stereoScans(x, [&](std::size_t i) {
      std::vector<std::int16_t> disparity = matcher[i];
      filterSpecklesAsCompute(disparity, x.cam.width, x.cam.height, sets[s].second);
      return disparity;
    });
    out[s] = generateSet(x, sets[s].first, sets[s].second, std::move(scans), matcher_share + secondsSince(set_start));
    report(s);
  }
}

// Per matcher combination, its speckle variants from one matcher computation per keyframe (docs/datasets.md,
// "How generation shares work").
void generateSharingMatcher(const DatasetContext& x, const std::vector<ChosenSet>& sets,
                            std::vector<PointCloudSetSummary>& out) {
  std::size_t done = 0;
  std::mutex print;
  const auto report = [&](std::size_t s) {
    const std::lock_guard lock(print);
    if (x.c.progress) printSet(x.name.str(), out[s], done, sets.size());
    done += 1;
  };
  for (const std::vector<std::size_t>& group : matcherGroups(sets)) {
    if (x.c.voxel_filter) generateVariantsSharingVoxels(x, sets, group, out, report);
    else generateVariantsSharingMatcher(x, sets, group, out, report);
  }
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
  checkGenerationTargets(dir, c, sets);
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
  summary.sets.resize(sets.size());  // in the order of `sets` whichever path runs, then ranked
  if (c.share_matcher) generateSharingMatcher(context, sets, summary.sets);
  else generateEachAlone(context, sets, summary.sets);
  rankSets(summary.sets);
  writeRanking(summary, c, grid, dir);
  return summary;
}

}  // namespace occsweep::stereo
