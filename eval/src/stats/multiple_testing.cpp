#include "occsweep/stats/multiple_testing.hpp"

#include <algorithm>
#include <numeric>
#include <stdexcept>
#include <string>

namespace occsweep::stats {

std::vector<double> holmAdjusted(const std::vector<double>& p_values) {
  for (std::size_t i = 0; i < p_values.size(); ++i)
    if (!(p_values[i] >= 0.0 && p_values[i] <= 1.0))
      throw std::invalid_argument("Holm correction: p-value " + std::to_string(i) + " is not in [0, 1]");
  std::vector<std::size_t> order(p_values.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return p_values[a] < p_values[b]; });
  const std::size_t m = p_values.size();
  std::vector<double> adjusted(m);
  double running = 0.0;  // the step-down maximum keeps the adjusted values in the order of the raw ones
  for (std::size_t rank = 0; rank < m; ++rank) {
    running = std::max(running, std::min(1.0, double(m - rank) * p_values[order[rank]]));
    adjusted[order[rank]] = running;
  }
  return adjusted;
}

}  // namespace occsweep::stats
