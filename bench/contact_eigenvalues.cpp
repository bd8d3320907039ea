// rodend-eigen: the stiffness that limits the explicit methods in sustained contact.
// For each mechanism scene with its defaults (thesis cycle, clearance 0.5 mm): the state at a
// ladder of times (dopri5 1e-10 up to each), and there the eigenvalues of the Jacobian
// (Scene::jacobian, in the driver's scaled variables z = x / scale: the same spectrum) with the
// largest modulus, and the step dopri5 can take stably on that eigenvalue: its stability region
// reaches |h lambda| ~ 3.3 on the negative real axis and ~ 3.4 on the imaginary axis.
//
//   ./build/bench/rodend-eigen [scene ...]
//
// With --breakaway: rod-end-actuator under the hinge-moment study's -100 N m
// (stroke +-60 mm, cvode_bdf 1e-8 up to t = 0.6049 s, where the ball creeps in loaded
// contact), the ball's tangential velocity then set to give each slip speed of a ladder across
// the thesis friction law's blends, and there the eigenvalue with the largest real part (an
// unstable mode where it is positive) and the one with the largest modulus.
//
//   ./build/bench/rodend-eigen --breakaway [friction law]
#include <Eigen/Eigenvalues>
#include <cmath>
#include <complex>
#include <cstdio>
#include <string>
#include <vector>

#include "core/integrator.hpp"
#include "core/params.hpp"
#include "core/scene.hpp"

using namespace rodend;

namespace {

/// The Jacobian's eigenvalues at (t, x) in the driver's scaled variables.
Eigen::VectorXcd scaled_eigenvalues(const Scene& scene, double t, const double* x,
                                    const DiscreteState& d) {
  const int n = scene.state_size();
  std::vector<double> scale(static_cast<std::size_t>(n)), J(static_cast<std::size_t>(n * n));
  scene.state_scale(scale.data());
  scene.jacobian(t, x, d, J.data());
  Eigen::MatrixXd Jz(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      Jz(i, j) = J[static_cast<std::size_t>(i * n + j)] * scale[static_cast<std::size_t>(j)] /
                 scale[static_cast<std::size_t>(i)];
  return Jz.eigenvalues();
}

int breakaway(const std::string& law) {
  ParameterSet p = ParameterSet::defaults_for("rod-end-actuator");
  p.set("motion.extension", Json(0.06));
  p.set("motion.retraction", Json(0.06));
  p.set("hinge.kind", Json("constant"));
  p.set("hinge.constant_moment", Json(-100.0));
  p.set("friction.law", Json(law));
  const auto scene = make_scene("rod-end-actuator", p);
  const double t = 0.6049;
  IntegratorSettings s;
  s.method = IntegratorMethod::cvode_bdf;
  s.abs_tol = s.rel_tol = 1e-8;
  s.max_step = 1e-3;
  RunObserver none;
  const RunResult r = simulate(*scene, s, TimeSettings{t, t}, none);
  if (r.status != RunStatus::ok) return std::printf("run failed: %s\n", r.message.c_str()), 1;
  DiscreteState d;
  d.contacts.resize(1);
  d.contacts[0] = {true, 1e-3};  // sustained contact, the impact speed at its 1 mm/s guard
  SignalFrame f0;
  scene->outputs(t, r.final_state.data(), d, f0);
  // the slip direction: opposite to the friction force on the ball
  const Vec3 ff = f0.get3(SignalId::friction_force_vector), slip_dir = -ff / ff.norm();
  const double v0 = f0.get(SignalId::slip_speed);
  std::printf(
      "friction law %s, t = %g s\n| slip speed [m/s] | normal force [N] | mu | "
      "largest Re lambda [1/s] | largest |lambda| [1/s] |\n|---|---|---|---|---|\n",
      law.c_str(), t);
  for (const double v : {2e-4, 5e-4, 9e-4, 1.05e-3, 1.5e-3, 2e-3, 3e-3, 4e-3, 4.5e-3, 6e-3, 2e-2}) {
    std::vector<double> x = r.final_state;
    for (int i = 0; i < 3; ++i) x[static_cast<std::size_t>(3 + i)] += (v - v0) * slip_dir[i];
    SignalFrame f;
    scene->outputs(t, x.data(), d, f);
    const Eigen::VectorXcd ev = scaled_eigenvalues(*scene, t, x.data(), d);
    std::complex<double> hi = ev[0], big = 0.0;
    for (Eigen::Index i = 0; i < ev.size(); ++i) {
      if (ev[i].real() > hi.real()) hi = ev[i];
      if (std::abs(ev[i]) > std::abs(big)) big = ev[i];
    }
    const double fn = f.get(SignalId::contact_force);
    std::printf("| %.3g | %.0f | %.4f | %.3g %+.3gi | %.3g %+.3gi |\n", f.get(SignalId::slip_speed),
                fn, f.get(SignalId::friction_force) / fn, hi.real(), hi.imag(), big.real(),
                big.imag());
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc > 1 && std::string(argv[1]) == "--breakaway")
    return breakaway(argc > 2 ? argv[2] : "thesis");
  std::vector<std::string> scenes;
  for (int i = 1; i < argc; ++i) scenes.emplace_back(argv[i]);
  if (scenes.empty()) scenes = {"rod-end-kinematic", "rod-end-actuator"};
  std::printf(
      "| scene | t [s] | in contact | penetration [m] | largest |lambda| [1/s] | lambda | "
      "dopri5 stable h ~ 3.3/|lambda| [s] |\n|---|---|---|---|---|---|---|\n");
  for (const std::string& name : scenes) {
    const auto scene = make_scene(name, ParameterSet::defaults_for(name));
    const int n = scene->state_size();
    std::vector<double> scale(static_cast<std::size_t>(n));
    scene->state_scale(scale.data());
    for (const double t : {0.05, 0.2, 0.4, 0.6, 0.8, 1.0, 1.4, 1.8, 2.2}) {
      IntegratorSettings s;
      s.method = IntegratorMethod::dopri5;
      s.abs_tol = s.rel_tol = 1e-10;
      RunObserver none;
      const RunResult r = simulate(*scene, s, TimeSettings{t, t}, none);
      if (r.status != RunStatus::ok) {
        std::printf("| %s | %g | run failed: %s |\n", name.c_str(), t, r.message.c_str());
        continue;
      }
      DiscreteState d;
      d.contacts.resize(static_cast<std::size_t>(scene->contact_count()));
      double pen = 0.0;
      bool touching = false;
      if (scene->contact_count() > 0) {
        const ContactGap g = scene->contact_gap(0, r.final_state.data());
        pen = g.penetration;
        touching = g.penetration > 0.0;
        d.contacts[0].in_contact = touching;
        d.contacts[0].impact_speed = touching ? std::max(std::abs(g.penetration_rate), 1e-3) : 0.0;
      }
      std::vector<double> J(static_cast<std::size_t>(n * n));
      scene->jacobian(t, r.final_state.data(), d, J.data());
      Eigen::MatrixXd Jz(n, n);
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j)
          Jz(i, j) = J[static_cast<std::size_t>(i * n + j)] * scale[static_cast<std::size_t>(j)] /
                     scale[static_cast<std::size_t>(i)];
      const Eigen::VectorXcd ev = Jz.eigenvalues();
      std::complex<double> big = 0.0;
      for (Eigen::Index i = 0; i < ev.size(); ++i)
        if (std::abs(ev[i]) > std::abs(big)) big = ev[i];
      std::printf("| %s | %g | %s | %.2e | %.3g | %.3g %+.3gi | %.2e |\n", name.c_str(), t,
                  touching ? "yes" : "no", pen, std::abs(big), big.real(), big.imag(),
                  3.3 / std::abs(big));
    }
  }
  return 0;
}
