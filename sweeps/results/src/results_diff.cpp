// diffResults: a candidate results file against a golden one, field by field (docs/results-format.md, "Regression
// checks against a golden file").
#include "occsweep/sweeps/results_diff.hpp"

#include <charconv>
#include <cmath>
#include <set>
#include <unordered_map>

namespace occsweep {
namespace {

/// The shortest text that reads back as `v` ("NaN" for NaN): a difference in the 17th digit stays visible.
std::string exactText(double v) {
  if (std::isnan(v)) return "NaN";
  char buf[32];
  const auto end = std::to_chars(buf, buf + sizeof buf, v).ptr;
  return std::string(buf, end);
}

std::string fixedText(Fixed v) { return exactText(toDouble(v)); }

std::string groupText(const std::optional<SweepSelection::Group>& g) {
  if (!g) return "none";
  return std::to_string(g->index) + "/" + std::to_string(g->count) + " seed " + std::to_string(g->seed);
}

/// Adds a header row when the two values differ.
void compareField(std::vector<ResultsDifference>& out, const std::string& field, const std::string& a,
                  const std::string& b) {
  if (a != b) out.push_back({std::nullopt, std::nullopt, "", field, a, b});
}

bool aucWithin(double golden, double candidate, double tolerance) {
  if (std::isnan(golden) || std::isnan(candidate)) return std::isnan(golden) && std::isnan(candidate);
  return std::abs(golden - candidate) <= tolerance;
}

struct CandidateIndex {
  std::unordered_map<std::uint64_t, const MapResult*> maps;  ///< by map index
  std::unordered_map<std::uint64_t, const ThresholdResult*> thresholds;  ///< by combination id
};

CandidateIndex indexCandidate(const ResultsFile& candidate) {
  CandidateIndex index;
  for (const auto& m : candidate.maps) {
    index.maps[m.map_index] = &m;
    for (const auto& t : m.thresholds) index.thresholds[t.id] = &t;
  }
  return index;
}

/// The rows of one golden combination: missing, or its p_t and counts where they differ.
void compareCombination(std::vector<ResultsDifference>& out, const ResultsDifference& where,
                        const ThresholdResult& golden, const ThresholdResult* candidate, CountsCheck counts) {
  auto row = [&](const std::string& field, const std::string& a, const std::string& b) {
    ResultsDifference d = where;
    d.field = field, d.golden = a, d.candidate = b;
    out.push_back(std::move(d));
  };
  if (!candidate) return row("combination", "present", "missing");
  if (candidate->p_t != golden.p_t) row("p_t", fixedText(golden.p_t), fixedText(candidate->p_t));
  if (counts == CountsCheck::Ignored) return;
  const ConfusionCounts &g = golden.counts, &c = candidate->counts;
  if (g.tp != c.tp) row("tp", std::to_string(g.tp), std::to_string(c.tp));
  if (g.fp != c.fp) row("fp", std::to_string(g.fp), std::to_string(c.fp));
  if (g.fn != c.fn) row("fn", std::to_string(g.fn), std::to_string(c.fn));
  if (g.tn != c.tn) row("tn", std::to_string(g.tn), std::to_string(c.tn));
}

/// The rows of one golden map: its combinations, then (when the candidate holds the map) its parameters and AUCs.
void compareMap(std::vector<ResultsDifference>& out, const MapResult& golden, const CandidateIndex& index,
                const ParameterLayout& method, double auc_tolerance, CountsCheck counts) {
  for (const auto& t : golden.thresholds) {
    const auto found = index.thresholds.find(t.id);
    const ResultsDifference where{golden.map_index, t.id, combinationText(golden.params, method, t.p_t), "", "", ""};
    compareCombination(out, where, t, found == index.thresholds.end() ? nullptr : found->second, counts);
  }
  const auto found = index.maps.find(golden.map_index);
  if (found == index.maps.end()) return;
  const MapResult& candidate = *found->second;
  const std::string text = combinationText(golden.params, method, std::nullopt);
  auto row = [&](const std::string& field, const std::string& a, const std::string& b) {
    out.push_back({golden.map_index, std::nullopt, text, field, a, b});
  };
  const std::string candidate_text = combinationText(candidate.params, method, std::nullopt);
  if (candidate_text != text) row("params", text, candidate_text);
  if (!aucWithin(golden.area.anchored, candidate.area.anchored, auc_tolerance))
    row("auc.anchored", exactText(golden.area.anchored), exactText(candidate.area.anchored));
  if (!aucWithin(golden.area.observed, candidate.area.observed, auc_tolerance))
    row("auc.observed", exactText(golden.area.observed), exactText(candidate.area.observed));
}

/// Combinations of the candidate that the golden file does not hold.
void listExtras(std::vector<ResultsDifference>& out, const ResultsFile& golden, const ResultsFile& candidate) {
  std::set<std::uint64_t> golden_ids;
  for (const auto& m : golden.maps)
    for (const auto& t : m.thresholds) golden_ids.insert(t.id);
  for (const auto& m : candidate.maps)
    for (const auto& t : m.thresholds)
      if (!golden_ids.count(t.id))
        out.push_back({m.map_index, t.id, combinationText(m.params, candidate.header.parameters, t.p_t), "combination",
                       "missing", "present"});
}

}  // namespace

std::vector<ResultsDifference> incomparableHeaderFields(const ResultsHeader& a, const ResultsHeader& b,
                                                        bool compare_shard) {
  std::vector<ResultsDifference> out;
  compareField(out, "grid.name", a.grid_name, b.grid_name);
  compareField(out, "grid.file_hash", a.grid_hash, b.grid_hash);
  compareField(out, "dataset.name", a.dataset_name, b.dataset_name);
  compareField(out, "dataset.content_hash", a.dataset_hash, b.dataset_hash);
  compareField(out, "selection.group", groupText(a.selection.group), groupText(b.selection.group));
  if (compare_shard) {
    compareField(out, "selection.shard.index", std::to_string(a.selection.shard_index),
                 std::to_string(b.selection.shard_index));
    compareField(out, "selection.shard.count", std::to_string(a.selection.shard_count),
                 std::to_string(b.selection.shard_count));
  }
  compareField(out, "map.resolution", exactText(a.map.resolution), exactText(b.map.resolution));
  compareField(out, "map.s_c", exactText(a.map.s_c), exactText(b.map.s_c));
  compareField(out, "map.variant", toText(a.map.variant), toText(b.map.variant));
  compareField(out, "map.stats", toText(a.map.stats), toText(b.map.stats));
  compareField(out, "map.truth", truthModeName(a.truth), truthModeName(b.truth));
  return out;
}

std::string combinationText(const MapParams& p, const ParameterLayout& parameters, std::optional<Fixed> p_t) {
  std::string text;
  for (std::size_t i = 0; i < parameters.names.size() && i < p.values.size(); ++i)
    text += (text.empty() ? "" : " ") + parameters.names[i] + "=" +
            (parameters.integer[i] ? std::to_string(p.values[i] / kFixedScale) : fixedText(p.values[i]));
  if (p_t) text += " p_t=" + fixedText(*p_t);
  return text;
}

ResultsDiff diffResults(const ResultsFile& golden, const ResultsFile& candidate, double auc_tolerance,
                        CountsCheck counts) {
  ResultsDiff diff;
  diff.golden_maps = golden.maps.size();
  for (const auto& m : golden.maps) diff.golden_combinations += m.thresholds.size();
  diff.header = incomparableHeaderFields(golden.header, candidate.header, true);
  if (!diff.header.empty()) return diff;
  const CandidateIndex index = indexCandidate(candidate);
  for (const auto& m : golden.maps)
    compareMap(diff.combinations, m, index, golden.header.parameters, auc_tolerance, counts);
  listExtras(diff.combinations, golden, candidate);
  return diff;
}

// The differences as lines: what tests and `results diff` callers print.
std::vector<std::string> resultDifferences(const ResultsFile& expected, const ResultsFile& actual,
                                           double auc_tolerance) {
  const ResultsDiff diff = diffResults(expected, actual, auc_tolerance);
  std::vector<std::string> out;
  for (const auto& d : diff.header)
    out.push_back("header: " + d.field + " " + d.candidate + ", expected " + d.golden);
  for (const auto& d : diff.combinations) {
    std::string where = d.map_index ? "map " + std::to_string(*d.map_index) : std::string("extra");
    if (d.id) where += ", id " + std::to_string(*d.id);
    out.push_back(where + " (" + d.combination + "): " + d.field + " " + d.candidate + ", expected " + d.golden);
  }
  return out;
}

}  // namespace occsweep
