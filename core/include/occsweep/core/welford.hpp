// Welford's recurrence for the mean and deviation of the average distances (Eq. 9-10).
#pragma once

#include <cmath>
#include <cstddef>

namespace occsweep {

/// Running mean mu_i and corrected sum of squares Q_i (Eq. 9); sigma = sqrt(Q_n / n) (Eq. 10).
class Welford {
 public:
  /// Eq. 9: mu_i = mu_{i-1} + (s_i - mu_{i-1}) / i, Q_i = Q_{i-1} + (s_i - mu_{i-1})(s_i - mu_i).
  void add(double s);
  [[nodiscard]] std::size_t count() const { return n_; }
  [[nodiscard]] double mean() const { return mean_; }
  /// Population deviation sqrt(Q_n / n) (Eq. 10); 0 before the first value.
  [[nodiscard]] double sigma() const { return n_ == 0 ? 0.0 : std::sqrt(q_ / double(n_)); }

 private:
  std::size_t n_ = 0;
  double mean_ = 0.0;  // mu_0 = 0
  double q_ = 0.0;     // Q_0 = 0
};

inline void Welford::add(double s) {
  ++n_;
  const double previous = mean_;
  mean_ = previous + (s - previous) / double(n_);
  q_ += (s - previous) * (s - mean_);
}

}  // namespace occsweep
