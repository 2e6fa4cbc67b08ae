#include "fuzzycsg/optim/cmaes.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>

#include "fuzzycsg/core/error.hpp"

namespace fuzzycsg::optim {

CmaesResult cmaes_minimize(const std::function<double(std::span<const double>)>& f,
                           const std::vector<double>& x0, const std::vector<double>& scale,
                           const CmaesOptions& o,
                           const std::function<bool(std::span<const double>, double)>& generation) {
  const int n = static_cast<int>(x0.size());
  if (n == 0) throw InputError("cmaes: no parameters to optimise");
  if (scale.size() != x0.size()) throw InputError("cmaes: one scale per parameter expected");
  for (const double s : scale) {
    if (!(s > 0)) throw InputError("cmaes: scales must be > 0");
  }
  if (!(o.sigma > 0)) throw InputError("cmaes: sigma must be > 0");
  if (o.population < 0 || o.max_evaluations < 1) throw InputError("cmaes: bad budget");
  using Vec = Eigen::VectorXd;
  using Mat = Eigen::MatrixXd;
  const int lambda = o.population > 0 ? o.population : 4 + static_cast<int>(3 * std::log(n));
  const int mu = lambda / 2;
  Vec w(mu);
  for (int i = 0; i < mu; ++i) w[i] = std::log(mu + 0.5) - std::log(i + 1.0);
  w /= w.sum();
  const double mueff = 1 / w.squaredNorm();
  const double dn = n;
  const double cc = (4 + mueff / dn) / (dn + 4 + 2 * mueff / dn);
  const double cs = (mueff + 2) / (dn + mueff + 5);
  const double c1 = 2 / ((dn + 1.3) * (dn + 1.3) + mueff);
  const double cmu = std::min(1 - c1, 2 * (mueff - 2 + 1 / mueff) / ((dn + 2) * (dn + 2) + mueff));
  const double damps = 1 + 2 * std::max(0.0, std::sqrt((mueff - 1) / (dn + 1)) - 1) + cs;
  const double chi_n = std::sqrt(dn) * (1 - 1 / (4 * dn) + 1 / (21 * dn * dn));

  Vec mean = Vec::Zero(n), pc = Vec::Zero(n), ps = Vec::Zero(n), diag = Vec::Ones(n);
  Mat c = Mat::Identity(n, n), b = Mat::Identity(n, n), inv_sqrt_c = Mat::Identity(n, n);
  double sigma = o.sigma;
  long eigen_at = 0;
  std::mt19937_64 rng(o.seed);
  std::normal_distribution<double> normal(0, 1);

  CmaesResult r;
  std::vector<double> x(x0.size());
  const auto evaluate = [&](const Vec& y) {
    for (int k = 0; k < n; ++k) {
      x[static_cast<std::size_t>(k)] =
          x0[static_cast<std::size_t>(k)] + scale[static_cast<std::size_t>(k)] * y[k];
    }
    const double v = f(x);
    ++r.evaluations;
    if (v < r.best_value || r.best.empty()) {
      r.best_value = v;
      r.best = x;
    }
    return v;
  };
  evaluate(mean);
  std::vector<Vec> ys(static_cast<std::size_t>(lambda), Vec(n));
  std::vector<double> values(static_cast<std::size_t>(lambda));
  std::vector<int> order(static_cast<std::size_t>(lambda));
  for (;;) {
    if (r.best_value <= o.stop_value) {
      r.stopped_by = "value";
      break;
    }
    if (r.evaluations + lambda > o.max_evaluations) {
      r.stopped_by = "evaluations";
      break;
    }
    for (int k = 0; k < lambda; ++k) {
      Vec z(n);
      for (int i = 0; i < n; ++i) z[i] = normal(rng);
      ys[static_cast<std::size_t>(k)] = mean + sigma * (b * diag.cwiseProduct(z));
      values[static_cast<std::size_t>(k)] = evaluate(ys[static_cast<std::size_t>(k)]);
    }
    ++r.generations;
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(), [&](int a, int bb) {
      return values[static_cast<std::size_t>(a)] < values[static_cast<std::size_t>(bb)];
    });
    const Vec old = mean;
    mean.setZero();
    for (int i = 0; i < mu; ++i) mean += w[i] * ys[static_cast<std::size_t>(order[i])];
    const Vec step = (mean - old) / sigma;
    ps = (1 - cs) * ps + std::sqrt(cs * (2 - cs) * mueff) * (inv_sqrt_c * step);
    const double ps_norm = ps.norm();
    const bool hsig =
        ps_norm / std::sqrt(1 - std::pow(1 - cs, 2.0 * r.generations)) / chi_n < 1.4 + 2 / (dn + 1);
    pc = (1 - cc) * pc + (hsig ? std::sqrt(cc * (2 - cc) * mueff) : 0.0) * step;
    Mat rank_mu = Mat::Zero(n, n);
    for (int i = 0; i < mu; ++i) {
      const Vec d = (ys[static_cast<std::size_t>(order[i])] - old) / sigma;
      rank_mu += w[i] * d * d.transpose();
    }
    c = (1 - c1 - cmu) * c + c1 * (pc * pc.transpose() + (hsig ? 0.0 : cc * (2 - cc)) * c) +
        cmu * rank_mu;
    sigma *= std::exp((cs / damps) * (ps_norm / chi_n - 1));
    if (r.evaluations - eigen_at > lambda / (c1 + cmu) / dn / 10) {
      eigen_at = r.evaluations;
      c = (c + c.transpose()) / 2;
      Eigen::SelfAdjointEigenSolver<Mat> es(c);
      Vec ev = es.eigenvalues().cwiseMax(1e-20);
      b = es.eigenvectors();
      diag = ev.cwiseSqrt();
      inv_sqrt_c = b * diag.cwiseInverse().asDiagonal() * b.transpose();
    }
    if (generation && !generation(r.best, r.best_value)) {
      r.stopped_by = "callback";
      break;
    }
    if (sigma * diag.maxCoeff() < o.tol_sigma) {
      r.stopped_by = "sigma";
      break;
    }
  }
  return r;
}

}  // namespace fuzzycsg::optim
