// A results file of either format exported as JSON or CSV, streamed map by map (docs/results-format.md, "Export").
#pragma once

#include <filesystem>
#include <ostream>

namespace occsweep {

/// Writes a results file's JSON form to `out` map by map, byte for byte what writeResults writes for the same
/// results (the export of a store, however large, in memory bounded by one map). Both exports read the file once
/// with every check of `results check` (readCheckedResults) and throw on the first failure, part-way through `out`.
void exportJson(const std::filesystem::path& file, std::ostream& out);
/// One CSV row per combination: the file's data set, its content hash, method, grid and truth, then id, map_index,
/// the method's parameters, p_t, TP, FP, FN, TN, TPR, FDR, and the map's anchored and observed AUC; numbers as every
/// CSV of occsweep's (csv_text.hpp; docs/results-format.md, "Export").
void exportCsv(const std::filesystem::path& file, std::ostream& out);

}  // namespace occsweep
