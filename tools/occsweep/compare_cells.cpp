// The cells of compare's tables (compare_cells.hpp): every format is made from the same cells.
#include "compare_cells.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "method_style.hpp"
#include "occsweep/eval/truth_coverage.hpp"

namespace occsweep::cli {
namespace {

std::string intervalText(const std::optional<stats::BootstrapInterval>& interval) {
  if (!interval) return "-";
  const auto& i = *interval;
  return cell(i.estimate, "%+.2f") + " [" + cell(i.lower, "%+.2f") + ", " + cell(i.upper, "%+.2f") + "]";
}

std::string crossValidatedText(const CrossValidated& c) {
  return c.groups ? cell(c.score, "%.4f") + " (gap " + cell(c.gap, "%.4f") + ")" : "-";
}

std::string budgetText(const BudgetSummary& b) {
  if (!b.maps) return "-";
  return cell(b.expected_best_at_budget, "%.4f") + " at " + std::to_string(b.budget) + " maps; " +
         (b.first_above_baseline ? "passes at " + std::to_string(*b.first_above_baseline) + " of "
                                 : std::string("does not pass within ")) +
         std::to_string(b.maps);
}

std::string testText(const DatasetComparison& c) {
  if (!c.test) return "-";
  return cell(c.test->p_value, "%.3g") + " (Holm " + cell(c.holm_p, "%.3g") + ")";
}

// "60 (20)": sets and data sets; "60 (20 over 10 scenes)" where provenance grouped the data sets into scenes.
std::string sampleCell(const MethodStatistics& s) {
  const bool scenes = s.optima.unit_name != "data sets";
  return std::to_string(s.sets) + " (" + std::to_string(s.datasets) +
         (scenes ? " over " + std::to_string(s.scenes) + (s.scenes == 1 ? " scene" : " " + s.optima.unit_name) : "") +
         ")";
}

// Where the method's results hold a map scoring the baseline's best AUC exactly (found from the maps, not the
// names), its optimum there is at least the baseline's: a tie at the optimum is no evidence, and where that holds on
// every set the optima verdict cannot be a loss; the cross-validated verdict can.
std::string nestingText(const MethodStatistics& s) {
  auto of = [&](std::size_t n) { return std::to_string(n) + " of " + std::to_string(s.sets); };
  std::string text = s.method + ": on " + of(s.sets_holding_baseline_best) + " sets its results hold a map "
                     "scoring the baseline's best AUC exactly, so its optimum there is at least the baseline's; "
                     "better on " + of(s.better) + ", equal on " + of(s.ties) + ", worse on " + of(s.worse);
  if (s.sets_holding_baseline_best == s.sets)
    text += " (on every set: the optima verdict cannot be a loss; the cross-validated one can)";
  return text;
}

// The optima over units as the verdict rests on them: where grids nest, the units that do not (docs/statistics.md,
// "Grids that nest"), so no p or interval beside "not a test of the method" comes from the nested units.
const DatasetComparison& verdictSample(const MethodStatistics& s) {
  return s.optima_not_nested ? *s.optima_not_nested : s.optima;
}

std::string verdictSampleText(const MethodStatistics& s, const std::string& text) {
  if (!s.optima_not_nested || text == "-") return text;
  return text + " (" + std::to_string(s.optima_not_nested->per_dataset.size()) + " not nesting)";
}

}  // namespace

// A number occsweep prints is either right or not printed (docs/robustness.md): "-" where there is none.
std::string cell(double v, const char* format) {
  if (!std::isfinite(v)) return "-";
  char buf[48];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

// The verdicts over their unit, the scene or the data set (docs/statistics.md, "Verdicts"): every header that counts
// or holds out units names it; the per-set interval stays as description.
Cells statisticsCells(const std::vector<MethodStatistics>& statistics, const std::string& baseline) {
  const std::string units = statistics.front().optima.unit_name, unit = units.substr(0, units.size() - 1);
  std::string hyphenated = unit;
  std::replace(hyphenated.begin(), hyphenated.end(), ' ', '-');
  Cells c{{"method", units == "data sets" ? "sets (data sets)" : "sets (data sets over " + units + ")",
           "better/worse/tie", "holds " + baseline + "'s best", "improvement % over sets [95% CI]", "over " + units,
           "exact test over " + units + ": p (Holm)", "per-set optimum", "leave-one-set-out (gap)",
           "leave-one-" + hyphenated + "-out (gap)", "cross-validated improvement % (by " + unit + ")",
           "leave-one-set-out improvement % (optimistic)", "budget: expected best (vs " + baseline + "'s best)",
           "verdict (optima)", "verdict (cross-validated)"}};
  for (const MethodStatistics& s : statistics) {
    const bool base = s.is_baseline;
    c.push_back({s.method, sampleCell(s),
                 base ? "-" : std::to_string(s.better) + "/" + std::to_string(s.worse) + "/" + std::to_string(s.ties),
                 base ? "-" : std::to_string(s.sets_holding_baseline_best) + " of " + std::to_string(s.sets),
                 intervalText(s.improvement_percent), verdictSampleText(s, intervalText(verdictSample(s).interval)),
                 base ? "-" : verdictSampleText(s, testText(verdictSample(s))),
                 cell(s.mean_best_auc, "%.4f"), crossValidatedText(s.leave_one_set_out),
                 crossValidatedText(s.leave_one_dataset_out), intervalText(s.cross_validated.interval),
                 intervalText(s.leave_one_set_out_improvement), base ? "-" : budgetText(s.budget),
                 base ? "baseline" : s.optima.verdict.text, base ? "baseline" : s.cross_validated.verdict.text});
  }
  return c;
}

// Each verdict with its sample, test and correction, one line each, and last which verdicts Holm's correction
// ran over together (docs/statistics.md, "Verdicts").
std::vector<std::string> verdictBases(const std::vector<MethodStatistics>& statistics) {
  std::vector<std::string> lines;
  std::string families;
  for (const MethodStatistics& s : statistics) {
    if (s.is_baseline) continue;
    for (const auto& [what, c] : {std::pair<const char*, const DatasetComparison&>{"optima", s.optima},
                                  {s.cross_validated.unit_name == "scenes" ? "cross-validated by scene"
                                                                           : "cross-validated by data set",
                                   s.cross_validated}})
      lines.push_back(s.method + ", " + what + ": " + c.verdict.text +
                      (c.verdict.basis.empty() ? "" : ": " + c.verdict.basis));
    if (s.sets_holding_baseline_best) lines.push_back(nestingText(s));
    if (families.empty())
      families = "Holm families, each corrected by itself: " + s.optima.holm_family + "; " +
                 s.cross_validated.holm_family;
  }
  if (!families.empty()) lines.push_back(families);
  return lines;
}

// Per set: the data set, its point cloud set, each method's AUC and (but the baseline) its improvement.
Cells perSetCells(const ComparisonTables& t) {
  Cells c{{"data set", "pcs"}};
  for (const std::string& m : t.methods) {
    c[0].push_back(m + " AUC");
    if (m != t.baseline) c[0].push_back(m + " vs " + t.baseline + " %");
  }
  for (const ComparisonRow& row : t.rows) {
    std::vector<std::string> line{row.dataset, row.point_cloud_set};
    for (const std::string& m : t.methods) {
      const auto best = row.best(m);
      line.push_back(best ? cell(best->auc, "%.4f") : "-");
      if (m != t.baseline) line.push_back(cell(row.improvementPercent(m, t.baseline), "%+.2f"));
    }
    c.push_back(std::move(line));
  }
  return c;
}

// `c` with every method name in it (a row's first cell, a word of a header: "knn AUC", "holds octomap's best")
// shown by its display name. Data set names, which a user chooses, are cells of their own and stay as they are.
Cells withDisplayNames(Cells c, const std::vector<std::string>& methods, std::size_t name_columns) {
  for (std::size_t r = 0; r < c.size(); ++r)
    for (std::size_t i = r == 0 ? 0 : name_columns; i < c[r].size(); ++i) {
      std::istringstream words(c[r][i]);
      std::string shown, word;
      while (words >> word) {
        const std::size_t end = word.find_last_not_of(",;:") + 1;  // punctuation after a name stays after it
        const std::string bare = word.substr(0, end), after = word.substr(end);
        for (const std::string& m : methods)
          if (bare == m || bare == m + "'s") word = displayNameOf(m) + bare.substr(m.size()) + after;
        shown += (shown.empty() ? "" : " ") + word;
      }
      if (!shown.empty()) c[r][i] = shown;
    }
  return c;
}

// One line of text (a verdict's basis) with the methods by their display names, as the tables show them.
std::string withDisplayNames(const std::string& line, const std::vector<std::string>& methods) {
  return withDisplayNames(Cells{{line}}, methods, 0)[0][0];
}

// The first that did: the files of one row share a data set, resolution and s_c (docs/import.md, "Truth coverage
// and alignment").
std::string coverageWarningOf(const ComparisonRow& r, const std::vector<ResultsFile>& in) {
  for (const auto& [method, files] : r.files_of)
    for (std::size_t f : files)
      if (const ResultsHeader& h = in[f].header; h.coverage) return coverageWarning(*h.coverage, h.truth);
  return "";
}

std::string truthLine(TruthMode truth) {
  return std::string("truth: ") + truthModeName(truth) +
         (truth == TruthMode::Full ? " (every truth voxel of the region counts)"
                                   : " (only truth voxels observable from the scan origins count)");
}

// Under every table what the terminal says of the truth: a table pasted into a paper without its warnings would hide
// that its AUCs measure the recording's coverage or a misalignment, not the mapping (docs/statistics.md, "In
// occsweep compare"). A warning shared by a data set's point cloud sets is said once.
std::vector<std::string> truthNotes(const ComparisonTables& t) {
  std::vector<std::string> notes{truthLine(t.truth)};
  for (const ComparisonRow& row : t.rows)
    if (const std::string why = coverageWarningOf(row, t.files); !why.empty()) {
      const std::string note = "warning: " + row.dataset + ": " + why;
      if (std::find(notes.begin(), notes.end(), note) == notes.end()) notes.push_back(note);
    }
  return notes;
}

// Said before every table of a comparison made with --allow-mixed: its numbers do not compare like with like.
std::string mixedNote(const ComparisonTables& t) {
  if (t.mixed.empty()) return "";
  return "Mixed settings (compare --allow-mixed): the files differ in " + std::to_string(t.mixed.size()) +
         (t.mixed.size() == 1 ? " way" : " ways") + " (the comparison's JSON lists them, under mixed), so these numbers "
         "do not compare like with like. ";
}

}  // namespace occsweep::cli
