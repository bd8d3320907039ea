// Forward-mode differentiation: a dual number carrying a value and its N partial derivatives
// (a gradient with respect to N seeded inputs), for exact Jacobians of a right-hand side written
// once as a template on its scalar (Scene::jacobian). With S = double the same template is the
// ordinary right-hand side, so the two never disagree.
//
// Generic code reads a value with value_of(s) and uses the helpers max_of / min_of, which are
// std::max / std::min for double. Branches compare values: a derivative is that of the branch
// taken (one-sided at a kink, as a difference quotient would be on that side).
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

namespace rodend {

template <int N>
struct Dual {
  using Grad = Eigen::Matrix<double, N, 1>;
  double v;  ///< value
  Grad d;    ///< partial derivatives with respect to the seeded inputs

  /// Uninitialised, as a double is: Eigen default-constructs the scalars of every vector it
  /// makes before assigning them, and zeroing the derivatives there cost a sixth of a Jacobian.
  Dual() {}  // NOLINT(modernize-use-equals-default): v and d left uninitialised on purpose
  Dual(double value) : v(value), d(Grad::Zero()) {}  // NOLINT: a constant: no derivatives
  Dual(double value, const Grad& grad) : v(value), d(grad) {}
  /// Input number `i` of the seeded ones, at `value`.
  static Dual seed(double value, int i) {
    Dual x(value);
    x.d[i] = 1.0;
    return x;
  }
  Dual& operator+=(const Dual& b) {
    v += b.v;
    d += b.d;
    return *this;
  }
  Dual& operator-=(const Dual& b) {
    v -= b.v;
    d -= b.d;
    return *this;
  }
  Dual& operator*=(const Dual& b) {
    d = d * b.v + b.d * v;
    v *= b.v;
    return *this;
  }
  Dual& operator/=(const Dual& b) { return *this = *this / b; }
  Dual& operator+=(double b) {
    v += b;
    return *this;
  }
  Dual& operator*=(double b) {
    v *= b;
    d *= b;
    return *this;
  }
  friend Dual operator-(const Dual& a) { return Dual(-a.v, -a.d); }
  friend Dual operator+(const Dual& a) { return a; }
  friend EIGEN_STRONG_INLINE Dual operator+(const Dual& a, const Dual& b) {
    return Dual(a.v + b.v, a.d + b.d);
  }
  friend EIGEN_STRONG_INLINE Dual operator-(const Dual& a, const Dual& b) {
    return Dual(a.v - b.v, a.d - b.d);
  }
  friend EIGEN_STRONG_INLINE Dual operator*(const Dual& a, const Dual& b) {
    return Dual(a.v * b.v, a.d * b.v + b.d * a.v);
  }
  friend Dual operator/(const Dual& a, const Dual& b) {
    const double q = a.v / b.v;
    return Dual(q, (a.d - b.d * q) / b.v);
  }
  friend Dual operator+(const Dual& a, double b) { return Dual(a.v + b, a.d); }
  friend Dual operator+(double a, const Dual& b) { return Dual(a + b.v, b.d); }
  friend Dual operator-(const Dual& a, double b) { return Dual(a.v - b, a.d); }
  friend Dual operator-(double a, const Dual& b) { return Dual(a - b.v, -b.d); }
  friend Dual operator*(const Dual& a, double b) { return Dual(a.v * b, a.d * b); }
  friend Dual operator*(double a, const Dual& b) { return Dual(a * b.v, b.d * a); }
  friend Dual operator/(const Dual& a, double b) { return Dual(a.v / b, a.d / b); }
  friend Dual operator/(double a, const Dual& b) {
    const double q = a / b.v;
    return Dual(q, b.d * (-q / b.v));
  }
#define RODEND_DUAL_COMPARE(op)                           \
  friend bool operator op(const Dual& a, const Dual& b) { \
    return a.v op b.v;                                    \
  }                                                       \
  friend bool operator op(const Dual& a, double b) {      \
    return a.v op b;                                      \
  }                                                       \
  friend bool operator op(double a, const Dual& b) {      \
    return a op b.v;                                      \
  }
  RODEND_DUAL_COMPARE(<)
  RODEND_DUAL_COMPARE(>)
  RODEND_DUAL_COMPARE(<=)
  RODEND_DUAL_COMPARE(>=)
  RODEND_DUAL_COMPARE(==)
  RODEND_DUAL_COMPARE(!=)
#undef RODEND_DUAL_COMPARE

  /// f(a) from f(a.v) and f'(a.v).
  static Dual chain(const Dual& a, double f, double df) {
    return Dual(f, a.d * df);
  }
  friend Dual sqrt(const Dual& a) {
    const double r = std::sqrt(a.v);
    return chain(a, r, 0.5 / r);
  }
  friend Dual abs(const Dual& a) {
    return a.v < 0.0 ? -a : a;
  }
  friend Dual sin(const Dual& a) {
    return chain(a, std::sin(a.v), std::cos(a.v));
  }
  friend Dual cos(const Dual& a) {
    return chain(a, std::cos(a.v), -std::sin(a.v));
  }
  friend Dual tanh(const Dual& a) {
    const double t = std::tanh(a.v);
    return chain(a, t, 1.0 - t * t);
  }
  friend Dual pow(const Dual& a, double n) {
    const double p = std::pow(a.v, n);
    return chain(a, p, n * std::pow(a.v, n - 1.0));
  }
  friend Dual atan2(const Dual& y, const Dual& x) {
    const double r2 = x.v * x.v + y.v * y.v;
    return Dual(std::atan2(y.v, x.v), (y.d * x.v - x.d * y.v) / r2);
  }
};

inline double value_of(double s) {
  return s;
}
template <int N>
double value_of(const Dual<N>& s) {
  return s.v;
}

/// std::max / std::min for double (the same result bit for bit); for a dual, the argument that
/// std::max would return.
inline double max_of(double a, double b) {
  return std::max(a, b);
}
inline double min_of(double a, double b) {
  return std::min(a, b);
}
template <int N>
Dual<N> max_of(const Dual<N>& a, double b) {
  return a < b ? Dual<N>(b) : a;
}
template <int N>
Dual<N> max_of(double a, const Dual<N>& b) {
  return a < b ? b : Dual<N>(a);
}
template <int N>
Dual<N> min_of(const Dual<N>& a, double b) {
  return b < a ? Dual<N>(b) : a;
}
template <int N>
Dual<N> min_of(const Dual<N>& a, const Dual<N>& b) {
  return b < a ? b : a;
}

/// The Jacobian J[i * n + j] = d f_i / d x_j (row-major) of f: R^n -> R^n at x, by one call of
/// `f(const Dual<N>* x, Dual<N>* f)` with the first N states seeded; the other columns (states
/// f does not read, e.g. energy integrals) are zero.
template <int N, class F>
void dual_jacobian(int n, const double* x, double* J, F&& f) {
  const auto un = static_cast<std::size_t>(n);
  std::vector<Dual<N>> xd(un), fd(un);
  for (int j = 0; j < n; ++j)
    xd[static_cast<std::size_t>(j)] = j < N ? Dual<N>::seed(x[j], j) : Dual<N>(x[j]);
  f(xd.data(), fd.data());
  for (std::size_t i = 0; i < un; ++i)
    for (std::size_t j = 0; j < un; ++j)
      J[i * un + j] = j < static_cast<std::size_t>(N) ? fd[i].d[static_cast<Eigen::Index>(j)] : 0.0;
}

}  // namespace rodend

namespace Eigen {

template <int N>
struct NumTraits<rodend::Dual<N>> : NumTraits<double> {
  using Real = rodend::Dual<N>;
  using NonInteger = rodend::Dual<N>;
  using Nested = rodend::Dual<N>;
  using Literal = double;
  enum {
    IsComplex = 0,
    IsInteger = 0,
    IsSigned = 1,
    RequireInitialization = 1,
    ReadCost = N + 1,
    AddCost = N + 1,
    MulCost = 2 * N + 1
  };
};

template <int N, typename BinaryOp>
struct ScalarBinaryOpTraits<rodend::Dual<N>, double, BinaryOp> {
  using ReturnType = rodend::Dual<N>;
};
template <int N, typename BinaryOp>
struct ScalarBinaryOpTraits<double, rodend::Dual<N>, BinaryOp> {
  using ReturnType = rodend::Dual<N>;
};

}  // namespace Eigen
