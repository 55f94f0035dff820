// Results files (SPEC §5): what a sweep measured, with everything needed to trust and repeat it.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "occsweep/eval/confusion.hpp"
#include "occsweep/eval/curve.hpp"
#include "occsweep/eval/observable_truth.hpp"
#include "occsweep/eval/output_file.hpp"
#include "grid.hpp"

namespace occsweep {

/// Which part of a grid a file covers: optionally one Eq. 16 group of ids, then one contiguous block of the
/// selected maps.
struct SweepSelection {
  struct Group {
    std::uint64_t index = 0, count = 1, seed = 0;
    friend bool operator==(const Group&, const Group&) = default;
  };
  std::optional<Group> group;
  std::uint64_t shard_index = 0, shard_count = 1;
  friend bool operator==(const SweepSelection&, const SweepSelection&) = default;
};

/// Everything about a results file except its numbers.
struct ResultsHeader {
  std::string version, commit;                 ///< occsweep that wrote it
  std::string grid_name, grid_hash;            ///< grid file and FNV-1a of its bytes
  GridMethod method = GridMethod::Knn;
  std::uint64_t grid_combinations = 0;
  SweepSelection selection;
  std::string dataset_name, dataset_hash;
  nlohmann::json point_cloud_set = nlohmann::json::object();  ///< the data set's `source`: its parameters
  double resolution = 0.1, s_c = 4.0;
  std::string variant = "default", stats = "batch", engine = "direct";
  /// Every engine that produced maps of this file, sorted: a sweep resumed under another engine, or merged shards
  /// of different engines, list both (and `engine` is then "mixed"). Files without the field: {engine}.
  std::vector<std::string> engines;
  /// Which truth voxels the counts count (docs/results-format.md, "Truth"); files without the field: full.
  TruthMode truth = TruthMode::Full;
};

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
};

struct ResultsFile {
  ResultsHeader header;
  std::vector<MapResult> maps;  ///< by map index
  bool complete = false;
  double seconds = 0.0;
};

/// True when two headers describe the same work (grid, data set, selection, map settings): what resuming and
/// merging require. Version, commit and engine may differ. `why` says the first difference.
[[nodiscard]] bool sameWork(const ResultsHeader& a, const ResultsHeader& b, bool compare_shard, std::string* why);

[[nodiscard]] nlohmann::json toJson(const ResultsHeader& h);
[[nodiscard]] nlohmann::json toJson(const MapResult& m, GridMethod method);
[[nodiscard]] nlohmann::json toJson(const ResultsFile& f);

/// Parsers: std::runtime_error naming the file and the field for anything missing, mistyped or inconsistent
/// (counts that do not add up, TPR/FDR/AUC that do not match the counts: a file edited by hand).
[[nodiscard]] ResultsHeader parseHeader(const nlohmann::json& j, const std::string& file);
[[nodiscard]] MapResult parseMapResult(const nlohmann::json& j, GridMethod method, const std::string& file,
                                       const std::string& where);
[[nodiscard]] ResultsFile parseResults(const nlohmann::json& j, const std::string& file);
[[nodiscard]] ResultsFile readResults(const std::filesystem::path& file);

/// Written to a temporary name beside `file` and renamed (writeFileAtomically).
void writeResults(const ResultsFile& f, const std::filesystem::path& file);
void writeJsonAtomically(const nlohmann::json& j, const std::filesystem::path& file);

/// A JSON file whose "format" field is `format`: occsweep's own output of that kind, which --force may replace.
[[nodiscard]] ReplaceableOutput jsonOutput(const std::string& name, const std::string& format);
/// An occsweep results file (sweep, merge).
[[nodiscard]] ReplaceableOutput resultsOutput();

/// Differences that matter between two results of the same work: any TP/FP/FN/TN, or an AUC further apart than
/// `auc_tolerance`. Timings, version and commit are ignored. Empty when they agree.
[[nodiscard]] std::vector<std::string> resultDifferences(const ResultsFile& expected, const ResultsFile& actual,
                                                         double auc_tolerance = 1e-12);

/// The map's numbers from its counts: curve area per SPEC §2.
[[nodiscard]] CurveArea mapArea(const std::vector<ThresholdResult>& thresholds);

}  // namespace occsweep
