#include "occsweep/stats/correlation.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <stdexcept>

#include "occsweep/core/splitmix64.hpp"
#include "occsweep/stats/wilcoxon.hpp"
#include "sample_checks.hpp"

namespace occsweep::stats {

namespace {

/// Tolerance of "at least as extreme": numerically distinct but theoretically equal |r| count as equal, with
/// SciPy 1.10's permutation_test tolerance max(1e-14, 1e-14 |observed|).
constexpr double kRelativeTie = 1e-14;

void requirePairs(const std::vector<double>& x, const std::vector<double>& y, const char* what) {
  if (x.size() != y.size())
    throw std::invalid_argument(std::string(what) + ": x has " + std::to_string(x.size()) + " values, y " +
                                std::to_string(y.size()));
  detail::requireFinite(x, (std::string(what) + " (x)").c_str());
  detail::requireFinite(y, (std::string(what) + " (y)").c_str());
}

/// values minus their mean, scaled to unit Euclidean norm; empty when the values are constant.
std::vector<double> centredUnit(const std::vector<double>& values) {
  const double mean = std::accumulate(values.begin(), values.end(), 0.0) / double(values.size());
  std::vector<double> centred(values.size());
  double norm = 0.0;
  for (std::size_t i = 0; i < values.size(); ++i) {
    centred[i] = values[i] - mean;
    norm += centred[i] * centred[i];
  }
  norm = std::sqrt(norm);
  if (!(norm > 0.0)) return {};
  for (double& v : centred) v /= norm;
  return centred;
}

/// r of unit centred a with b permuted by `order`: sum a_i b_order(i), kept within [-1, 1].
double permutedDot(const std::vector<double>& a, const std::vector<double>& b, const std::vector<std::size_t>& order) {
  double sum = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) sum += a[i] * b[order[i]];
  return std::clamp(sum, -1.0, 1.0);
}

void requireGroups(const std::vector<double>& x, const std::vector<double>& y, const std::vector<std::string>& group,
                   const char* what) {
  requirePairs(x, y, what);
  if (group.size() != x.size())
    throw std::invalid_argument(std::string(what) + ": " + std::to_string(group.size()) + " group labels for " +
                                std::to_string(x.size()) + " pairs");
}

double pearsonOfChecked(const std::vector<double>& x, const std::vector<double>& y) {
  const auto a = centredUnit(x), b = centredUnit(y);
  if (a.empty() || b.empty()) return NAN;
  std::vector<std::size_t> identity(x.size());
  std::iota(identity.begin(), identity.end(), 0);
  return permutedDot(a, b, identity);
}

/// How many permutations of b reach |r| >= threshold: all n! of them (std::next_permutation from the identity).
std::size_t countExact(const std::vector<double>& a, const std::vector<double>& b, double threshold,
                       std::size_t& permutations) {
  std::vector<std::size_t> order(a.size());
  std::iota(order.begin(), order.end(), 0);
  std::size_t count = 0;
  permutations = 0;
  do {
    count += std::fabs(permutedDot(a, b, order)) >= threshold ? 1 : 0;
    ++permutations;
  } while (std::next_permutation(order.begin(), order.end()));
  return count;
}

/// How many of `resamples` uniform random permutations (Fisher-Yates on SplitMix64) reach |r| >= threshold.
std::size_t countRandom(const std::vector<double>& a, const std::vector<double>& b, double threshold,
                        std::size_t resamples, std::uint64_t seed) {
  SplitMix64 rng(seed);
  std::vector<std::size_t> order(a.size());
  std::iota(order.begin(), order.end(), 0);
  std::size_t count = 0;
  for (std::size_t k = 0; k < resamples; ++k) {
    for (std::size_t i = order.size() - 1; i > 0; --i) std::swap(order[i], order[rng.below(i + 1)]);
    count += std::fabs(permutedDot(a, b, order)) >= threshold ? 1 : 0;
  }
  return count;
}

}  // namespace

double pearsonCorrelation(const std::vector<double>& x, const std::vector<double>& y) {
  requirePairs(x, y, "pearsonCorrelation");
  if (x.size() < 2) throw std::invalid_argument("pearsonCorrelation: needs at least 2 pairs");
  return pearsonOfChecked(x, y);
}

double spearmanCorrelation(const std::vector<double>& x, const std::vector<double>& y) {
  requirePairs(x, y, "spearmanCorrelation");
  if (x.size() < 2) throw std::invalid_argument("spearmanCorrelation: needs at least 2 pairs");
  return pearsonOfChecked(midRanks(x), midRanks(y));
}

double correlation(const std::vector<double>& x, const std::vector<double>& y, CorrelationKind kind) {
  return kind == CorrelationKind::Spearman ? spearmanCorrelation(x, y) : pearsonCorrelation(x, y);
}

PermutationResult correlationPermutationTest(const std::vector<double>& x, const std::vector<double>& y,
                                             const PermutationOptions& options) {
  const double observed = correlation(x, y, options.kind);  // checks the input
  if (std::isnan(observed)) throw std::invalid_argument("correlationPermutationTest: x or y is constant");
  if (options.resamples == 0) throw std::invalid_argument("correlationPermutationTest: resamples must be at least 1");
  const bool ranks = options.kind == CorrelationKind::Spearman;
  const auto a = centredUnit(ranks ? midRanks(x) : x), b = centredUnit(ranks ? midRanks(y) : y);
  const double threshold = std::fabs(observed) - std::max(kRelativeTie, kRelativeTie * std::fabs(observed));
  PermutationResult result;
  result.statistic = observed;
  result.exact = x.size() <= kMaxExactPermutationCount;
  if (result.exact) {
    const std::size_t count = countExact(a, b, threshold, result.permutations);
    result.p_value = double(count) / double(result.permutations);
  } else {
    result.permutations = options.resamples;
    const std::size_t count = countRandom(a, b, threshold, options.resamples, options.seed);
    result.p_value = double(count + 1) / double(options.resamples + 1);
  }
  return result;
}

std::vector<GroupCorrelation> correlationWithinGroups(const std::vector<double>& x, const std::vector<double>& y,
                                                      const std::vector<std::string>& group) {
  requireGroups(x, y, group, "correlationWithinGroups");
  std::map<std::string, std::pair<std::vector<double>, std::vector<double>>> members;
  for (std::size_t i = 0; i < x.size(); ++i) {
    members[group[i]].first.push_back(x[i]);
    members[group[i]].second.push_back(y[i]);
  }
  std::vector<GroupCorrelation> result;
  for (const auto& [label, xy] : members) {
    const bool defined = xy.first.size() >= 2;
    result.push_back({label, xy.first.size(), defined ? pearsonOfChecked(xy.first, xy.second) : NAN,
                      defined ? pearsonOfChecked(midRanks(xy.first), midRanks(xy.second)) : NAN});
  }
  return result;
}

double pooledWithinGroupPearson(const std::vector<double>& x, const std::vector<double>& y,
                                const std::vector<std::string>& group) {
  requireGroups(x, y, group, "pooledWithinGroupPearson");
  std::map<std::string, std::pair<double, double>> sums;
  std::map<std::string, std::size_t> counts;
  for (std::size_t i = 0; i < x.size(); ++i) {
    sums[group[i]].first += x[i];
    sums[group[i]].second += y[i];
    ++counts[group[i]];
  }
  std::vector<double> dx(x.size()), dy(y.size());
  for (std::size_t i = 0; i < x.size(); ++i) {
    dx[i] = x[i] - sums[group[i]].first / double(counts[group[i]]);
    dy[i] = y[i] - sums[group[i]].second / double(counts[group[i]]);
  }
  return x.size() >= 2 ? pearsonOfChecked(dx, dy) : NAN;
}

}  // namespace occsweep::stats
