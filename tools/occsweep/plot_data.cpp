// The data of `occsweep plot` (plot_data.hpp).
#include "plot_data.hpp"

#include <cmath>
#include <map>
#include <stdexcept>

#include "compare_tables.hpp"
#include "occsweep/eval/curve.hpp"

namespace occsweep::cli {
namespace {

using nlohmann::json;

// The best map's own results (its thresholds) in the file it came from.
const MapResult& bestMapOf(const BestMap& best, const std::vector<ResultsFile>& files) {
  for (const MapResult& m : files[best.file].maps)
    if (m.map_index == best.map_index) return m;
  throw std::logic_error("plot: a best map is not in its file");
}

}  // namespace

json curvesData(const PlotInputs& in) {
  json sets = json::array();
  for (std::size_t r = 0; r < in.rows.size() && r < kMaxCurveSets; ++r) {
    const ComparisonRow& row = in.rows[r];
    json methods = json::array();
    for (const std::string& m : comparedMethods(in.rows)) {
      const auto best = row.best(m);
      if (!best) continue;
      std::vector<ConfusionCounts> counts;
      for (const auto& t : bestMapOf(*best, in.files).thresholds) counts.push_back(t.counts);
      json points = json::array();
      for (const CurvePoint& p : curvePoints(counts)) points.push_back({p.fdr, p.tpr});
      methods.push_back({{"method", m}, {"auc", finiteNumber(best->auc)}, {"parameters", bestParametersText(*best, in.files)},
                         {"points", points}});
    }
    sets.push_back({{"set", row.dataset}, {"methods", methods}});
  }
  return {{"kind", "curves"}, {"sets", sets}, {"sets_given", in.rows.size()}};
}

json budgetData(const PlotInputs& in) {
  json methods = json::array();
  double baseline_best = 0.0;
  std::size_t n = 0;
  for (const ComparisonRow& row : in.rows)
    if (const auto b = row.best(in.baseline)) baseline_best += b->auc, ++n;
  for (const std::string& m : comparedMethods(in.rows)) {
    const std::vector<double> curve = meanBudgetCurve(in.rows, in.files, m);
    if (!curve.empty()) methods.push_back({{"method", m}, {"maps", curve.size()}, {"curve", curve}});
  }
  return {{"kind", "budget"}, {"baseline", in.baseline}, {"baseline_best", finiteNumber(n ? baseline_best / double(n) : NAN)},
          {"sets", n}, {"methods", methods}};
}

json improvementData(const PlotInputs& in) {
  json methods = json::array();
  for (const MethodStatistics& s : compareStatistics(in.rows, in.files, statisticsAgainst(in.baseline))) {
    if (s.is_baseline) continue;
    json points = json::array();
    for (const ComparisonRow& row : in.rows) {
      const double improvement = row.improvementPercent(s.method, in.baseline);
      if (std::isfinite(improvement)) points.push_back({row.best(in.baseline)->auc, improvement, row.dataset});
    }
    json interval = nullptr;
    if (const auto& i = s.improvement_percent) interval = {{"mean", i->estimate}, {"lower", i->lower}, {"upper", i->upper}};
    methods.push_back({{"method", s.method}, {"points", points}, {"interval", interval}, {"verdict", s.optima.verdict.text}});
  }
  return {{"kind", "improvement"}, {"baseline", in.baseline}, {"methods", methods}};
}

json paramsData(const PlotInputs& in) {
  // Every map of the method's files: per parameter and value, the sum, count and best of the map AUCs.
  struct Cell { double sum = 0, best = -INFINITY; std::size_t count = 0; };
  std::map<std::string, std::map<double, Cell>> marginal;
  std::vector<std::string> names;
  for (const ResultsFile& f : in.files) {
    if (f.header.method != in.method) continue;
    names = f.header.parameters.names;
    for (const MapResult& m : f.maps) {
      if (!std::isfinite(m.area.anchored)) continue;
      for (std::size_t i = 0; i < names.size(); ++i) {
        Cell& c = marginal[names[i]][toDouble(m.params.values[i])];
        c.sum += m.area.anchored, ++c.count, c.best = std::max(c.best, m.area.anchored);
      }
    }
  }
  if (names.empty()) throw std::invalid_argument("plot params: no results of method " + in.method + " given");
  json parameters = json::array();
  for (const std::string& name : names) {
    json values = json::array(), mean = json::array(), best = json::array();
    for (const auto& [v, c] : marginal[name]) values.push_back(v), mean.push_back(c.sum / double(c.count)), best.push_back(c.best);
    if (values.size() > 1) parameters.push_back({{"name", name}, {"values", values}, {"mean", mean}, {"best", best}});
  }
  return {{"kind", "params"}, {"method", in.method}, {"parameters", parameters}};
}

json plotData(const std::string& kind, const PlotInputs& in) {
  if (kind == "curves") return curvesData(in);
  if (kind == "budget") return budgetData(in);
  if (kind == "improvement") return improvementData(in);
  if (kind == "params") return paramsData(in);
  throw std::invalid_argument("plot: no figure " + kind);
}

}  // namespace occsweep::cli
