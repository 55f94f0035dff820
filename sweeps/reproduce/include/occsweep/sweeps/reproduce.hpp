// `occsweep reproduce`: every experiment of the paper's Section 4 in one command. Each step writes one
// JSON file under OUT (fits, nca, comparison, curves, runtime); the figures are drawn from those files (the
// command runs tools/plot_reproduction.py) and report.md sets each of the paper's findings beside ours. See docs/reproduction.md.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace occsweep {

/// The steps of a reproduction in their order: fits (Fig. 3), nca (Fig. 4), comparison (Fig. 5), curves (Fig. 6),
/// runtime (Fig. 7), and real-stereo (no figure of the paper: k-NN against OctoMap on a real stereo pair without
/// the voxel filter, docs/fidelity.md, "Real stereo with truth").
[[nodiscard]] inline std::vector<std::string> reproductionSteps() {
  return {"fits", "nca", "comparison", "curves", "runtime", "real-stereo"};
}

/// What the real-stereo step is given: one real stereo pair's point cloud sets at one resolution and one voxel
/// filter, or why there are none.
struct RealStereoSets {
  std::string pair;                     ///< which pair, in words (report.md)
  std::vector<std::string> folders;     ///< pcs-NNNN under the folder asked for, in point cloud id order
  std::vector<std::int64_t> ids;        ///< point cloud parameter ids, same order
  std::vector<std::uint64_t> points;    ///< points of each set (one scan each)
  std::string not_available;            ///< non-empty: why no set was written (report.md's "not run: ...")
};

/// `reproduce --realistic`: the `dataset generate` options that the experiments of docs/fidelity.md point to, and
/// the key every such data set's ranking.json `options` must then hold. One home: the report and the check read it.
struct RealisticData {
  static constexpr const char* kGenerateOptions = "--realistic";
  static constexpr const char* kRankingKey = "realistic";
};

struct ReproduceConfig {
  std::string scale = "ci";                  ///< ci | small | paper: the data sets' scale (docs/datasets.md)
  std::filesystem::path out;                 ///< results, figures and report.md
  std::filesystem::path data;                ///< generated data sets; empty: OUT/data. Existing ones are reused
  std::vector<std::string> datasets;         ///< empty: the paper's 20, paperDatasetNames() (eval/paper_datasets.hpp)
  /// Missing data sets are generated with RealisticData's options, and existing ones must have been (--realistic).
  bool realistic = false;
  std::uint64_t seed = 1;                    ///< Eq. 16 split of the reduction grid, NCA subsample and folds
  /// Section 4.4 / Fig. 3: the 800th (median-ranked) set of building-voronoi-I; falls back to the first data set.
  std::string fit_dataset = "building-voronoi-I";
  int fit_k = 1;                             ///< k of the s_i fitted (the paper does not say; knn-opt's k)
  std::string reduction_grid = "reduction";  ///< Table 1 note a, split over the 20 data sets (Eq. 16)
  std::size_t nca_samples = 0;               ///< NCA samples per data set and response, drawn from the group's
                                             ///< 5,625; 0: all (NCA is O(n^2) per iteration)
  int nca_folds = 5;                         ///< cross-validation folds for lambda
  std::vector<double> nca_lambda_factors = {0.0, 0.25, 1.0, 4.0, 16.0};  ///< lambda = factor / n
  std::string map_dataset = "parking-voronoi-O";  ///< Fig. 6: its 1st ranked set
  std::vector<int> runtime_k = {1, 3, 5, 7};      ///< Fig. 7b: k of the timed k-NN builds (Table 1 note a)
  int runtime_fractions = 4;                 ///< Fig. 7: builds on the first 1/F, 2/F, ..., F/F of each set's scans
  int runtime_datasets = 4;                  ///< Fig. 7: timed data sets (spread over the list), reduction set
  int runtime_repeats = 1;                   ///< each build timed this often, the fastest kept
  int threads = 0;                           ///< sweeps and NCA; 0: all cores (timed builds always use 1)
  /// Makes the missing data set NAME at SCALE under the folder OUT (OUT/NAME/ranking.json written last), with
  /// RealisticData's options when `realistic`. The library runs no program: the command hands in `dataset
  /// generate`'s own code (tools/occsweep/cmd_dataset.hpp). Empty: a missing data set is an error.
  std::function<void(const std::string& name, const std::string& scale, const std::filesystem::path& out,
                     bool realistic)>
      generate_dataset;
  /// real-stereo: the map resolutions, each also the truth's voxel size.
  std::vector<double> real_stereo_resolutions = {0.05, 0.1};
  /// real-stereo: the voxel filter's leaf as a fraction of the resolution, 0 for no filter (one point per valid
  /// disparity). At 1 one point is left per voxel and scan, and Eq. 7's per-voxel sum has one term, as OctoMap's
  /// update; below 1 and without the filter it has several (docs/fidelity.md, "Real stereo with truth").
  std::vector<double> real_stereo_filters = {0.0, 0.5, 1.0};
  /// Writes the real pair's sets, truth at `resolution`, voxel-filtered at `filter_leaf` metres (0: not filtered),
  /// into `folder` (the command hands in `dataset middlebury --leaf RESOLUTION [--voxel-filter F |
  /// --no-voxel-filter]`'s own code: tools/occsweep/cmd_dataset_middlebury.hpp).
  /// Empty, or sets with `not_available`: the step writes a "not run" report section saying why.
  std::function<RealStereoSets(const std::filesystem::path& folder, double resolution, double filter_leaf)>
      write_real_stereo;
  /// Draws the figures of `steps` from the step files in OUT, last. Empty: JSON and report.md only (`--no-figures`).
  /// The command checks that it can draw them before the run starts.
  std::function<void(const std::filesystem::path& out, const std::vector<std::string>& steps)> draw_figures;
  /// The steps to run, a subset of reproductionSteps() (`--steps`): curves needs comparison. Steps left out write
  /// no JSON, no figure and a "not run" line in report.md.
  std::vector<std::string> steps = reproductionSteps();
  bool quiet = false;                        ///< no progress on stderr
};

/// Defaults per scale: ci keeps the whole pipeline under 10 minutes on 2 cores (NCA on 800 samples, 3 folds),
/// small 1,000 samples and 5 folds, paper all samples, 5 folds and 5 lambdas. Throws std::invalid_argument for another scale.
[[nodiscard]] ReproduceConfig reproduceDefaults(const std::string& scale);

/// One data set's point cloud sets from its ranking.json, best first.
struct RankedDataset {
  std::string name;
  std::filesystem::path root;              ///< DATA/NAME
  std::vector<std::string> folders;        ///< pcs-NNNN in rank order
  std::vector<std::int64_t> ids;           ///< point cloud parameter ids, same order
  nlohmann::json generator_options = nlohmann::json::object();  ///< ranking.json `options`: {} for the defaults
  /// Rank positions (0-based) standing for the paper's 1st, 800th and 1,600th of 1,600: first, (n+1)/2-th, last.
  [[nodiscard]] std::vector<std::size_t> paperRanks() const;
};

/// Generates the missing data sets (c.generate_dataset) and reads every ranking.json. Every data set of one
/// reproduction must come from the same generator options (the report states them); with c.realistic they must be
/// RealisticData's. Throws std::runtime_error naming the ranking.json that differs.
[[nodiscard]] std::vector<RankedDataset> prepareDatasets(const ReproduceConfig& c);

/// Fig. 3: fits of the s_i of the fit data set's median-ranked set. Returns the fits.json content.
nlohmann::json runDistributionFits(const ReproduceConfig& c, const std::vector<RankedDataset>& d);
/// Fig. 4: reduction-grid sweeps (Eq. 16 group per data set) and NCA weights for TPR and FDR.
nlohmann::json runNcaWeights(const ReproduceConfig& c, const std::vector<RankedDataset>& d);
/// Fig. 5: knn-opt and octomap-opt sweeps of the 1st, median and last set of each data set; best AUCs.
nlohmann::json runOptimalComparison(const ReproduceConfig& c, const std::vector<RankedDataset>& d);
/// Fig. 6: both best curves of the map data set's 1st set, maps at points of similar FDR as PLY.
nlohmann::json runCurvesAndMaps(const ReproduceConfig& c, const std::vector<RankedDataset>& d,
                                const nlohmann::json& comparison);
/// Fig. 7: timed builds, Eq. 17 and Eq. 18 fits.
nlohmann::json runRuntimeModels(const ReproduceConfig& c, const std::vector<RankedDataset>& d);
/// Real stereo without the voxel filter: per resolution, octomap-opt and knn-opt on each set under full and
/// observable truth, the best of each, the ablation (the best knn-opt map with p_u = p_l) and compareStatistics'
/// verdict. The sets go to OUT/data/real-stereo/, the sweeps to OUT/sweeps/real-stereo/. Returns real-stereo.json.
nlohmann::json runRealStereo(const ReproduceConfig& c);

/// The step files of one reproduction; a step that was not run is null.
struct ReproductionResults {
  std::size_t datasets = 0;
  nlohmann::json generator_options = nlohmann::json::object();  ///< of every data set (prepareDatasets checks)
  nlohmann::json fits, nca, comparison, curves, runtime, real_stereo;
};

/// report.md: each finding of the paper beside ours, every number from the step files; a step not run is said so.
[[nodiscard]] std::string reproductionReport(const ReproduceConfig& c, const ReproductionResults& r);
/// The first line of report.md: its proof of being occsweep's, which a re-run replaces (docs/io.md, "Ownership").
inline constexpr const char* kReproductionReportMark = "<!-- occsweep reproduce report -->";
/// The Software text chunk of every figure of a reproduction (tools/plot_reproduction.py writes it).
inline constexpr const char* kReproductionFigureMark = "occsweep reproduce";

/// Checks `steps` against reproductionSteps() (each known, none twice, curves with comparison); throws
/// std::invalid_argument naming the step and the rule.
void checkReproductionSteps(const std::vector<std::string>& steps);

/// All steps in order; each step's JSON is written to OUT (temporary name, renamed) before the next starts,
/// sweeps resume from OUT/sweeps. Returns the wall time in seconds.
double runReproduction(const ReproduceConfig& c);

}  // namespace occsweep
