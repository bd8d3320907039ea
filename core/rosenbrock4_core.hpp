// Internal to core: odeint's rosenbrock4 behind a C++17 interface. Boost 1.74's uBLAS (which
// rosenbrock4 needs) does not compile as C++20 (std::allocator::construct is gone), so
// rosenbrock4_core.cpp is compiled as C++17 and sees only this header.
#pragma once

#include <functional>
#include <memory>
#include <utility>
#include <vector>

namespace rodend::detail {

/// A dense-output Rosenbrock 4 stepper on std::vector states; the Jacobian is taken by forward
/// differences of `rhs`.
class Rosenbrock4Core {
 public:
  using Rhs = std::function<void(const std::vector<double>&, std::vector<double>&, double)>;
  virtual ~Rosenbrock4Core() = default;
  virtual void initialize(const std::vector<double>& z, double t, double dt) = 0;
  virtual std::pair<double, double> do_step() = 0;
  virtual void calc_state(double t, std::vector<double>& out) = 0;
  virtual void current_state(std::vector<double>& out) const = 0;
  virtual double current_time_step() const = 0;
};

std::unique_ptr<Rosenbrock4Core> make_rosenbrock4(double abs_tol, double rel_tol, double max_dt,
                                                  Rosenbrock4Core::Rhs rhs);

}  // namespace rodend::detail
