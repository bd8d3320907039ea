// Compiled as C++17: see rosenbrock4_core.hpp.
#include "core/rosenbrock4_core.hpp"

#include <algorithm>
#include <boost/numeric/odeint.hpp>
#include <cmath>
#include <limits>

namespace rodend::detail {
namespace {
namespace odeint = boost::numeric::odeint;
using vec = boost::numeric::ublas::vector<double>;
using mat = boost::numeric::ublas::matrix<double>;

class Core final : public Rosenbrock4Core {
 public:
  Core(double a, double r, double max_dt, Rhs rhs)
      : dense_(odeint::rosenbrock4_controller<odeint::rosenbrock4<double>>(a, r, max_dt)),
        rhs_(std::move(rhs)) {}

  void initialize(const std::vector<double>& z, double t, double dt) override {
    vec x(z.size());
    std::copy(z.begin(), z.end(), x.begin());
    dense_.initialize(x, t, dt);
  }
  std::pair<double, double> do_step() override {
    return dense_.do_step(std::make_pair(
        [this](const vec& x, vec& dxdt, double t) { f(x, dxdt, t); },
        [this](const vec& x, mat& J, double t, vec& dfdt) { jacobian(x, J, t, dfdt); }));
  }
  void calc_state(double t, std::vector<double>& out) override {
    vec x(dense_.current_state().size());
    dense_.calc_state(t, x);
    out.assign(x.begin(), x.end());
  }
  void current_state(std::vector<double>& out) const override {
    out.assign(dense_.current_state().begin(), dense_.current_state().end());
  }
  double current_time_step() const override { return dense_.current_time_step(); }

 private:
  void f(const vec& x, vec& dxdt, double t) {
    z_.assign(x.begin(), x.end());
    dz_.resize(z_.size());
    rhs_(z_, dz_, t);
    dxdt.resize(z_.size());
    std::copy(dz_.begin(), dz_.end(), dxdt.begin());
  }
  // forward differences on the scaled state: one increment size suits every component
  void jacobian(const vec& x, mat& J, double t, vec& dfdt) {
    const std::size_t n = x.size();
    const double eps = std::sqrt(std::numeric_limits<double>::epsilon());
    z_.assign(x.begin(), x.end());
    dz_.resize(n);
    dz2_.resize(n);
    rhs_(z_, dz_, t);
    J.resize(n, n);
    for (std::size_t j = 0; j < n; ++j) {
      const double h = eps * std::max(1.0, std::abs(z_[j]));
      const double keep = z_[j];
      z_[j] = keep + h;
      rhs_(z_, dz2_, t);
      z_[j] = keep;
      for (std::size_t i = 0; i < n; ++i) J(i, j) = (dz2_[i] - dz_[i]) / h;
    }
    const double ht = eps * std::max(1.0, std::abs(t));
    rhs_(z_, dz2_, t + ht);
    dfdt.resize(n);
    for (std::size_t i = 0; i < n; ++i) dfdt[i] = (dz2_[i] - dz_[i]) / ht;
  }

  odeint::rosenbrock4_dense_output<odeint::rosenbrock4_controller<odeint::rosenbrock4<double>>>
      dense_;
  Rhs rhs_;
  std::vector<double> z_, dz_, dz2_;
};

}  // namespace

std::unique_ptr<Rosenbrock4Core> make_rosenbrock4(double abs_tol, double rel_tol, double max_dt,
                                                  Rosenbrock4Core::Rhs rhs) {
  return std::make_unique<Core>(abs_tol, rel_tol, max_dt, std::move(rhs));
}

}  // namespace rodend::detail
