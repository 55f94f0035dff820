// Section 3.5 / Fig. 4: neighbourhood component analysis for regression (Yang, Wang, Zuo 2012), in the
// formulation of MATLAB's fsrnca:
//   d_w(i, j) = sum_r w_r^2 |x_ir - x_jr|,  p_ij = exp(-d_w(i,j)/sigma) / sum_{k != i} exp(-d_w(i,k)/sigma),
//   l_i = sum_{j != i} p_ij |y_i - y_j|  (mean absolute deviation loss),
//   f(w) = (1/n) sum_i l_i + lambda sum_r w_r^2,
// minimised by L-BFGS from w = 1, with lambda chosen by k-fold cross-validation around 1/n.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

namespace occsweep {

struct NcaConfig {
  double sigma = 1.0;                 ///< kernel width (fsrnca's LengthScale default)
  std::vector<double> lambda_factors = {0.0, 0.25, 1.0, 4.0, 16.0};  ///< lambda = factor / n (fsrnca default: 1/n)
  int folds = 5;                      ///< cross-validation folds for lambda (fewer than 2: lambda = 1/n, no CV)
  int max_iterations = 200;           ///< L-BFGS iterations
  double gradient_tolerance = 1e-6;   ///< stop when the largest |gradient| falls below this
  bool standardize = true;            ///< features to zero mean and unit deviation first: grid parameters have
                                      ///< different ranges (k in 1..7, probabilities in 0..1)
  std::uint64_t seed = 1;             ///< fold assignment (SplitMix64 Fisher-Yates: portable)
};

/// f(w) and, when `gradient` is given, its gradient. x: n rows of samples, p feature columns.
[[nodiscard]] double ncaObjective(const Eigen::MatrixXd& x, const Eigen::VectorXd& y, const Eigen::VectorXd& w,
                                  double lambda, double sigma, Eigen::VectorXd* gradient);

/// Minimises f from w = 1 by L-BFGS (memory 10, backtracking Armijo line search).
[[nodiscard]] Eigen::VectorXd fitNcaWeights(const Eigen::MatrixXd& x, const Eigen::VectorXd& y, double lambda,
                                            const NcaConfig& config, int* iterations = nullptr);

/// Mean |y - y_hat| over the test samples, y_hat = sum_j p_j y_j over the training samples (fsrnca's predict).
[[nodiscard]] double ncaTestLoss(const Eigen::MatrixXd& train_x, const Eigen::VectorXd& train_y,
                                 const Eigen::VectorXd& w, const Eigen::MatrixXd& test_x,
                                 const Eigen::VectorXd& test_y, double sigma);

struct NcaResult {
  std::vector<double> weights;      ///< |w_r|, in feature order
  std::vector<double> normalized;   ///< |w_r| / sum |w|: shares that sum to 1 (see docs/reproduction.md)
  double lambda = 0.0;
  std::vector<double> lambdas;      ///< tried
  std::vector<double> cv_loss;      ///< mean test loss per lambda (empty without CV)
  int iterations = 0;               ///< of the final fit
  std::size_t samples = 0;
};

/// Cross-validates lambda, then fits on every sample. Throws std::invalid_argument for fewer than 4 samples,
/// mismatched sizes or non-finite values.
[[nodiscard]] NcaResult ncaFeatureWeights(const Eigen::MatrixXd& x, const Eigen::VectorXd& y,
                                          const NcaConfig& config = {});

}  // namespace occsweep
