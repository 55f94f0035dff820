// NCA for regression (fsrnca's formulation), its gradient, an L-BFGS minimiser and lambda by cross-validation.
#include "occsweep/stats/nca.hpp"

#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>
#include <numeric>
#include <stdexcept>

#include "occsweep/core/splitmix64.hpp"

namespace occsweep {
namespace {

// Samples as contiguous columns (d x n): the inner loops below walk one sample's features at a time.
using Columns = Eigen::MatrixXd;

// Softmax neighbour probabilities of sample xi over the columns of `ref` (column `self` excluded, -1 for none).
void neighbourProbabilities(const Columns& ref, const double* xi, const Eigen::VectorXd& w2, double sigma,
                            Eigen::Index self, Eigen::VectorXd& p) {
  const Eigen::Index n = ref.cols(), d = ref.rows();
  p.resize(n);
  double smallest = std::numeric_limits<double>::infinity();
  for (Eigen::Index j = 0; j < n; ++j) {
    if (j == self) continue;
    const double* xj = ref.data() + j * d;
    double dist = 0.0;
    for (Eigen::Index r = 0; r < d; ++r) dist += w2(r) * std::abs(xj[r] - xi[r]);
    p(j) = dist;
    smallest = std::min(smallest, dist);
  }
  double total = 0.0;
  for (Eigen::Index j = 0; j < n; ++j) {
    // exp(-(d - d_min)/sigma): the same ratios, no underflow of every term
    p(j) = j == self ? 0.0 : std::exp(-(p(j) - smallest) / sigma);
    total += p(j);
  }
  p /= total;
}

Eigen::MatrixXd rows(const Eigen::MatrixXd& x, const std::vector<Eigen::Index>& idx) {
  Eigen::MatrixXd out(Eigen::Index(idx.size()), x.cols());
  for (std::size_t i = 0; i < idx.size(); ++i) out.row(Eigen::Index(i)) = x.row(idx[i]);
  return out;
}

Eigen::VectorXd entries(const Eigen::VectorXd& y, const std::vector<Eigen::Index>& idx) {
  Eigen::VectorXd out(Eigen::Index(idx.size()));
  for (std::size_t i = 0; i < idx.size(); ++i) out(Eigen::Index(i)) = y(idx[i]);
  return out;
}

}  // namespace

double ncaObjective(const Eigen::MatrixXd& x, const Eigen::VectorXd& y, const Eigen::VectorXd& w, double lambda,
                    double sigma, Eigen::VectorXd* gradient) {
  const Eigen::Index n = x.rows(), d = x.cols();
  const Columns xt = x.transpose();
  const Eigen::VectorXd w2 = w.cwiseProduct(w);
  Eigen::VectorXd p;
  Eigen::VectorXd weighted(d);  // sum_j p_ij (L_ij - l_i) |x_ir - x_jr| per feature r
  if (gradient) gradient->setZero(d);
  double loss = 0.0;
  for (Eigen::Index i = 0; i < n; ++i) {
    const double* xi = xt.data() + i * d;
    neighbourProbabilities(xt, xi, w2, sigma, i, p);
    double li = 0.0;
    for (Eigen::Index j = 0; j < n; ++j) li += p(j) * std::abs(y(j) - y(i));
    loss += li;
    if (!gradient) continue;
    weighted.setZero();
    for (Eigen::Index j = 0; j < n; ++j) {
      if (j == i || p(j) == 0.0) continue;
      const double coefficient = p(j) * (std::abs(y(j) - y(i)) - li);
      const double* xj = xt.data() + j * d;
      for (Eigen::Index r = 0; r < d; ++r) weighted(r) += coefficient * std::abs(xj[r] - xi[r]);
    }
    // d l_i / d w_r = -(2 w_r / sigma) sum_j p_ij (L_ij - l_i) |x_ir - x_jr|
    *gradient -= (2.0 / sigma) * w.cwiseProduct(weighted);
  }
  if (gradient) *gradient = *gradient / double(n) + 2.0 * lambda * w;
  return loss / double(n) + lambda * w2.sum();
}

Eigen::VectorXd fitNcaWeights(const Eigen::MatrixXd& x, const Eigen::VectorXd& y, double lambda,
                              const NcaConfig& c, int* iterations) {
  constexpr std::size_t kMemory = 10;
  Eigen::VectorXd w = Eigen::VectorXd::Ones(x.cols()), g;
  double f = ncaObjective(x, y, w, lambda, c.sigma, &g);
  std::deque<std::pair<Eigen::VectorXd, Eigen::VectorXd>> history;  // (s, y) pairs
  int it = 0;
  for (; it < c.max_iterations && g.cwiseAbs().maxCoeff() > c.gradient_tolerance; ++it) {
    // Two-loop recursion: direction = -H g.
    Eigen::VectorXd q = g;
    std::vector<double> alpha(history.size());
    for (std::size_t k = history.size(); k-- > 0;) {
      alpha[k] = history[k].first.dot(q) / history[k].second.dot(history[k].first);
      q -= alpha[k] * history[k].second;
    }
    if (!history.empty()) q *= history.back().first.dot(history.back().second) / history.back().second.squaredNorm();
    for (std::size_t k = 0; k < history.size(); ++k) {
      const double beta = history[k].second.dot(q) / history[k].second.dot(history[k].first);
      q += history[k].first * (alpha[k] - beta);
    }
    Eigen::VectorXd dir = -q;
    if (g.dot(dir) >= 0) dir = -g, history.clear();  // not a descent direction: restart from steepest descent
    double step = history.empty() ? std::min(1.0, 1.0 / g.norm()) : 1.0;
    Eigen::VectorXd w_new, g_new;
    double f_new = f;
    bool accepted = false;
    for (int tries = 0; tries < 40; ++tries, step *= 0.5) {
      w_new = w + step * dir;
      f_new = ncaObjective(x, y, w_new, lambda, c.sigma, &g_new);
      if (f_new <= f + 1e-4 * step * g.dot(dir)) {
        accepted = true;
        break;
      }
    }
    if (!accepted) break;
    const Eigen::VectorXd s = w_new - w, yy = g_new - g;
    if (s.dot(yy) > 1e-12) {
      history.emplace_back(s, yy);
      if (history.size() > kMemory) history.pop_front();
    }
    const double change = f - f_new;
    w = w_new, g = g_new, f = f_new;
    if (change <= 1e-10 * std::max(1.0, std::abs(f))) break;
  }
  if (iterations) *iterations = it;
  return w;
}

double ncaTestLoss(const Eigen::MatrixXd& train_x, const Eigen::VectorXd& train_y, const Eigen::VectorXd& w,
                   const Eigen::MatrixXd& test_x, const Eigen::VectorXd& test_y, double sigma) {
  const Columns train = train_x.transpose(), test = test_x.transpose();
  const Eigen::VectorXd w2 = w.cwiseProduct(w);
  Eigen::VectorXd p;
  double loss = 0.0;
  for (Eigen::Index i = 0; i < test.cols(); ++i) {
    neighbourProbabilities(train, test.data() + i * test.rows(), w2, sigma, -1, p);
    loss += std::abs(test_y(i) - p.dot(train_y));
  }
  return loss / double(test.cols());
}

NcaResult ncaFeatureWeights(const Eigen::MatrixXd& x_in, const Eigen::VectorXd& y, const NcaConfig& c) {
  const Eigen::Index n = x_in.rows();
  if (n < 4 || y.size() != n || x_in.cols() < 1) throw std::invalid_argument("NCA: needs >= 4 samples, one y each");
  if (!x_in.allFinite() || !y.allFinite()) throw std::invalid_argument("NCA: features and responses must be finite");
  Eigen::MatrixXd x = x_in;
  if (c.standardize)
    for (Eigen::Index r = 0; r < x.cols(); ++r) {
      const double m = x.col(r).mean();
      const double sd = std::sqrt((x.col(r).array() - m).square().mean());
      x.col(r) = (x.col(r).array() - m) / (sd > 0 ? sd : 1.0);  // a constant feature stays 0 everywhere
    }
  NcaResult r;
  r.samples = std::size_t(n);
  for (double factor : c.lambda_factors) r.lambdas.push_back(factor / double(n));
  r.lambda = 1.0 / double(n);
  if (c.folds >= 2 && !r.lambdas.empty()) {
    std::vector<Eigen::Index> order(static_cast<std::size_t>(n));
    std::iota(order.begin(), order.end(), 0);
    SplitMix64 rng(c.seed);
    for (std::size_t i = order.size(); i > 1; --i) std::swap(order[i - 1], order[rng.below(i)]);
    r.cv_loss.assign(r.lambdas.size(), 0.0);
    for (int fold = 0; fold < c.folds; ++fold) {
      std::vector<Eigen::Index> train, test;
      for (std::size_t i = 0; i < order.size(); ++i) (int(i % std::size_t(c.folds)) == fold ? test : train).push_back(order[i]);
      const Eigen::MatrixXd tx = rows(x, train), vx = rows(x, test);
      const Eigen::VectorXd ty = entries(y, train), vy = entries(y, test);
      for (std::size_t l = 0; l < r.lambdas.size(); ++l) {
        // lambda scales with 1/n of the training fold, as fsrnca's default would there
        const double lambda = c.lambda_factors[l] / double(train.size());
        r.cv_loss[l] += ncaTestLoss(tx, ty, fitNcaWeights(tx, ty, lambda, c), vx, vy, c.sigma) / c.folds;
      }
    }
    r.lambda = r.lambdas[std::size_t(std::min_element(r.cv_loss.begin(), r.cv_loss.end()) - r.cv_loss.begin())];
  }
  const Eigen::VectorXd w = fitNcaWeights(x, y, r.lambda, c, &r.iterations);
  const double total = w.cwiseAbs().sum();
  for (Eigen::Index k = 0; k < w.size(); ++k) {
    r.weights.push_back(std::abs(w(k)));
    r.normalized.push_back(total > 0 ? std::abs(w(k)) / total : 0.0);
  }
  return r;
}

}  // namespace occsweep
