// Grids that nest (compare_nesting.hpp, docs/statistics.md "Grids that nest"). A unit every set of which holds the
// baseline's best has a difference >= 0 by construction: it is no evidence about the method, so the optima verdict
// rests on the other units, under the same rules and in the same Holm family.
#include "compare_nesting.hpp"

#include <algorithm>
#include <map>
#include <optional>

namespace occsweep::nesting {
namespace {

// Whether a result of `method` for this row holds a map scoring the baseline's best exactly (to the last bit).
bool holdsBaselineBest(const ComparisonRow& row, const std::vector<ResultsFile>& files, const std::string& method,
                       const BestMap& baseline_best) {
  for (const std::size_t f : row.files_of.at(method))
    for (const MapResult& m : files[f].maps)
      if (m.area.anchored == baseline_best.auc && m.area.observed == baseline_best.observed) return true;
  return false;
}

}  // namespace

Nesting nestingOf(const std::vector<ComparisonRow>& rows, const std::vector<ResultsFile>& files,
                  const std::string& method, const std::string& baseline,
                  const std::vector<std::string>& unit_of_row) {
  Nesting n;
  std::map<std::string, bool> every_set_holds;
  for (std::size_t r = 0; r < rows.size(); ++r) {
    const auto m = rows[r].best(method), b = rows[r].best(baseline);
    if (!m || !b) continue;
    const bool holds = holdsBaselineBest(rows[r], files, method, *b);
    n.sets += holds;
    const auto [it, fresh] = every_set_holds.try_emplace(unit_of_row[r], holds);
    if (!fresh) it->second = it->second && holds;
  }
  for (const auto& [unit, holds] : every_set_holds)
    if (holds) n.units.insert(unit);
  return n;
}

stats::Verdict nestedVerdict(const stats::Verdict& kept, const stats::Verdict& over_all, std::size_t units,
                             std::size_t nested, const std::string& unit_name, const std::string& baseline) {
  if (over_all.kind == stats::VerdictKind::TooFew) return over_all;  // every unit cannot tell: nor can fewer
  const std::size_t other = units - nested;
  const std::string counts = std::to_string(nested) + " of " + std::to_string(units);
  if (kept.kind == stats::VerdictKind::TooFew) {
    const std::string rest =
        other == 0 ? "" : "; the other " + std::to_string(other) + (other == 1 ? " is" : " are") + " too few to tell";
    return {stats::VerdictKind::NotComputed, std::nullopt,
            "at least the baseline by construction (holds " + baseline + "'s best on all sets of " + counts + " " +
                unit_name + rest + "): not a test of the method",
            over_all.basis};
  }
  stats::Verdict v = kept;  // "gain", "negligible median difference (...)", "gain, below the smallest effect ..."
  const std::size_t word_ends = std::min({v.text.find(" ("), v.text.find(','), v.text.size()});
  v.text.insert(word_ends, " over the " + std::to_string(other) + " " + unit_name + " where the grids do not nest, " +
                               counts + " holding " + baseline + "'s best on all their sets");
  return v;
}

}  // namespace occsweep::nesting
