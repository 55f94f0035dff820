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

// The data set a point cloud set belongs to: generated sets are named DATASET/pcs-NNNN (docs/datasets.md); any
// other name is a data set of its own.
std::string datasetOf(const std::string& name) { return name.substr(0, name.find('/')); }

// One method's AUC table: per set with a best map, every map's AUC; all sets must come from one grid.
struct AucTable {
  std::vector<std::vector<double>> per_set;
  std::vector<std::string> dataset;  ///< the data set of each set (for leave-one-data-set-out)
  std::vector<std::size_t> row;      ///< the row of each set
  bool one_grid = true;
};

AucTable aucTable(const std::vector<ComparisonRow>& rows, const std::vector<ResultsFile>& files,
                  const std::string& method) {
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
    t.dataset.push_back(datasetOf(row.dataset));
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

// The same sets of a method and of the baseline, paired: their AUCs (per-set optima) and data sets.
struct PairedSets {
  std::vector<double> method, baseline;
  std::vector<std::string> dataset;
};

// Sorted first, so that the interval depends on the values and the seed, not on the order the files were given in.
std::optional<stats::BootstrapInterval> meanInterval(std::vector<double> values, const CompareStatisticsOptions& o) {
  if (values.size() < 2) return std::nullopt;
  std::sort(values.begin(), values.end());
  return stats::bootstrapMeanInterval(values, {o.level, o.resamples, o.seed, stats::BootstrapMethod::BCa});
}

// Each data set's mean of its sets' improvements (percent).
std::vector<double> perDatasetMeans(const std::vector<double>& improvement, const std::vector<std::string>& dataset) {
  std::map<std::string, std::pair<double, std::size_t>> sums;
  for (std::size_t i = 0; i < improvement.size(); ++i) {
    auto& [sum, n] = sums[dataset[i]];
    sum += improvement[i], ++n;
  }
  std::vector<double> out;
  for (const auto& [_, v] : sums) out.push_back(v.first / double(v.second));
  return out;
}

// The paired tests of a method against the baseline on the sets where both have an AUC.
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
  s.improvement_over_datasets = meanInterval(perDatasetMeans(improvement, dataset), o);
}

// Leave one set out for both, paired by set: the method's held-out score against the baseline's, in percent.
std::optional<stats::BootstrapInterval> crossValidatedImprovement(const AucTable& mine, const AucTable& base,
                                                                  const CompareStatisticsOptions& o) {
  if (!mine.one_grid || !base.one_grid || mine.row != base.row || !rectangular(mine.per_set) ||
      !rectangular(base.per_set))
    return std::nullopt;
  const stats::LeaveOneGroupOut m = stats::leaveOneGroupOut(mine.per_set), b = stats::leaveOneGroupOut(base.per_set);
  std::vector<double> improvement;
  for (std::size_t i = 0; i < m.groups.size(); ++i)
    if (b.groups[i].cv_score > 0)
      improvement.push_back((m.groups[i].cv_score - b.groups[i].cv_score) / b.groups[i].cv_score * 100.0);
  return meanInterval(improvement, o);
}

std::string verdictOf(const std::optional<stats::BootstrapInterval>& interval) {
  if (!interval) return "too few sets";
  if (interval->contains(0.0)) return "no clear difference (the interval contains 0)";
  return interval->lower > 0 ? "gain" : "loss";
}

}  // namespace

std::vector<double> meanBudgetCurve(const std::vector<ComparisonRow>& rows, const std::vector<ResultsFile>& files,
                                    const std::string& method, std::size_t max_maps) {
  return meanCurve(aucTable(rows, files, method), max_maps);
}

std::vector<std::string> comparedMethods(const std::vector<ComparisonRow>& rows) {
  std::set<std::string> names;
  for (const ComparisonRow& row : rows) {
    if (row.octomap) names.insert("octomap");
    if (row.knn) names.insert("knn");
    for (const auto& [name, _] : row.others) names.insert(name);
  }
  return {names.begin(), names.end()};
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
  const AucTable baseline_table = aucTable(rows, files, o.baseline);
  const std::size_t budget = baseline_table.one_grid && !baseline_table.per_set.empty()
                                 ? baseline_table.per_set.front().size() : 0;
  std::vector<MethodStatistics> out;
  for (const std::string& method : methods) {
    MethodStatistics s;
    s.method = method;
    s.is_baseline = method == o.baseline;
    PairedSets paired;
    std::vector<double> bests;
    for (const ComparisonRow& row : rows) {
      const auto m = row.best(method), b = row.best(o.baseline);
      if (m) bests.push_back(m->auc);
      if (m && b) paired.method.push_back(m->auc), paired.baseline.push_back(b->auc), paired.dataset.push_back(datasetOf(row.dataset));
    }
    const std::vector<double>& theirs = paired.baseline;
    s.mean_best_auc = bests.empty() ? NAN : std::accumulate(bests.begin(), bests.end(), 0.0) / double(bests.size());
    const AucTable table = aucTable(rows, files, method);
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
      s.verdict = s.cross_validated_verdict = "baseline";
    } else {
      pairedTests(paired, o, s);
      s.verdict = verdictOf(s.improvement_percent);
      s.cross_validated_improvement = crossValidatedImprovement(table, baseline_table, o);
      s.cross_validated_verdict = s.cross_validated_improvement || s.sets < 2
                                      ? verdictOf(s.cross_validated_improvement)
                                      : "not computed (the sets differ in grid or maps, or an AUC is undefined)";
    }
    out.push_back(std::move(s));
  }
  return out;
}

nlohmann::json toJson(const std::vector<MethodStatistics>& statistics, const CompareStatisticsOptions& o) {
  nlohmann::json out = nlohmann::json::array();
  const auto cv = [](const CrossValidated& c) -> nlohmann::json {
    if (!c.groups) return nullptr;
    return {{"groups", c.groups}, {"optimum", finiteNumber(c.optimum)}, {"score", finiteNumber(c.score)}, {"gap", finiteNumber(c.gap)}};
  };
  for (const MethodStatistics& s : statistics) {
    nlohmann::json j = {{"method", s.method}, {"baseline", s.is_baseline}, {"sets", s.sets},
                        {"mean_best_auc", finiteNumber(s.mean_best_auc)}, {"leave_one_set_out", cv(s.leave_one_set_out)},
                        {"leave_one_dataset_out", cv(s.leave_one_dataset_out)}, {"verdict", s.verdict}};
    if (s.budget.maps)
      j["budget"] = {{"maps", s.budget.maps}, {"budget", s.budget.budget},
                     {"expected_best_at_budget", finiteNumber(s.budget.expected_best_at_budget)},
                     {"first_above_baseline", s.budget.first_above_baseline ? nlohmann::json(*s.budget.first_above_baseline)
                                                                            : nlohmann::json(nullptr)}};
    if (!s.is_baseline) {
      j["better"] = s.better, j["worse"] = s.worse, j["ties"] = s.ties;
      j["cross_validated_verdict"] = s.cross_validated_verdict;
      const auto interval = [&](const std::optional<stats::BootstrapInterval>& i) -> nlohmann::json {
        if (!i) return nullptr;
        return {{"mean", finiteNumber(i->estimate)}, {"lower", finiteNumber(i->lower)}, {"upper", finiteNumber(i->upper)},
                {"level", o.level}, {"resamples", o.resamples}, {"seed", o.seed}, {"method", "BCa bootstrap"}};
      };
      j["improvement_percent"] = interval(s.improvement_percent);
      j["improvement_percent_over_datasets"] = interval(s.improvement_over_datasets);
      j["cross_validated_improvement_percent"] = interval(s.cross_validated_improvement);
      if (s.wilcoxon) j["wilcoxon"] = {{"statistic", s.wilcoxon->statistic}, {"p_value", s.wilcoxon->p_value},
                                       {"exact", s.wilcoxon->exact}, {"used", s.wilcoxon->used}};
      if (s.sign) j["sign_test"] = {{"positive", s.sign->positive}, {"negative", s.sign->negative}, {"p_value", s.sign->p_value}};
      if (s.effect) j["effect"] = {{"mean_difference", s.effect->mean_difference},
                                   {"median_difference", s.effect->median_difference},
                                   {"rank_biserial", s.effect->rank_biserial}};
    }
    out.push_back(std::move(j));
  }
  return out;
}

}  // namespace occsweep
