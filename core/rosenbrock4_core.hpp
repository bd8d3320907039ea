// Internal to core: odeint's rosenbrock4 stepper (one trial step with its embedded error, and its
// dense output) behind a C++17 interface. Boost 1.74's uBLAS (which rosenbrock4 needs) does not
// compile as C++20 (std::allocator::construct is gone), so rosenbrock4_core.cpp is compiled as
// C++17 and sees only this header. The step-size control is the caller's (steppers_odeint.cpp),
// so rejections are counted and the error is measured as for the other methods of the menu.
#pragma once

#include <functional>
#include <memory>
#include <vector>

namespace rodend::detail {

class Rosenbrock4Core {
 public:
  using Rhs = std::function<void(const std::vector<double>&, std::vector<double>&, double)>;
  /// J (row-major, n x n) = df/dz and dfdt = df/dt at (z, t).
  using Jac = std::function<void(const std::vector<double>& z, double t, std::vector<double>& J,
                                 std::vector<double>& dfdt)>;
  virtual ~Rosenbrock4Core() = default;
  /// One trial step of size dt from (z, t): z_out and the embedded error estimate err (both in
  /// the state's units). The Jacobian is evaluated once per (z, t): a retry of the same step
  /// with a shorter dt reuses it and only factorises again.
  virtual void try_step(const std::vector<double>& z, double t, double dt,
                        std::vector<double>& z_out, std::vector<double>& err) = 0;
  /// After an accepted try_step: keep its stages for the dense output.
  virtual void accept() = 0;
  /// The dense output (third order) over the accepted step (z_old, t_old) -> (z_new, t_new).
  virtual void calc_state(double t, std::vector<double>& out, const std::vector<double>& z_old,
                          double t_old, const std::vector<double>& z_new, double t_new) = 0;
  /// Forget the cached Jacobian (the discrete state changed, so the right-hand side did).
  virtual void invalidate_jacobian() = 0;
  virtual long long jacobian_evaluations() const = 0;
};

std::unique_ptr<Rosenbrock4Core> make_rosenbrock4(Rosenbrock4Core::Rhs rhs,
                                                  Rosenbrock4Core::Jac jac);

}  // namespace rodend::detail
