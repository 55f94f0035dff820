// The cells every table of `occsweep compare` is made from (compare_tables.hpp): the statistics and the per-set
// results as rows of text, each verdict's basis, and the methods by their display names.
#pragma once

#include <string>
#include <vector>

#include "compare_tables.hpp"

namespace occsweep::cli {

using Cells = std::vector<std::vector<std::string>>;  ///< a header line, then the body

/// `v` printed by `format`, or "-" where it is not finite.
[[nodiscard]] std::string cell(double v, const char* format);
/// A row per method, a column per statistic; the headers name the verdicts' unit (scenes, or data sets).
[[nodiscard]] Cells statisticsCells(const std::vector<MethodStatistics>& statistics, const std::string& baseline);
/// A row per set: its data set, point cloud set, each method's AUC and (but the baseline) its improvement.
[[nodiscard]] Cells perSetCells(const ComparisonTables& t);
/// Each verdict with its basis, a line each, the grids that nest, and last the Holm families.
[[nodiscard]] std::vector<std::string> verdictBases(const std::vector<MethodStatistics>& statistics);
/// `c` with the method names in it by their display names, from column `name_columns` on (all of the header).
[[nodiscard]] Cells withDisplayNames(Cells c, const std::vector<std::string>& methods, std::size_t name_columns);
/// One line (a verdict's basis) with the methods by their display names.
[[nodiscard]] std::string withDisplayNames(const std::string& line, const std::vector<std::string>& methods);
/// The warning of truth coverage or alignment the row's results files recorded (coverageWarning); "" when none.
[[nodiscard]] std::string coverageWarningOf(const ComparisonRow& r, const std::vector<ResultsFile>& in);
/// "truth: full (every truth voxel of the region counts)", or observable's: what the AUCs are scored against.
[[nodiscard]] std::string truthLine(TruthMode truth);
/// The notes under every table: truthLine, then "warning: DATA SET: " each row's coverage warning (once each).
[[nodiscard]] std::vector<std::string> truthNotes(const ComparisonTables& t);
/// What every table of a comparison made with --allow-mixed begins with; "" otherwise.
[[nodiscard]] std::string mixedNote(const ComparisonTables& t);

}  // namespace occsweep::cli
