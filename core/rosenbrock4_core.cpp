// Compiled as C++17: see rosenbrock4_core.hpp.
#include "core/rosenbrock4_core.hpp"

#include <algorithm>
#include <boost/numeric/odeint.hpp>
#include <utility>

namespace rodend::detail {
namespace {
namespace odeint = boost::numeric::odeint;
using vec = boost::numeric::ublas::vector<double>;
using mat = boost::numeric::ublas::matrix<double>;

/// odeint's coefficients (Hairer and Wanner's RODAS set: gamma = 0.25, c = 0.386, 0.21, 0.63)
/// with the sign of d4 corrected. Boost 1.74 has d4 = +0.0362, Hairer's rodas.f -0.0362; d_i is
/// the coefficient of dt * df/dt in stage i, so with the wrong sign every right-hand side that
/// depends on t (every prescribed motion) makes the step first order: local error O(h^2) where
/// O(h^5) is due, and the embedded estimate O(h^2) too. That is why rosenbrock4 took 1.4 million
/// steps of ~2e-6 s on one thesis cycle. Measured on y'' = -y + cos 3t (one step from t = 0.3):
/// local error 8.0e-4, 2.0e-4, 5.0e-5, 1.3e-5 for h = 0.1 ... 0.0125 with +0.0362, 3.2e-8,
/// 1.1e-9, 3.8e-11, 1.2e-12 with -0.0362 (order 5). Test: "[rosenbrock4]".
struct CorrectedCoefficients : odeint::default_rosenbrock_coefficients<double> {
  const double d4 = -0.3620000000000023e-01;  // shadows the base's +0.0362 (m_coef.d4)
};

class Core final : public Rosenbrock4Core {
 public:
  Core(Rhs rhs, Jac jac) : rhs_(std::move(rhs)), jac_(std::move(jac)) {}

  void try_step(const std::vector<double>& z, double t, double dt, std::vector<double>& z_out,
                std::vector<double>& err) override {
    const std::size_t n = z.size();
    x_.resize(n, false);
    xout_.resize(n, false);
    xerr_.resize(n, false);
    std::copy(z.begin(), z.end(), x_.begin());
    stepper_.do_step(std::make_pair([this](const vec& x, vec& dxdt, double tt) { f(x, dxdt, tt); },
                                    [this](const vec& x, mat& J, double tt, vec& dfdt) {
                                      jacobian(x, J, tt, dfdt);
                                    }),
                     x_, t, xout_, dt, xerr_);
    z_out.assign(xout_.begin(), xout_.end());
    err.assign(xerr_.begin(), xerr_.end());
  }
  void accept() override { stepper_.prepare_dense_output(); }
  void calc_state(double t, std::vector<double>& out, const std::vector<double>& z_old,
                  double t_old, const std::vector<double>& z_new, double t_new) override {
    const std::size_t n = z_old.size();
    a_.resize(n, false);
    b_.resize(n, false);
    c_.resize(n, false);
    std::copy(z_old.begin(), z_old.end(), a_.begin());
    std::copy(z_new.begin(), z_new.end(), b_.begin());
    stepper_.calc_state(t, c_, a_, t_old, b_, t_new);
    out.assign(c_.begin(), c_.end());
  }
  void invalidate_jacobian() override { cached_ = false; }
  long long jacobian_evaluations() const override { return evaluations_; }

 private:
  void f(const vec& x, vec& dxdt, double t) {
    z_.assign(x.begin(), x.end());
    dz_.resize(z_.size());
    rhs_(z_, dz_, t);
    dxdt.resize(z_.size(), false);
    std::copy(dz_.begin(), dz_.end(), dxdt.begin());
  }
  void jacobian(const vec& x, mat& J, double t, vec& dfdt) {
    const std::size_t n = x.size();
    const bool same = cached_ && t == t_jac_ && z_jac_.size() == n &&
                      std::equal(z_jac_.begin(), z_jac_.end(), x.begin());
    if (!same) {
      z_jac_.assign(x.begin(), x.end());
      t_jac_ = t;
      jac_(z_jac_, t, J_, dfdt_);
      cached_ = true;
      ++evaluations_;
    }
    J.resize(n, n, false);
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t j = 0; j < n; ++j) J(i, j) = J_[i * n + j];
    dfdt.resize(n, false);
    std::copy(dfdt_.begin(), dfdt_.end(), dfdt.begin());
  }

  odeint::rosenbrock4<double, CorrectedCoefficients> stepper_;
  Rhs rhs_;
  Jac jac_;
  vec x_, xout_, xerr_, a_, b_, c_;
  std::vector<double> z_, dz_, z_jac_, J_, dfdt_;
  double t_jac_ = 0.0;
  bool cached_ = false;
  long long evaluations_ = 0;
};

}  // namespace

std::unique_ptr<Rosenbrock4Core> make_rosenbrock4(Rosenbrock4Core::Rhs rhs,
                                                  Rosenbrock4Core::Jac jac) {
  return std::make_unique<Core>(std::move(rhs), std::move(jac));
}

}  // namespace rodend::detail
