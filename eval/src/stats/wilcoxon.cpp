#include "occsweep/stats/wilcoxon.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

#include "occsweep/stats/bootstrap.hpp"
#include "sample_checks.hpp"

namespace occsweep::stats {

namespace {

/// Auto mode's switch to the normal approximation, as SciPy 1.10's method="auto".
constexpr std::size_t kMaxAutoExactCount = 50;

struct RankSums {
  double plus = 0.0;
  double minus = 0.0;
  double tie_term = 0.0;  ///< sum over tie groups of t (t^2 - 1)
};

RankSums rankSums(const std::vector<double>& non_zero) {
  std::vector<double> magnitudes(non_zero.size());
  std::transform(non_zero.begin(), non_zero.end(), magnitudes.begin(), [](double v) { return std::fabs(v); });
  const auto ranks = midRanks(magnitudes);
  RankSums sums;
  for (std::size_t i = 0; i < non_zero.size(); ++i) (non_zero[i] > 0.0 ? sums.plus : sums.minus) += ranks[i];
  std::sort(magnitudes.begin(), magnitudes.end());
  for (std::size_t start = 0; start < magnitudes.size();) {
    std::size_t end = start;
    while (end < magnitudes.size() && magnitudes[end] == magnitudes[start]) ++end;
    const double t = double(end - start);
    sums.tie_term += t * (t * t - 1.0);
    start = end;
  }
  return sums;
}

/// P(W+ = s) under the null for n untied ranks, s = 0..n(n+1)/2: each rank joins W+ with probability 1/2.
std::vector<double> signedRankNullDistribution(std::size_t n) {
  std::vector<double> pmf(n * (n + 1) / 2 + 1, 0.0);
  pmf[0] = 1.0;
  std::size_t top = 0;
  for (std::size_t rank = 1; rank <= n; ++rank) {
    top += rank;
    for (std::size_t s = top; s >= rank; --s) pmf[s] = 0.5 * (pmf[s] + pmf[s - rank]);
    for (std::size_t s = std::min(rank, top + 1); s-- > 0;) pmf[s] *= 0.5;
  }
  return pmf;
}

double exactTwoSidedP(std::size_t n, double w_plus) {
  const auto pmf = signedRankNullDistribution(n);
  const auto observed = std::size_t(std::llround(w_plus));
  const double at_most = std::accumulate(pmf.begin(), pmf.begin() + std::ptrdiff_t(observed) + 1, 0.0);
  const double at_least = std::accumulate(pmf.begin() + std::ptrdiff_t(observed), pmf.end(), 0.0);
  return std::min(1.0, 2.0 * std::min(at_most, at_least));
}

/// Normal approximation with the tie-corrected variance (Lehmann 1975, ch. 3) and, optionally, the continuity
/// correction 0.5 towards the mean, exactly as SciPy 1.10's wilcoxon(..., method="approx").
void approximate(SignedRankResult& result, const RankSums& sums, bool continuity_correction) {
  const double n = double(result.used);
  const double mean = n * (n + 1.0) / 4.0;
  const double sd = std::sqrt((n * (n + 1.0) * (2.0 * n + 1.0) - 0.5 * sums.tie_term) / 24.0);
  const double t = result.statistic;
  const double correction = continuity_correction ? 0.5 * double((t > mean) - (t < mean)) : 0.0;
  result.z = (t - mean - correction) / sd;
  result.p_value = std::erfc(std::fabs(result.z) / std::sqrt(2.0));
}

}  // namespace

std::vector<double> midRanks(const std::vector<double>& values) {
  std::vector<std::size_t> order(values.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return values[a] < values[b]; });
  std::vector<double> ranks(values.size());
  for (std::size_t start = 0; start < order.size();) {
    std::size_t end = start;
    while (end < order.size() && values[order[end]] == values[order[start]]) ++end;
    const double shared = (double(start + 1) + double(end)) / 2.0;
    for (std::size_t k = start; k < end; ++k) ranks[order[k]] = shared;
    start = end;
  }
  return ranks;
}

SignedRankResult wilcoxonSignedRank(const std::vector<double>& differences, const SignedRankOptions& options) {
  detail::requireFinite(differences, "signed-rank test");
  const auto non_zero = detail::nonZero(differences);
  if (non_zero.empty()) throw std::invalid_argument("signed-rank test: every difference is zero");
  const RankSums sums = rankSums(non_zero);
  SignedRankResult result;
  result.w_plus = sums.plus;
  result.w_minus = sums.minus;
  result.statistic = std::min(sums.plus, sums.minus);
  result.used = non_zero.size();
  const bool ties = sums.tie_term > 0.0;
  if (options.mode == SignedRankMode::Exact && ties)
    throw std::invalid_argument("signed-rank test: the exact distribution needs untied |differences|");
  if (options.mode == SignedRankMode::Exact && result.used > kMaxExactSignedRankCount)
    throw std::invalid_argument("signed-rank test: exact mode takes at most 1000 non-zero differences");
  result.exact = options.mode == SignedRankMode::Exact ||
                 (options.mode == SignedRankMode::Auto && !ties && result.used <= kMaxAutoExactCount);
  if (result.exact)
    result.p_value = exactTwoSidedP(result.used, sums.plus);
  else
    approximate(result, sums, options.continuity_correction);
  return result;
}

}  // namespace occsweep::stats
