// The statistics of a comparison (compare_statistics.hpp, docs/statistics.md), from the rows compareBest makes and
// the results files they come from.
#include "occsweep/sweeps/compare_statistics.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <set>
#include <stdexcept>

#include "occsweep/stats/budget_curve.hpp"
#include "occsweep/stats/cross_validation.hpp"
#include "occsweep/stats/multiple_testing.hpp"
#include "compare_nesting.hpp"

namespace occsweep {
namespace {

// Every map's anchored AUC of the file a row's best came from, by map index; none when a map's AUC is undefined.
std::optional<std::vector<double>> mapAucs(const ResultsFile& f) {
  std::vector<double> out;
  for (const MapResult& m : f.maps) {
    if (!std::isfinite(m.area.anchored)) return std::nullopt;
    out.push_back(m.area.anchored);
  }
  return out;
}

// One method's AUC table: per set with a best map, every map's AUC; all sets must come from one grid.
struct AucTable {
  std::vector<std::vector<double>> per_set;
  std::vector<std::string> dataset;  ///< the data set of each set (for leave-one-data-set-out)
  std::vector<std::size_t> row;      ///< the row of each set
  bool one_grid = true;
};

AucTable aucTable(const std::vector<ComparisonRow>& rows, const std::vector<ResultsFile>& files,
                  const std::string& method, const std::vector<std::string>& units) {
  AucTable t;
  std::set<std::string> grids;
  for (const ComparisonRow& row : rows) {
    const std::optional<BestMap> best = row.best(method);
    if (!best) continue;
    const ResultsFile& f = files[best->file];
    grids.insert(f.header.grid_hash);
    const auto aucs = mapAucs(f);
    if (!aucs) return {{}, {}, {}, false};
    t.per_set.push_back(*aucs);
    t.dataset.push_back(units[std::size_t(&row - rows.data())]);
    t.row.push_back(std::size_t(&row - rows.data()));
  }
  t.one_grid = grids.size() == 1;
  return t;
}

// At least 2 groups, each with the same combinations (leaveOneGroupOut's table).
bool rectangular(const std::vector<std::vector<double>>& groups) {
  if (groups.size() < 2) return false;
  for (const auto& g : groups)
    if (g.size() != groups.front().size() || g.empty()) return false;
  return true;
}

CrossValidated crossValidated(const std::vector<std::vector<double>>& groups) {
  if (!rectangular(groups)) return {};
  const stats::LeaveOneGroupOut cv = stats::leaveOneGroupOut(groups);
  return {groups.size(), cv.mean_optimum, cv.mean_cv_score, cv.mean_gap};
}

// Leave one data set out: a data set's AUC of a map is the mean over its sets.
std::vector<std::vector<double>> perDataset(const AucTable& t) {
  std::map<std::string, std::pair<std::vector<double>, std::size_t>> sums;
  std::vector<std::string> order;
  for (std::size_t i = 0; i < t.per_set.size(); ++i) {
    auto [it, fresh] = sums.try_emplace(t.dataset[i], std::vector<double>(t.per_set[i].size(), 0.0), 0);
    if (fresh) order.push_back(t.dataset[i]);
    if (it->second.first.size() != t.per_set[i].size()) return {};
    for (std::size_t c = 0; c < t.per_set[i].size(); ++c) it->second.first[c] += t.per_set[i][c];
    ++it->second.second;
  }
  std::vector<std::vector<double>> out;
  for (const auto& name : order) {
    auto [sum, n] = sums.at(name);
    for (double& v : sum) v /= double(n);
    out.push_back(sum);
  }
  return out;
}

// The mean over sets of each budget's expected best (every set's grid of the same size), and where it passes the
// baseline's mean best.
std::vector<double> meanCurve(const AucTable& t, std::size_t max_maps) {
  if (!t.one_grid || t.per_set.empty() || t.per_set.front().size() > max_maps) return {};
  const std::size_t maps = t.per_set.front().size();
  for (const auto& aucs : t.per_set)  // one grid but other selections (Eq. 16 groups): no common budget axis
    if (aucs.size() != maps) return {};
  std::vector<double> mean_curve(maps, 0.0);
  for (const auto& aucs : t.per_set) {
    const std::vector<double> curve = stats::expectedBestCurve(aucs);
    for (std::size_t n = 0; n < maps; ++n) mean_curve[n] += curve[n] / double(t.per_set.size());
  }
  return mean_curve;
}

BudgetSummary budgetSummary(const AucTable& t, std::size_t budget, double baseline_best, std::size_t max_maps) {
  const std::vector<double> mean_curve = meanCurve(t, max_maps);
  if (mean_curve.empty() || budget == 0) return {};
  const std::size_t maps = mean_curve.size();
  BudgetSummary b;
  b.maps = maps;
  b.budget = budget;
  b.expected_best_at_budget = mean_curve[std::min(budget, maps) - 1];
  if (const auto first = stats::firstBudgetAbove(mean_curve, baseline_best)) b.first_above_baseline = *first;
  return b;
}

// The same sets of a method and of the baseline, paired: their AUCs (per-set optima), units and data sets.
struct PairedSets {
  std::vector<double> method, baseline;
  std::vector<std::string> dataset;  ///< the unit (scene) of each set
  std::set<std::string> datasets;    ///< the data sets, by unit and name
};

// Sorted first, so that the interval depends on the values and the seed, not on the order the files were given in.
std::optional<stats::BootstrapInterval> meanInterval(std::vector<double> values, const CompareStatisticsOptions& o) {
  if (values.size() < 2) return std::nullopt;
  std::sort(values.begin(), values.end());
  return stats::bootstrapMeanInterval(values, {o.level, o.resamples, o.seed, stats::BootstrapMethod::BCa});
}

// Each data set's mean of its sets' values, in data-set name order.
struct PerDataset {
  std::vector<std::string> names;
  std::vector<double> values;
};

PerDataset perDatasetMeans(const std::vector<double>& values, const std::vector<std::string>& dataset) {
  std::map<std::string, std::pair<double, std::size_t>> sums;
  for (std::size_t i = 0; i < values.size(); ++i) {
    auto& [sum, n] = sums[dataset[i]];
    sum += values[i], ++n;
  }
  PerDataset out;
  for (const auto& [name, v] : sums) out.names.push_back(name), out.values.push_back(v.first / double(v.second));
  return out;
}

// A comparison over data sets (or scenes), up to Holm's correction (applied over the family by decideFamily).
void overDatasets(PerDataset per_dataset, const CompareStatisticsOptions& o, DatasetComparison& c) {
  c.datasets = std::move(per_dataset.names);
  c.per_dataset = std::move(per_dataset.values);
  c.interval = meanInterval(c.per_dataset, o);
  if (std::any_of(c.per_dataset.begin(), c.per_dataset.end(), [](double v) { return v != 0.0; }))
    c.test = stats::exactPairedTest(c.per_dataset);
}

// The paired description over sets, and the comparison of the optima over data sets.
void pairedTests(const PairedSets& p, const CompareStatisticsOptions& o, MethodStatistics& s) {
  std::vector<double> differences, improvement;
  std::vector<std::string> dataset;
  for (std::size_t i = 0; i < p.method.size(); ++i) {
    const double d = p.method[i] - p.baseline[i];
    differences.push_back(d);
    if (p.baseline[i] > 0) improvement.push_back(d / p.baseline[i] * 100.0), dataset.push_back(p.dataset[i]);
    (d > 0 ? s.better : (d < 0 ? s.worse : s.ties))++;
  }
  s.sets = differences.size();
  if (differences.empty()) return;
  s.effect = stats::pairedEffectSize(differences);
  s.sign = stats::signTest(differences);
  if (s.better + s.worse > 0) s.wilcoxon = stats::wilcoxonSignedRank(differences);
  s.improvement_percent = meanInterval(improvement, o);
  overDatasets(perDatasetMeans(improvement, dataset), o, s.optima);
}

// Per held-out group, the method's cross-validated score against the baseline's, in percent of the baseline's
// (groups where the baseline scores 0 have no percentage and are left out).
PerDataset heldOutImprovement(const std::vector<std::vector<double>>& mine, const std::vector<std::vector<double>>& base,
                              const std::vector<std::string>& names) {
  const stats::LeaveOneGroupOut m = stats::leaveOneGroupOut(mine), b = stats::leaveOneGroupOut(base);
  PerDataset out;
  for (std::size_t i = 0; i < m.groups.size(); ++i)
    if (b.groups[i].cv_score > 0) {
      out.names.push_back(names.empty() ? std::to_string(i) : names[i]);
      out.values.push_back((m.groups[i].cv_score - b.groups[i].cv_score) / b.groups[i].cv_score * 100.0);
    }
  return out;
}

// The data sets of a table in order of first appearance (perDataset's group order).
std::vector<std::string> datasetOrder(const AucTable& t) {
  std::vector<std::string> order;
  std::set<std::string> seen;
  for (const std::string& d : t.dataset)
    if (seen.insert(d).second) order.push_back(d);
  return order;
}

// Both methods on the same sets of one grid each, every AUC defined: what cross-validation needs.
bool crossValidatable(const AucTable& mine, const AucTable& base) {
  return mine.one_grid && base.one_grid && mine.row == base.row && rectangular(mine.per_set) &&
         rectangular(base.per_set);
}

// Leave one unit (scene) out (the verdict's basis) and leave one set out (optimistic: siblings share a scene).
void crossValidatedImprovements(const AucTable& mine, const AucTable& base, const CompareStatisticsOptions& o,
                                MethodStatistics& s) {
  if (s.scenes < 2) {
    s.cross_validated.not_computed = "too few " + s.cross_validated.unit_name + " to tell (n = " +
                                     std::to_string(s.scenes) + "; holding one out needs at least 2)";
    return;
  }
  if (!crossValidatable(mine, base)) {
    s.cross_validated.not_computed = "not computed (the sets differ in grid or maps, or an AUC is undefined)";
    return;
  }
  s.leave_one_set_out_improvement = meanInterval(heldOutImprovement(mine.per_set, base.per_set, {}).values, o);
  overDatasets(heldOutImprovement(perDataset(mine), perDataset(base), datasetOrder(mine)), o, s.cross_validated);
}

}  // namespace

// Holm's correction over the family of comparisons with the baseline (one p-value each; 1 where there is no
// test or no evidence, which keeps the correction conservative: docs/statistics.md, "Verdicts"), then each verdict.
void decideFamily(const std::vector<DatasetComparison*>& family, const std::string& family_text,
                  const CompareStatisticsOptions& o, const char* unit_name, const char* value_unit) {
  std::vector<double> p, smallest_p, smallest_p_of_units;
  for (const DatasetComparison* c : family) {
    p.push_back(c->test ? c->test->p_value : 1.0);
    smallest_p.push_back(c->test && c->not_computed.empty() ? c->test->smallest_possible_p : 1.0);
    smallest_p_of_units.push_back(c->not_computed.empty() ? stats::smallestPossibleP(c->per_dataset.size()) : 1.0);
  }
  const std::vector<double> adjusted = stats::holmAdjusted(p);
  for (std::size_t i = 0; i < family.size(); ++i) {
    DatasetComparison& c = *family[i];
    c.holm_p = adjusted[i];
    c.family = family.size();
    c.holm_family = family_text;
    if (!c.not_computed.empty()) {
      c.verdict = {stats::VerdictKind::NotComputed, std::nullopt, c.not_computed, c.sample};
      continue;
    }
    stats::VerdictEvidence e{c.per_dataset, unit_name ? unit_name : c.unit_name, value_unit, c.interval, o.level,
                             c.test, c.holm_p, c.family,
                             stats::smallestPossibleHolmP(smallest_p, i),
                             stats::smallestPossibleHolmP(smallest_p_of_units, i)};
    c.verdict = stats::decideVerdict(e, o.rules);
    if (!c.sample.empty()) c.verdict.basis += "; " + c.sample;  // which units, counted how: every verdict names it
  }
}

namespace {

// The optima comparison over the units not in `nested`, for the verdict (grids that nest, compare_nesting.hpp); none
// when no unit of it nests or every difference is 0 (a tie is a description, over every unit).
std::optional<DatasetComparison> withoutNestedUnits(const DatasetComparison& optima,
                                                    const std::set<std::string>& nested,
                                                    const CompareStatisticsOptions& o) {
  if (!optima.test) return std::nullopt;
  PerDataset kept;
  for (std::size_t i = 0; i < optima.datasets.size(); ++i)
    if (!nested.count(optima.datasets[i]))
      kept.names.push_back(optima.datasets[i]), kept.values.push_back(optima.per_dataset[i]);
  if (kept.names.size() == optima.datasets.size()) return std::nullopt;
  DatasetComparison c;
  // "7 scenes where the grids do not nest, of 8 data sets over 8 scenes (...)": the verdict's n, then the sample's
  c.unit_name = optima.unit_name;
  c.sample = std::to_string(kept.names.size()) + " " + optima.unit_name + " where the grids do not nest, of " +
             optima.sample;
  overDatasets(std::move(kept), o, c);
  return c;
}

// The sets where both the method and the baseline have a best map, paired, with their units and data sets.
PairedSets pairedSets(const std::vector<ComparisonRow>& rows, const std::string& method, const std::string& baseline,
                      const SampleUnits& units) {
  PairedSets paired;
  for (std::size_t r = 0; r < rows.size(); ++r) {
    const auto m = rows[r].best(method), b = rows[r].best(baseline);
    if (!m || !b) continue;
    paired.method.push_back(m->auc), paired.baseline.push_back(b->auc), paired.dataset.push_back(units.of_row[r]);
    paired.datasets.insert(units.of_row[r] + '\n' + datasetOf(rows[r].dataset));
  }
  return paired;
}

// How the units were found and counted, on both comparisons (docs/statistics.md, "Verdicts").
void nameSample(const SampleUnits& units, MethodStatistics& s) {
  for (DatasetComparison* c : {&s.optima, &s.cross_validated})
    c->unit_name = units.noun, c->sample = sampleText(units, s.datasets, s.scenes);
}

// One method's statistics against the baseline, up to Holm's correction over the methods.
MethodStatistics methodStatistics(const std::vector<ComparisonRow>& rows, const std::vector<ResultsFile>& files,
                                  const std::string& method, const AucTable& baseline_table, std::size_t budget,
                                  const CompareStatisticsOptions& o, const SampleUnits& units) {
  MethodStatistics s;
  s.method = method;
  s.is_baseline = method == o.baseline;
  const PairedSets paired = pairedSets(rows, method, o.baseline, units);
  s.datasets = paired.datasets.size();
  s.scenes = std::set<std::string>(paired.dataset.begin(), paired.dataset.end()).size();
  std::vector<double> bests;
  for (const ComparisonRow& row : rows)
    if (const auto m = row.best(method)) bests.push_back(m->auc);
  const std::vector<double>& theirs = paired.baseline;
  s.mean_best_auc = bests.empty() ? NAN : std::accumulate(bests.begin(), bests.end(), 0.0) / double(bests.size());
  const AucTable table = aucTable(rows, files, method, units.of_row);
  if (table.one_grid) {
    s.leave_one_set_out = crossValidated(table.per_set);
    s.leave_one_dataset_out = crossValidated(perDataset(table));
  }
  // Summed as budgetSummary sums its curves (each term divided first), so that identical grids compare equal.
  double baseline_best = theirs.empty() ? NAN : 0.0;
  for (double b : theirs) baseline_best += b / double(theirs.size());
  s.budget = budgetSummary(table, budget, baseline_best, o.budget_max_maps);
  if (s.is_baseline) {
    s.sets = bests.size();
    nameSample(units, s);
    return s;
  }
  nameSample(units, s);
  pairedTests(paired, o, s);
  crossValidatedImprovements(table, baseline_table, o, s);
  const nesting::Nesting nested = nesting::nestingOf(rows, files, method, o.baseline, units.of_row);
  s.sets_holding_baseline_best = nested.sets, s.scenes_holding_baseline_best = nested.units.size();
  s.optima_not_nested = withoutNestedUnits(s.optima, nested.units, o);
  return s;
}

// The optima verdicts, Holm over every method's units (the description); where grids nest, again with each such
// method's units that do not nest, whose verdict it gets (compare_nesting.hpp; docs/statistics.md, "Grids that nest").
void decideOptima(std::vector<MethodStatistics>& out, const std::string& family, const CompareStatisticsOptions& o) {
  std::vector<DatasetComparison*> over_all, decided;
  for (MethodStatistics& s : out)
    if (!s.is_baseline)
      over_all.push_back(&s.optima), decided.push_back(s.optima_not_nested ? &*s.optima_not_nested : &s.optima);
  decideFamily(over_all, family, o, nullptr, "%");  // each its own unit
  if (decided == over_all) return;
  decideFamily(decided, family, o, nullptr, "%");
  for (MethodStatistics& s : out)
    if (s.optima_not_nested) {
      const std::size_t units = s.optima.per_dataset.size();
      s.optima.verdict = nesting::nestedVerdict(s.optima_not_nested->verdict, s.optima.verdict, units,
                                                units - s.optima_not_nested->per_dataset.size(), s.optima.unit_name,
                                                o.baseline);
    }
}

}  // namespace

std::vector<double> meanBudgetCurve(const std::vector<ComparisonRow>& rows, const std::vector<ResultsFile>& files,
                                    const std::string& method, std::size_t max_maps) {
  return meanCurve(aucTable(rows, files, method, sampleUnits(rows, UnitRule::Names).of_row), max_maps);
}

std::vector<std::string> pooledDatasetNames(const std::vector<ComparisonRow>& rows, UnitRule rule) {
  const SampleUnits sample = sampleUnits(rows, rule);
  struct Unit {
    std::set<std::string> whole_contents;  ///< hashes of rows named the unit itself (no pcs-NNNN part)
    bool has_sets = false;                 ///< rows named UNIT/pcs-NNNN
  };
  std::map<std::string, Unit> units;
  const auto& by_name = sample.without_provenance;
  for (const ComparisonRow& row : rows) {
    if (sample.noun != "data sets" && !std::binary_search(by_name.begin(), by_name.end(), datasetOf(row.dataset)))
      continue;  // its provenance, not its name, decides its unit
    Unit& u = units[datasetOf(row.dataset)];
    if (datasetOf(row.dataset) == row.dataset) u.whole_contents.insert(row.dataset_hash);
    else u.has_sets = true;
  }
  std::vector<std::string> pooled;
  for (const auto& [name, u] : units)
    if (u.whole_contents.size() > 1 || (!u.whole_contents.empty() && u.has_sets)) pooled.push_back(name);
  return pooled;
}

DatasetComparison pairedComparison(std::vector<std::string> names, std::vector<double> values,
                                   const CompareStatisticsOptions& options) {
  DatasetComparison c;
  overDatasets({std::move(names), std::move(values)}, options, c);
  return c;
}

std::string holmFamilyText(const std::string& kind, const std::vector<std::string>& methods,
                           const std::string& baseline) {
  if (methods.size() == 1)
    return "the " + kind + " verdict of " + methods[0] + " against " + baseline + " alone (no correction)";
  std::string list;
  for (const std::string& m : methods) list += (list.empty() ? "" : ", ") + m;
  return "the " + std::to_string(methods.size()) + " " + kind + " verdicts of " + list + " against " + baseline;
}

std::vector<MethodStatistics> compareStatistics(const std::vector<ComparisonRow>& rows,
                                                const std::vector<ResultsFile>& files,
                                                const CompareStatisticsOptions& o) {
  std::vector<std::string> methods = comparedMethods(rows);
  const auto base = std::find(methods.begin(), methods.end(), o.baseline);
  if (base == methods.end()) {
    std::string given;
    for (const auto& m : methods) given += (given.empty() ? "" : ", ") + m;
    throw std::invalid_argument("baseline " + o.baseline + ": no results of this method given (methods: " + given + ")");
  }
  std::rotate(methods.begin(), base, base + 1);  // the baseline first
  const SampleUnits units = sampleUnits(rows, o.units);
  const AucTable baseline_table = aucTable(rows, files, o.baseline, units.of_row);
  const std::size_t budget = baseline_table.one_grid && !baseline_table.per_set.empty()
                                 ? baseline_table.per_set.front().size() : 0;
  std::vector<MethodStatistics> out;
  for (const std::string& method : methods)
    out.push_back(methodStatistics(rows, files, method, baseline_table, budget, o, units));
  methods.erase(methods.begin());  // the family: every method but the baseline
  decideOptima(out, holmFamilyText("optima", methods, o.baseline), o);
  std::vector<DatasetComparison*> cross_validated;
  for (MethodStatistics& s : out)
    if (!s.is_baseline) cross_validated.push_back(&s.cross_validated);
  decideFamily(cross_validated, holmFamilyText("cross-validated", methods, o.baseline), o, nullptr, "%");
  return out;
}

namespace {

nlohmann::json crossValidatedJson(const CrossValidated& c) {
  if (!c.groups) return nullptr;
  return {{"groups", c.groups}, {"optimum", finiteNumber(c.optimum)}, {"score", finiteNumber(c.score)},
          {"gap", finiteNumber(c.gap)}};
}

nlohmann::json intervalJson(const std::optional<stats::BootstrapInterval>& i, const CompareStatisticsOptions& o) {
  if (!i) return nullptr;
  return {{"mean", finiteNumber(i->estimate)}, {"lower", finiteNumber(i->lower)}, {"upper", finiteNumber(i->upper)},
          {"level", o.level}, {"resamples", o.resamples}, {"seed", o.seed}, {"method", "BCa bootstrap"}};
}

// A comparison over data sets: its sample, interval, exact test with Holm's correction, and the rules applied.
nlohmann::json datasetComparisonJson(const DatasetComparison& c, const CompareStatisticsOptions& o) {
  nlohmann::json test = nullptr;
  if (c.test)
    test = {{"name", c.test->name}, {"p_value", c.test->p_value}, {"nonzero", c.test->nonzero},
            {"smallest_possible_p", c.test->smallest_possible_p}, {"holm_p", c.holm_p}, {"family", c.family}};
  nlohmann::json equivalence = nullptr;
  if (c.verdict.equivalence)
    equivalence = {{"test", "sign test, interval of the median"}, {"level", c.verdict.equivalence->level},
                   {"lower", c.verdict.equivalence->lower}, {"upper", c.verdict.equivalence->upper}};
  nlohmann::json per_dataset = nlohmann::json::array();
  for (std::size_t i = 0; i < c.per_dataset.size(); ++i)
    per_dataset.push_back({{"dataset", c.datasets[i]}, {"improvement_percent", finiteNumber(c.per_dataset[i])}});
  return {{"datasets", c.per_dataset.size()}, {"unit", c.unit_name}, {"sample", c.sample}, {"per_dataset", per_dataset},
          {"improvement_percent", intervalJson(c.interval, o)}, {"test", test}, {"equivalence", equivalence},
          {"alpha", o.rules.alpha}, {"smallest_effect_percent", o.rules.smallest_effect},
          {"holm_family", c.holm_family}, {"verdict", c.verdict.text}, {"basis", c.verdict.basis}};
}

nlohmann::json budgetJson(const BudgetSummary& b) {
  return {{"maps", b.maps}, {"budget", b.budget}, {"expected_best_at_budget", finiteNumber(b.expected_best_at_budget)},
          {"first_above_baseline", b.first_above_baseline ? nlohmann::json(*b.first_above_baseline) : nlohmann::json(nullptr)}};
}

// Against the baseline: the verdicts first, then the per-set description.
void addComparisonJson(const MethodStatistics& s, const CompareStatisticsOptions& o, nlohmann::json& j) {
  j["better"] = s.better, j["worse"] = s.worse, j["ties"] = s.ties;
  j["sets_holding_baseline_best"] = s.sets_holding_baseline_best;
  j["scenes_holding_baseline_best"] = s.scenes_holding_baseline_best;
  if (s.optima_not_nested) j["optima_where_grids_do_not_nest"] = datasetComparisonJson(*s.optima_not_nested, o);
  j["verdict"] = s.optima.verdict.text;
  j["cross_validated_verdict"] = s.cross_validated.verdict.text;
  j["optima_over_datasets"] = datasetComparisonJson(s.optima, o);
  j["cross_validated_over_datasets"] = datasetComparisonJson(s.cross_validated, o);
  j["improvement_percent"] = intervalJson(s.improvement_percent, o);
  j["improvement_percent_over_datasets"] = intervalJson(s.optima.interval, o);
  j["cross_validated_improvement_percent"] = intervalJson(s.cross_validated.interval, o);
  j["leave_one_set_out_improvement_percent"] = intervalJson(s.leave_one_set_out_improvement, o);
  if (s.wilcoxon) j["wilcoxon"] = {{"statistic", s.wilcoxon->statistic}, {"p_value", s.wilcoxon->p_value},
                                   {"exact", s.wilcoxon->exact}, {"used", s.wilcoxon->used}};
  if (s.sign) j["sign_test"] = {{"positive", s.sign->positive}, {"negative", s.sign->negative}, {"p_value", s.sign->p_value}};
  if (s.effect) j["effect"] = {{"mean_difference", s.effect->mean_difference},
                               {"median_difference", s.effect->median_difference},
                               {"rank_biserial", s.effect->rank_biserial}};
}

}  // namespace

nlohmann::json toJson(const std::vector<MethodStatistics>& statistics, const CompareStatisticsOptions& o) {
  nlohmann::json out = nlohmann::json::array();
  for (const MethodStatistics& s : statistics) {
    nlohmann::json j = {{"method", s.method}, {"baseline", s.is_baseline}, {"sets", s.sets}, {"datasets", s.datasets},
                        {"scenes", s.scenes},
                        {"mean_best_auc", finiteNumber(s.mean_best_auc)},
                        {"leave_one_set_out", crossValidatedJson(s.leave_one_set_out)},
                        {"leave_one_dataset_out", crossValidatedJson(s.leave_one_dataset_out)}, {"verdict", "baseline"}};
    if (s.budget.maps) j["budget"] = budgetJson(s.budget);
    if (!s.is_baseline) addComparisonJson(s, o, j);
    out.push_back(std::move(j));
  }
  return out;
}

}  // namespace occsweep
