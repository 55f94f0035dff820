#include "occsweep/stats/runtime_model.hpp"

#include <stdexcept>

#include <Eigen/Dense>

namespace occsweep {
namespace {

RuntimeFit solve(const Eigen::MatrixXd& X, const Eigen::VectorXd& y, int unknowns) {
  if (X.rows() < unknowns) throw std::invalid_argument("run-time fit: too few samples");
  const auto qr = X.colPivHouseholderQr();
  if (qr.rank() < unknowns) throw std::invalid_argument("run-time fit: samples do not determine the model");
  const Eigen::VectorXd beta = qr.solve(y);
  const Eigen::VectorXd residual = y - X * beta;
  const double mean = y.mean();
  const double total = (y.array() - mean).square().sum();
  RuntimeFit f;
  f.a = beta(0);
  f.b = beta(1);
  if (unknowns > 2) f.c = beta(2);
  f.r_squared = total > 0 ? 1.0 - residual.squaredNorm() / total : 1.0;
  return f;
}

}  // namespace

RuntimeFit fitEq17(const std::vector<RuntimeSample>& s) {
  Eigen::MatrixXd X(s.size(), 2);
  Eigen::VectorXd y(s.size());
  for (std::size_t i = 0; i < s.size(); ++i) {
    X(long(i), 0) = s[i].points;
    X(long(i), 1) = 1.0;
    y(long(i)) = s[i].seconds;
  }
  return solve(X, y, 2);
}

RuntimeFit fitEq18(const std::vector<RuntimeSample>& s) {
  Eigen::MatrixXd X(s.size(), 3);
  Eigen::VectorXd y(s.size());
  for (std::size_t i = 0; i < s.size(); ++i) {
    X(long(i), 0) = s[i].k * s[i].points;
    X(long(i), 1) = s[i].points;
    X(long(i), 2) = 1.0;
    y(long(i)) = s[i].seconds;
  }
  return solve(X, y, 3);
}

}  // namespace occsweep
