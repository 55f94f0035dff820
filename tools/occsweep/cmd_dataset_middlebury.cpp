// occsweep dataset middlebury: a real stereo pair with ground truth (Middlebury 2006, as Debian's opencv-doc ships
// it) as occsweep data sets, one per point cloud parameter set of the ci subset (docs/datasets.md).
#include <cstdio>
#include <iostream>
#include <sstream>

#include "cmd_dataset_middlebury.hpp"
#include "command_registry.hpp"
#include "option_checks.hpp"

#ifdef OCCSWEEP_HAVE_STEREO
#include "occsweep/eval/provenance.hpp"
#include "occsweep/io/output_file.hpp"
#include "occsweep/stereo/middlebury.hpp"
#include "occsweep/stereo/pointcloud_grid.hpp"
#include "occsweep/sweeps/grid.hpp"
#endif

namespace occsweep::cli {
namespace {

#ifdef OCCSWEEP_HAVE_STEREO
// The default inputs come from a package: say which one is missing rather than only "file is missing".
void requirePackagedFile(const std::string& file) {
  namespace fs = std::filesystem;
  if (fs::path(file).parent_path() == stereo::kOpenCvSampleData && !fs::exists(file))
    throw std::runtime_error(file + ": missing; the Middlebury Aloe pair comes with Debian's opencv-doc package "
                             "(apt-get install opencv-doc; tools/setup.sh installs it), or give --left, --right, --gt");
}

// One point cloud set written to OUT/pcs-NNNN; its folder name, its points and the line `dataset middlebury` prints.
struct SetWritten {
  std::string folder, line;
  std::uint64_t points = 0;
};

SetWritten writeSet(const MiddleburyOptions& o, const stereo::MiddleburyPair& pair, const stereo::PointCloudGrid& grid,
                    std::uint64_t id, int num_disparities) {
  using namespace stereo;
  const MiddleburyCamera camera{o.focal, o.baseline, o.doffs};
  MiddleburySetSummary s;
  Dataset d = middleburyDataset(pair, camera, grid.at(id), num_disparities, {o.leaf, !o.no_voxel_filter, o.voxel_filter}, &s);
  char folder[32];
  std::snprintf(folder, sizeof folder, "pcs-%04llu", static_cast<unsigned long long>(id));
  d.name = std::string("middlebury/") + folder;
  d.source["inputs"] = {{"left", o.left}, {"right", o.right}, {"ground_truth", o.gt}};
  // The pair's bytes: every set of it is one recording, one unit of compare's tests (docs/statistics.md, Verdicts)
  d.source["provenance"] = {{"inputs", fileContentHashes({o.left, o.right, o.gt})}};
  d.source["pointcloud_id"] = id;
  d.source["pointcloud_grid"] = {{"name", grid.name}, {"file_hash", grid.file_hash}, {"size", grid.size()}};
  const std::filesystem::path dir = std::filesystem::path(o.out) / folder;
  checkOutputTarget(dir, true, datasetOutput());  // a rerun replaces only its own data-set folders
  writeDataset(d, dir);
  std::ostringstream line;
  line << folder << ": " << s.points << " points, valid on known pixels " << s.valid_fraction << " of "
       << s.truth_pixels << ", bad 1.0 " << s.bad1_fraction << ", truth voxels " << d.truth.points.size()
       << ", naive TPR " << s.naive.tpr() << " FDR " << s.naive.fdr() << '\n';
  return {folder, line.str(), s.points};
}
#endif

}  // namespace

MiddleburyOptions middleburyDefaults() {
  MiddleburyOptions o;
#ifdef OCCSWEEP_HAVE_STEREO
  o.left = (stereo::kOpenCvSampleData / "aloeL.jpg").string();
  o.right = (stereo::kOpenCvSampleData / "aloeR.jpg").string();
  o.gt = (stereo::kOpenCvSampleData / "aloeGT.png").string();
#endif
  return o;
}

#ifdef OCCSWEEP_HAVE_STEREO
std::string middleburyUnavailable(const MiddleburyOptions& o) {
  try {
    for (const auto& f : {o.left, o.right, o.gt}) requirePackagedFile(f);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  for (const auto& f : {o.left, o.right, o.gt})
    if (!std::filesystem::exists(f)) return f + ": missing";
  return "";
}

MiddleburySetsWritten writeMiddleburySets(const MiddleburyOptions& o, bool quiet) {
  using namespace stereo;
  for (const auto& f : {o.left, o.right, o.gt}) requirePackagedFile(f);
  const MiddleburyPair pair = readMiddleburyPair(o.left, o.right, o.gt);
  const PointCloudGrid grid = loadPointCloudGrid(resolveGridPath(o.grid));
  const int num_disparities = numDisparitiesCovering(pair);
  if (!quiet)
    std::cout << "pair " << pair.left.width << "x" << pair.left.height << ", numDisparities " << num_disparities
              << " (largest ground-truth disparity below it)\n";
  MiddleburySetsWritten written;
  for (const std::uint64_t id : middleburyPointCloudIds(grid)) {
    const SetWritten set = writeSet(o, pair, grid, id, num_disparities);
    if (!quiet) std::cout << set.line;
    written.folders.push_back(set.folder);
    written.ids.push_back(id);
    written.points.push_back(set.points);
  }
  return written;
}
#else
std::string middleburyUnavailable(const MiddleburyOptions&) {
  return "this build has no stereo tools (configure with -DOCCSWEEP_STEREO=ON and OpenCV's calib3d and imgproc)";
}

MiddleburySetsWritten writeMiddleburySets(const MiddleburyOptions& o, bool) {
  throw std::runtime_error("dataset middlebury: " + middleburyUnavailable(o));
}
#endif

std::pair<CLI::App*, std::function<int()>> addDatasetMiddlebury(CLI::App& dataset) {
  auto o = std::make_shared<MiddleburyOptions>(middleburyDefaults());
  CLI::App* mb = dataset.add_subcommand("middlebury", "A real stereo pair with ground-truth disparity (Middlebury 2006; "
                                                      "default: Aloe from Debian's opencv-doc) as OUT/pcs-*/ data sets");
  addExample(*mb, "occsweep dataset middlebury --out aloe");
  mb->add_option("--left", o->left, "Left image (JPEG or 8-bit PNG)")->type_name(kPath)->capture_default_str();
  mb->add_option("--right", o->right, "Right image")->type_name(kPath)->capture_default_str();
  mb->add_option("--gt", o->gt, "Ground-truth disparity of the left image: 8-bit PNG, full-size pixels, 0 unknown")
      ->type_name(kPath)
      ->capture_default_str();
  mb->add_option("--out", o->out, "Output folder")->type_name(kPath)->required();
  mb->add_option("--leaf", o->leaf, "Truth voxel size and the voxel filter's leaf, metres (sweep at this resolution)")
      ->capture_default_str()->check(voxelLeaf());
  auto* filter = mb->add_option("--voxel-filter", o->voxel_filter, "LEAF metres: PCL VoxelGrid's filter at this leaf "
                                "instead of --leaf (truth stays at --leaf), as import's flag")
                     ->check(voxelLeaf());
  mb->add_flag("--no-voxel-filter", o->no_voxel_filter, "Write the raw reprojected points, one per valid disparity "
               "(truth stays at --leaf), as dataset generate's flag")->excludes(filter);
  mb->add_option("--focal", o->focal, "Focal length, pixels (full size)")->capture_default_str()->check(numberAbove(0));
  mb->add_option("--stereo-baseline", o->baseline, "Distance between the two cameras' centres, metres")->capture_default_str()->check(numberAbove(0));
  mb->add_option("--doffs", o->doffs, "Disparity offset, pixels (the set's dmin.txt)")->capture_default_str()->check(numberAtLeast(0));
  mb->add_option("--pcs-grid", o->grid, "Point cloud parameter grid (its ci subset is used)")->capture_default_str();
  auto quiet = std::make_shared<bool>(false);
  mb->add_flag("--quiet", *quiet, "No progress on stderr");
  return {mb, [o, quiet]() -> int {
#ifdef OCCSWEEP_HAVE_STEREO
            (void)writeMiddleburySets(*o, *quiet);
            return 0;
#else
            std::cerr << "occsweep dataset middlebury: this build has no stereo tools (configure with "
                         "-DOCCSWEEP_STEREO=ON and OpenCV's calib3d and imgproc)\n";
            return 2;
#endif
          }};
}

}  // namespace occsweep::cli
