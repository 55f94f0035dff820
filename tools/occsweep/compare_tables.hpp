// The tables of `occsweep compare` beyond its terminal output (docs/statistics.md): the statistics against the
// baseline as text, and the whole comparison as CSV (best parameters as fields), Markdown and LaTeX.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "occsweep/sweeps/compare_statistics.hpp"
#include "occsweep/sweeps/results_file.hpp"

namespace occsweep::cli {

/// What every table is made of.
struct ComparisonTables {
  const std::vector<ComparisonRow>& rows;
  const std::vector<ResultsFile>& files;      ///< the results files, in the order of `names`
  const std::vector<std::string>& names;      ///< their paths as given
  const std::vector<std::string>& methods;    ///< the baseline first (compareStatistics' order)
  const std::vector<MethodStatistics>& statistics;  ///< empty when the baseline was not given
  std::string baseline;
  stats::VerdictRules rules{};  ///< alpha and the smallest effect the verdicts used (compare --alpha, --smallest-effect)
  /// What differs between the files compared with --allow-mixed (mixedSettings); empty otherwise. Every table then
  /// says so: a CSV column, and the tables' captions.
  std::vector<std::string> mixed{};
  /// Each row's unit of the tests (SampleUnits::of_row): the CSV's `unit` column.
  std::vector<std::string> units{};
  TruthMode truth;  ///< what every AUC is scored against (map.truth, one for all files: mixedTruths)
};

/// The results files compare and plot read: only complete files that pass every check of `results check`
/// (docs/results-format.md); std::runtime_error naming the file otherwise. A store read at MapDetail::Summary
/// (compare: no thresholds held) is checked against its grid map by map; its counts are `results check`'s.
[[nodiscard]] std::vector<ResultsFile> readChecked(const std::vector<std::string>& files, MapDetail detail);

/// Refuses (std::invalid_argument naming the file, the name and the character) a data set name of `files` (named by
/// `names`) with a character the --latex tables cannot show: pdflatex would stop on it. (A point cloud set is shown
/// by its number.)
void requireLatexCharacters(const std::vector<ResultsFile>& files, const std::vector<std::string>& names);

/// The statistics block printed after the table.
[[nodiscard]] std::string statisticsText(const ComparisonTables& t);
/// Every parameter of a best map, the grid's fixed ones too, in the method's order and to the 1e-6 grids keep:
/// "p_max=0.98 p_min=0.02 p_h=0.62 p_m=0.38". With the file's settings (resolution, s_c, variant, statistics,
/// truth), what `occsweep map` takes to rebuild it; `map --from FILE --best` takes them all from the file.
[[nodiscard]] std::string bestParametersText(const BestMap& best, const std::vector<ResultsFile>& files);
/// How wide compare's terminal output is at most.
inline constexpr std::size_t kTerminalColumns = 100;
/// `text`'s words on lines of at most `width` columns, each `indent` spaces in and ending in a newline (a word longer
/// than a line goes on over lines, cut where they end).
[[nodiscard]] std::string wrappedLines(const std::string& text, std::size_t indent, std::size_t width);
/// `text` exactly as it is (every space kept: a path, a name), on lines of at most `width` bytes, each `indent` spaces
/// in and ending in a newline, cut only between whole UTF-8 characters.
[[nodiscard]] std::string cutLines(const std::string& text, std::size_t indent, std::size_t width);
/// A best map's parameters as fields: {"p_h": 0.62, "p_m": 0.38, ...}.
[[nodiscard]] nlohmann::json parameterFields(const BestMap& best, const std::vector<ResultsFile>& files);
/// One line per set: data set, point cloud set, then per method its AUC, its improvement over the baseline in
/// percent, its file and each best parameter (METHOD.auc, METHOD.improvement_percent, METHOD.file, METHOD.p_h, ...).
[[nodiscard]] std::string csvTable(const ComparisonTables& t);
/// The per-set AUCs and the statistics as two Markdown tables.
[[nodiscard]] std::string markdownTables(const ComparisonTables& t);
/// The same as two LaTeX booktabs tables.
[[nodiscard]] std::string latexTables(const ComparisonTables& t);

}  // namespace occsweep::cli
