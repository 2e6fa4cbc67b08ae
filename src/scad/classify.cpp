// Classification of quadric leaves: the affine type of {q < 0} by the eigen-decomposition of
// the quadratic part and completion of squares, in coordinates where the domain is [-1, 1]
// (one scale for every axis) and the largest coefficient is 1, so that one relative tolerance
// decides what counts as zero. Every candidate is checked against the quadric's sign on
// samples of the domain.
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <random>

#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/core/placement.hpp"
#include "fuzzycsg/scad/scad.hpp"

namespace fuzzycsg::scad {

namespace {

template <int D>
using Mat = Eigen::Matrix<double, D, D>;
template <int D>
using Vec = Eigen::Matrix<double, D, 1>;

// q(x) = x^T A x + b^T x + k.
template <int D>
struct Quadric {
  Mat<D> a = Mat<D>::Zero();
  Vec<D> b = Vec<D>::Zero();
  double k = 0.0;
  double operator()(const Vec<D>& x) const { return x.dot(a * x) + b.dot(x) + k; }
};

template <int D>
Quadric<D> from_coefficients(std::span<const double> q) {
  Quadric<D> out;
  if constexpr (D == 3) {
    out.a << q[0], 0.5 * q[3], 0.5 * q[5], 0.5 * q[3], q[1], 0.5 * q[4], 0.5 * q[5], 0.5 * q[4],
        q[2];
    out.b << q[6], q[7], q[8];
    out.k = q[9];
  } else {
    out.a << q[0], 0.5 * q[2], 0.5 * q[2], q[1];
    out.b << q[3], q[4];
    out.k = q[5];
  }
  return out;
}

template <int D>
std::vector<double> to_coefficients(const Quadric<D>& q) {
  if constexpr (D == 3) {
    return {q.a(0, 0),     q.a(1, 1), q.a(2, 2), 2 * q.a(0, 1), 2 * q.a(1, 2),
            2 * q.a(0, 2), q.b[0],    q.b[1],    q.b[2],        q.k};
  } else {
    return {q.a(0, 0), q.a(1, 1), 2 * q.a(0, 1), q.b[0], q.b[1], q.k};
  }
}

// The largest absolute coefficient in the tree format's terms (cross terms doubled).
template <int D>
double coefficient_scale(const Quadric<D>& q) {
  double s = std::abs(q.k);
  for (int i = 0; i < D; ++i) {
    s = std::max(s, std::abs(q.b[i]));
    for (int j = i; j < D; ++j) s = std::max(s, (i == j ? 1.0 : 2.0) * std::abs(q.a(i, j)));
  }
  return s;
}

// A candidate in normalized coordinates u: u = center + frame * diag(axes) * v.
template <int D>
struct Candidate {
  QuadricKind kind = QuadricKind::kNone;
  bool outside = false;
  Mat<D> frame = Mat<D>::Identity();
  Vec<D> center = Vec<D>::Zero();
  Vec<D> axes = Vec<D>::Ones();
  std::string note;
};

template <int D>
Mat<D> with_columns(const Mat<D>& v, const std::array<int, D>& order) {
  Mat<D> out;
  for (int c = 0; c < D; ++c) out.col(c) = v.col(order[static_cast<std::size_t>(c)]);
  return out;
}

template <int D>
Candidate<D> classify_normalized(const Quadric<D>& q, double tol) {
  Candidate<D> out;
  const Eigen::SelfAdjointEigenSolver<Mat<D>> es(q.a);
  const Vec<D> lam = es.eigenvalues();
  const Mat<D> vecs = es.eigenvectors();
  const Vec<D> bt = vecs.transpose() * q.b;
  std::vector<int> pos, neg, zero;
  for (int i = 0; i < D; ++i) {
    if (std::abs(lam[i]) <= tol) {
      zero.push_back(i);
    } else {
      (lam[i] > 0 ? pos : neg).push_back(i);
    }
  }
  // Completed squares: q = sum_nz lam_i (y_i - y0_i)^2 + sum_z bt_i y_i + c.
  Vec<D> y0 = Vec<D>::Zero();
  double c = q.k;
  for (int i = 0; i < D; ++i) {
    if (std::abs(lam[i]) <= tol) continue;
    y0[i] = -bt[i] / (2 * lam[i]);
    c -= bt[i] * bt[i] / (4 * lam[i]);
  }
  const int rank = static_cast<int>(pos.size() + neg.size());
  const bool one_sign = pos.empty() || neg.empty();
  const bool positive = !pos.empty();  // with one_sign: the sign of the nonzero eigenvalues
  const auto constant = [&](bool full) {
    out.kind = full ? QuadricKind::kFull : QuadricKind::kEmpty;
    return out;
  };

  if (rank == D) {
    if (one_sign) {
      // Definite: an ellipsoid (its inside or outside) or nothing / everything.
      if (positive ? c >= 0 : c <= 0) return constant(!positive);
      out.kind = QuadricKind::kEllipsoid;
      out.outside = !positive;
      out.frame = vecs;
      out.center = vecs * y0;
      for (int i = 0; i < D; ++i) out.axes[i] = std::sqrt(std::abs(c / lam[i]));
      return out;
    }
    if (D == 3 && std::abs(c) <= tol) {
      // An elliptic cone: the axis is the eigenvector of the odd sign.
      const int m = pos.size() == 1 ? pos[0] : neg[0];
      std::array<int, D> order{};
      int k = 0;
      for (int i = 0; i < D; ++i) {
        if (i != m) order[static_cast<std::size_t>(k++)] = i;
      }
      order[D - 1] = m;
      out.kind = QuadricKind::kCone;
      out.outside = lam[m] > 0;
      out.frame = with_columns<D>(vecs, order);
      out.center = vecs * y0;
      for (int i = 0; i < D - 1; ++i) {
        out.axes[i] = std::sqrt(std::abs(lam[m] / lam[order[static_cast<std::size_t>(i)]]));
      }
      out.axes[D - 1] = 1.0;
      return out;
    }
    if (D == 2) {
      out.note = std::abs(c) <= tol ? "two crossing lines" : "a hyperbola";
    } else {
      const bool one_sheet = (c < 0) == (pos.size() == 2);
      out.note = one_sheet ? "a hyperboloid of one sheet" : "a hyperboloid of two sheets";
    }
    return out;
  }

  if (rank == D - 1) {
    const int z = zero[0];
    const double beta = bt[z];
    std::array<int, D> order{};
    int k = 0;
    for (int i = 0; i < D; ++i) {
      if (i != z) order[static_cast<std::size_t>(k++)] = i;
    }
    order[D - 1] = z;
    if (!one_sign) {
      // Only in 3D (in 2D rank 1 has one nonzero eigenvalue).
      out.note = std::abs(beta) > tol
                     ? "a hyperbolic paraboloid (saddle)"
                     : (std::abs(c) <= tol ? "two crossing planes" : "a hyperbolic cylinder");
      return out;
    }
    if (std::abs(beta) <= tol) {
      if (positive ? c >= 0 : c <= 0) return constant(!positive);
      out.outside = !positive;
      out.center = vecs * y0;
      if constexpr (D == 3) {
        // An elliptic cylinder along the zero eigenvector.
        out.kind = QuadricKind::kCylinder;
        out.frame = with_columns<D>(vecs, order);
        for (int i = 0; i < D - 1; ++i) {
          out.axes[i] = std::sqrt(std::abs(c / lam[order[static_cast<std::size_t>(i)]]));
        }
        out.axes[D - 1] = 1.0;
      } else {
        // A band between two lines along the zero eigenvector: |v2| < 1 across it.
        out.kind = QuadricKind::kSlab;
        out.frame = with_columns<D>(vecs, {z, 1 - z});
        out.axes[0] = 1.0;
        out.axes[1] = std::sqrt(std::abs(c / lam[1 - z]));
      }
      return out;
    }
    // An elliptic paraboloid (2D: parabola) opening along sigma * the zero eigenvector.
    const double sigma = positive ? -std::copysign(1.0, beta) : std::copysign(1.0, beta);
    Vec<D> apex = y0;
    apex[z] = -c / beta;
    out.kind = QuadricKind::kParaboloid;
    out.outside = !positive;
    out.frame = with_columns<D>(vecs, order);
    out.frame.col(D - 1) *= sigma;
    out.center = vecs * apex;
    for (int i = 0; i < D - 1; ++i) {
      out.axes[i] = std::sqrt(std::abs(beta / lam[order[static_cast<std::size_t>(i)]]));
    }
    out.axes[D - 1] = 1.0;
    return out;
  }

  if (rank == 1) {  // 3D with two zero eigenvalues
    const int m = pos.empty() ? neg[0] : pos[0];
    const double beta = std::hypot(bt[zero[0]], bt[zero[1]]);
    if (beta > tol) {
      out.note = "a parabolic cylinder";
      return out;
    }
    if (positive ? c >= 0 : c <= 0) return constant(!positive);
    std::array<int, D> order{};
    order[0] = zero[0];
    order[1] = zero[1];
    order[D - 1] = m;
    out.kind = QuadricKind::kSlab;
    out.outside = !positive;
    out.frame = with_columns<D>(vecs, order);
    out.center = vecs * y0;
    out.axes.setOnes();
    out.axes[D - 1] = std::sqrt(std::abs(c / lam[m]));
    return out;
  }

  // rank 0: linear or constant.
  const double nb = q.b.norm();
  if (nb <= tol) return constant(q.k < 0);
  const Vec<D> n = q.b / nb;
  out.kind = QuadricKind::kPlane;
  out.center = (-q.k / nb) * n;
  if constexpr (D == 3) {
    const Eigen::Vector3d t1 = Eigen::Vector3d(n).unitOrthogonal();
    const Eigen::Vector3d t2 = Eigen::Vector3d(n).cross(t1);
    out.frame.col(0) = t1;
    out.frame.col(1) = t2;
    out.frame.col(2) = n;
  } else {
    out.frame.col(0) = Vec<D>(n[1], -n[0]);
    out.frame.col(1) = n;
  }
  return out;
}

// The candidate in world coordinates x = c_d + h u, with each kind's axes brought to the
// documented normalisation.
template <int D>
QuadricClass to_world(const Candidate<D>& cand, const Vec<D>& cd, double h, double tol) {
  QuadricClass out;
  out.dim = D;
  out.kind = cand.kind;
  out.outside = cand.outside;
  out.note = cand.note;
  if (cand.kind == QuadricKind::kNone || cand.kind == QuadricKind::kEmpty ||
      cand.kind == QuadricKind::kFull) {
    return out;
  }
  Mat<D> frame = cand.frame;
  if (frame.determinant() < 0) frame.col(0) *= -1.0;  // every kind is symmetric in v1
  Vec<D> axes = h * cand.axes;
  switch (cand.kind) {
    case QuadricKind::kCylinder:
      axes[D - 1] = 1.0;
      break;
    case QuadricKind::kCone:
      axes /= axes[D - 1];
      break;
    case QuadricKind::kParaboloid:
      for (int i = 0; i < D - 1; ++i) axes[i] /= std::sqrt(axes[D - 1]);
      axes[D - 1] = 1.0;
      break;
    case QuadricKind::kPlane:
      axes.setOnes();
      break;
    case QuadricKind::kSlab:
      for (int i = 0; i < D - 1; ++i) axes[i] = 1.0;
      break;
    default:
      break;
  }
  // Equal radii within the tolerance: one radius (a sphere, a circular cylinder or cone).
  const int round = cand.kind == QuadricKind::kEllipsoid ? D
                    : (cand.kind == QuadricKind::kCylinder || cand.kind == QuadricKind::kCone ||
                       cand.kind == QuadricKind::kParaboloid)
                        ? D - 1
                        : 0;
  if (round >= 2) {
    const double lo = axes.head(round).minCoeff(), hi = axes.head(round).maxCoeff();
    if (hi - lo <= tol * hi) {
      const double mean = axes.head(round).mean();
      for (int i = 0; i < round; ++i) axes[i] = mean;
      if (cand.kind == QuadricKind::kEllipsoid) out.kind = QuadricKind::kSphere;
    }
  }
  for (int r = 0; r < D; ++r) {
    for (int col = 0; col < D; ++col) {
      out.rotation[static_cast<std::size_t>(r * 3 + col)] = frame(r, col);
    }
  }
  const Vec<D> center = cd + h * cand.center;
  for (int i = 0; i < D; ++i) {
    out.center[static_cast<std::size_t>(i)] = center[i];
    out.axes[static_cast<std::size_t>(i)] = axes[i];
  }
  return out;
}

// Fraction of uniform samples of the domain where the classification's sign agrees with the
// quadric's; `accept` also applies the relative criterion.
template <int D>
bool validate(const Quadric<D>& world, QuadricClass& cls, const Domain& domain,
              const ClassifyOptions& o) {
  std::mt19937_64 rng(o.seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const int n = std::max(o.samples, 1);
  int agree = 0, inside = 0;
  for (int s = 0; s < n; ++s) {
    Vec<D> x;
    for (int i = 0; i < D; ++i) {
      x[i] = domain.min[static_cast<std::size_t>(i)] +
             unit(rng) * (domain.max[static_cast<std::size_t>(i)] -
                          domain.min[static_cast<std::size_t>(i)]);
    }
    const bool in_q = world(x) < 0;
    const bool in_c = cls.value(x.data()) < 0;
    agree += in_q == in_c ? 1 : 0;
    inside += in_q ? 1 : 0;
  }
  const int wrong = n - agree;
  cls.agreement = static_cast<double>(agree) / n;
  const int smaller = std::min(inside, n - inside);
  return cls.agreement >= o.min_agreement && wrong <= o.max_relative_error * smaller;
}

template <int D>
QuadricClass classify(std::span<const double> coefficients, const Domain& domain,
                      const ClassifyOptions& o) {
  const Quadric<D> world = from_coefficients<D>(coefficients);
  Vec<D> cd;
  double h = 0.0;
  for (int i = 0; i < D; ++i) {
    const auto a = static_cast<std::size_t>(i);
    cd[i] = 0.5 * (domain.min[a] + domain.max[a]);
    h = std::max(h, 0.5 * (domain.max[a] - domain.min[a]));
  }
  // q(cd + h u) = h^2 u^T A u + h (2 A cd + b)^T u + q(cd), divided by its largest coefficient.
  Quadric<D> nq;
  nq.a = h * h * world.a;
  nq.b = h * (2.0 * world.a * cd + world.b);
  nq.k = world(cd);
  const double scale = coefficient_scale(nq);
  QuadricClass refused;
  refused.dim = D;
  if (!(scale > 0) || !std::isfinite(scale)) {
    refused.kind = QuadricKind::kEmpty;  // q == 0: q < 0 nowhere
    refused.agreement = 1.0;
    if (!std::isfinite(scale)) {
      refused.kind = QuadricKind::kNone;
      refused.note = "coefficients out of range";
    }
    return refused;
  }
  nq.a /= scale;
  nq.b /= scale;
  nq.k /= scale;
  std::vector<double> tolerances{o.tolerance};
  if (o.tolerance > 1e-9) tolerances.push_back(1e-9);
  for (const double tol : tolerances) {
    QuadricClass cls = to_world<D>(classify_normalized<D>(nq, tol), cd, h, tol);
    if (cls.kind == QuadricKind::kNone) {
      if (refused.note.empty()) refused.note = cls.note;
      continue;
    }
    if (validate<D>(world, cls, domain, o)) return cls;
    if (refused.note.empty()) {
      refused.note = std::string(kind_name(cls.kind, D)) + " refused: signs agree on " +
                     std::to_string(cls.agreement * 100.0).substr(0, 5) + "% of the samples";
    }
    refused.agreement = std::max(refused.agreement, cls.agreement);
  }
  return refused;
}

}  // namespace

std::string_view kind_name(QuadricKind kind, int dim) {
  switch (kind) {
    case QuadricKind::kNone:
      return "none";
    case QuadricKind::kEmpty:
      return "empty";
    case QuadricKind::kFull:
      return "full";
    case QuadricKind::kSphere:
      return dim == 2 ? "circle" : "sphere";
    case QuadricKind::kEllipsoid:
      return dim == 2 ? "ellipse" : "ellipsoid";
    case QuadricKind::kCylinder:
      return "cylinder";
    case QuadricKind::kCone:
      return "cone";
    case QuadricKind::kPlane:
      return dim == 2 ? "half-plane" : "plane";
    case QuadricKind::kParaboloid:
      return dim == 2 ? "parabola" : "paraboloid";
    case QuadricKind::kSlab:
      return dim == 2 ? "band" : "slab";
  }
  return "none";
}

std::array<double, 12> QuadricClass::affine() const {
  std::array<double, 12> m{};
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) {
      const auto rc = static_cast<std::size_t>(r * 3 + c);
      m[static_cast<std::size_t>(r * 4 + c)] = rotation[rc] * axes[static_cast<std::size_t>(c)];
    }
    m[static_cast<std::size_t>(r * 4 + 3)] = center[static_cast<std::size_t>(r)];
  }
  return m;
}

double QuadricClass::value(const double* x) const {
  if (kind == QuadricKind::kEmpty) return 1.0;
  if (kind == QuadricKind::kFull) return -1.0;
  // v = diag(1 / axes) R^T (x - center).
  std::array<double, 3> v{0, 0, 0};
  for (int c = 0; c < dim; ++c) {
    double s = 0.0;
    for (int r = 0; r < dim; ++r) {
      s += rotation[static_cast<std::size_t>(r * 3 + c)] *
           (x[r] - center[static_cast<std::size_t>(r)]);
    }
    v[static_cast<std::size_t>(c)] = s / axes[static_cast<std::size_t>(c)];
  }
  const double last = v[static_cast<std::size_t>(dim - 1)];
  double across = 0.0;  // sum of squares of the coordinates before the last
  for (int i = 0; i + 1 < dim; ++i)
    across += v[static_cast<std::size_t>(i)] * v[static_cast<std::size_t>(i)];
  double g = 1.0;
  switch (kind) {
    case QuadricKind::kSphere:
    case QuadricKind::kEllipsoid:
      g = across + last * last - 1.0;
      break;
    case QuadricKind::kCylinder:
      g = across - 1.0;
      break;
    case QuadricKind::kCone:
      g = across - last * last;
      break;
    case QuadricKind::kPlane:
      g = last;
      break;
    case QuadricKind::kParaboloid:
      g = across - last;
      break;
    case QuadricKind::kSlab:
      g = last * last - 1.0;
      break;
    default:
      break;
  }
  return outside ? -g : g;
}

QuadricClass classify_quadric(int dim, std::span<const double> coefficients, const Domain& domain,
                              const ClassifyOptions& options) {
  if (dim != 2 && dim != 3) throw InputError("classify_quadric: dim must be 2 or 3");
  const std::size_t want = dim == 3 ? 10 : 6;
  if (coefficients.size() != want) {
    throw InputError("classify_quadric: expected " + std::to_string(want) + " coefficients (got " +
                     std::to_string(coefficients.size()) + ")");
  }
  for (int i = 0; i < dim; ++i) {
    if (!(domain.max[static_cast<std::size_t>(i)] > domain.min[static_cast<std::size_t>(i)])) {
      throw InputError("classify_quadric: the domain is empty");
    }
  }
  return dim == 3 ? classify<3>(coefficients, domain, options)
                  : classify<2>(coefficients, domain, options);
}

std::vector<double> world_quadric(const Tree& tree, std::span<const double> params, int node) {
  const Node& n = tree.node(node);
  if (n.kind != NodeKind::kPrimitive ||
      (n.shape.type != PrimitiveType::kQuadric3 && n.shape.type != PrimitiveType::kQuadric2)) {
    throw Error("world_quadric: node " + std::to_string(node) + " is not a quadric leaf");
  }
  std::vector<double> local(n.intrinsic.size());
  for (std::size_t i = 0; i < local.size(); ++i) local[i] = params[n.intrinsic[i].index];
  const auto fold = [&]<int D>(Quadric<D> q) {
    // p_local = B p + e with B = R^T / s, e = -R^T t / s; q_world = s q_local(B p + e).
    Mat<D> r = Mat<D>::Identity();
    const auto& pl = n.placement;
    if (!pl.rotate.empty()) {
      if constexpr (D == 3) {
        const auto m = placement::rotation_3d(
            params[pl.rotate[0].index], params[pl.rotate[1].index], params[pl.rotate[2].index]);
        for (int i = 0; i < 9; ++i) r(i / 3, i % 3) = m[static_cast<std::size_t>(i)];
      } else {
        const auto m = placement::rotation_2d(params[pl.rotate[0].index]);
        for (int i = 0; i < 4; ++i) r(i / 2, i % 2) = m[static_cast<std::size_t>(i)];
      }
    }
    Vec<D> t = Vec<D>::Zero();
    if (!pl.translate.empty()) {
      for (int i = 0; i < D; ++i) t[i] = params[pl.translate[static_cast<std::size_t>(i)].index];
    }
    const double s = pl.scale ? params[pl.scale->index] : 1.0;
    const Mat<D> b = r.transpose() / s;
    const Vec<D> e = -(r.transpose() * t) / s;
    Quadric<D> w;
    w.a = s * (b.transpose() * q.a * b);
    w.b = s * (2.0 * b.transpose() * q.a * e + b.transpose() * q.b);
    w.k = s * (e.dot(q.a * e) + q.b.dot(e) + q.k);
    return to_coefficients<D>(w);
  };
  return tree.dim == 3 ? fold(from_coefficients<3>(local)) : fold(from_coefficients<2>(local));
}

}  // namespace fuzzycsg::scad
