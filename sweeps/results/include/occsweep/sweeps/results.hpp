// Results files (docs/definitions.md, Results files): what a sweep measured, with everything needed to trust
// and repeat it.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "occsweep/core/map_settings.hpp"
#include "occsweep/eval/confusion.hpp"
#include "occsweep/eval/curve.hpp"
#include "occsweep/eval/observable_truth.hpp"
#include "occsweep/io/output_file.hpp"
#include "occsweep/eval/truth_coverage.hpp"
#include "occsweep/sweeps/grid.hpp"
#include "occsweep/sweeps/selection.hpp"

namespace occsweep {

/// The most combinations a JSON results file may take: it is built in memory while the sweep runs and
/// read back whole by every reader (about 1.9 KB a combination writing, 1.4 KB reading: 200,000 is about 380 MB),
/// whereas a store (--out NAME.db) is written batch by batch for grids of any size. The paper's largest grid
/// (reduction) has 112,500. `sweep`, `merge`, `results export` and `cluster plan` refuse more (docs/robustness.md,
/// "Limits and non-regular files").
inline constexpr std::uint64_t kMaxJsonCombinations = 200'000;
/// Refuses (std::invalid_argument, exit 2) a JSON results file `out` into which `writer` ("this sweep of knn-opt",
/// "the merge of 2 files") would write more than kMaxJsonCombinations `combinations`, pointing at a store.
void refuseLargeJson(const std::filesystem::path& out, const std::string& writer, std::uint64_t combinations);

/// The engines a results file may name in map.engines (docs/results-format.md): the sweep engines' names.
inline constexpr const char* kDirectEngine = "direct";
inline constexpr const char* kReplayEngine = "replay";

/// Everything about a results file except its numbers.
struct ResultsHeader {
  std::string version, commit;                 ///< occsweep that wrote it
  std::string grid_name, grid_hash;            ///< grid file and FNV-1a of its bytes
  std::string method;                          ///< the grid's method (docs/methods.md)
  /// The method's parameters as the maps' params hold them: from the registry, or, for a method this program has
  /// not registered, from the first map's keys in name order (results are readable without the method's code).
  ParameterLayout parameters;
  std::uint64_t grid_combinations = 0;
  SweepSelection selection;
  std::string dataset_name, dataset_hash;
  nlohmann::json point_cloud_set = nlohmann::json::object();  ///< the data set's `source`: its parameters
  MapSettings map;                             ///< what every map of the file shares ("map" in the file)
  std::string engine = "direct";
  /// Every engine that produced maps of this file, sorted: a sweep resumed under another engine, or merged shards
  /// of different engines, list both (and `engine` is then "mixed"). Files without the field: {engine}.
  std::vector<std::string> engines;
  /// Which truth voxels the counts count (docs/results-format.md, "Truth"); files without the field: full.
  TruthMode truth = TruthMode::Full;
  /// How much of the truth the scans observe and how far their points lie from it, at map.resolution and map.s_c
  /// (dataset.coverage, docs/results-format.md); none in files written before the field, or without truth.
  std::optional<TruthCoverage> coverage;
};

/// The point cloud set a results file is of: its `pcs_id` in the data set's source, "-" for a data set not
/// generated as one (an import, the built-in scene). compare and the export CSV name it alike.
[[nodiscard]] inline std::string pointCloudSetOf(const ResultsHeader& h) {
  return h.point_cloud_set.contains("pcs_id") ? h.point_cloud_set.at("pcs_id").dump() : "-";
}

struct ThresholdResult {
  std::uint64_t id = 0;  ///< the combination's stable id
  Fixed p_t = 0;
  ConfusionCounts counts;
};

struct MapResult {
  std::uint64_t map_index = 0;
  MapParams params;
  std::vector<ThresholdResult> thresholds;
  CurveArea area;
  double seconds = 0.0;
  /// Frees the thresholds, for a reader that keeps the rest (MapDetail::Summary): `thresholds = {}` or clear() keep
  /// their memory, 200 MB for `compare` of a 3.2 M-combination store.
  void dropThresholds() { std::vector<ThresholdResult>().swap(thresholds); }
};

struct ResultsFile {
  ResultsHeader header;
  std::vector<MapResult> maps;  ///< by map index
  bool complete = false;
  double seconds = 0.0;
  /// TP+FN of its maps: the truth's voxels it counts, the same for every map (0 with no map). Every reader sets
  /// it, also where maps are read without thresholds (results_store.hpp, MapDetail::Summary).
  std::uint64_t truth_voxels = 0;
};

/// True when two headers describe the same work (grid, data set, selection, map settings): what resuming and
/// merging require. Version, commit and engine may differ. `why` says the first difference.
[[nodiscard]] bool sameWork(const ResultsHeader& a, const ResultsHeader& b, bool compare_shard, std::string* why);

/// Records every engine that produced maps of the file (at least one): `engines` sorted, `engine` the one engine
/// or "mixed" (docs/results-format.md, "Provenance of the engine").
void setEngines(ResultsHeader& h, const std::set<std::string>& engines);

/// A finite number as a JSON number, NaN and infinities as null (JSON has no NaN): how every occsweep JSON output
/// writes a number that may be undefined.
[[nodiscard]] nlohmann::json finiteNumber(double v);

/// The settings every map shares as results files, plans and MAP.ot.json write them: {"resolution", "s_c",
/// "variant", "stats"} (kMapSettingNames).
[[nodiscard]] nlohmann::json toJson(const MapSettings& settings);
/// The settings read back from the object `j`; `fail(key, rule)` for a key missing, mistyped or out of range (it must
/// throw), with the rule in the words `results check` uses.
[[nodiscard]] MapSettings parseMapSettings(const nlohmann::json& j,
                                           const std::function<void(const std::string&, const std::string&)>& fail);

[[nodiscard]] nlohmann::json toJson(const ResultsHeader& h);
/// A map's parameters by name, as results files write them: integers (k) as integers, the rest as numbers.
[[nodiscard]] nlohmann::json toJson(const MapParams& params, const ParameterLayout& parameters);
[[nodiscard]] nlohmann::json toJson(const MapResult& m, const ParameterLayout& parameters);
[[nodiscard]] nlohmann::json toJson(const ResultsFile& f);

/// Parsers: std::runtime_error naming the file and the field for anything missing, mistyped or inconsistent
/// (counts that do not add up, TPR/FDR/AUC that do not match the counts: a file edited by hand).
[[nodiscard]] ResultsHeader parseHeader(const nlohmann::json& j, const std::string& file);
[[nodiscard]] MapResult parseMapResult(const nlohmann::json& j, const ParameterLayout& parameters, const std::string& file,
                                       const std::string& where);
[[nodiscard]] ResultsFile parseResults(const nlohmann::json& j, const std::string& file);
/// A results file of either format (JSON, or a store: results_store.hpp) whole in memory: for small results.
[[nodiscard]] ResultsFile readResults(const std::filesystem::path& file);

/// JSON, written to a temporary name beside `file` and renamed (writeFileAtomically).
void writeResults(const ResultsFile& f, const std::filesystem::path& file);
/// An occsweep results file of either format (sweep, merge).
[[nodiscard]] ReplaceableOutput resultsOutput();

/// Differences that matter between two results of the same work: any TP/FP/FN/TN, or an AUC further apart than
/// `auc_tolerance`. Timings, version and commit are ignored. Empty when they agree.
[[nodiscard]] std::vector<std::string> resultDifferences(const ResultsFile& expected, const ResultsFile& actual,
                                                         double auc_tolerance = 1e-12);

/// The map's numbers from its counts: curve area per docs/definitions.md, Confusion counts and AUC.
[[nodiscard]] CurveArea mapArea(const std::vector<ThresholdResult>& thresholds);

}  // namespace occsweep
