// rodend-eigen: the stiffness that limits the explicit methods in sustained contact (issue 20).
// For each mechanism scene with its defaults (thesis cycle, clearance 0.5 mm): the state at a
// ladder of times (dopri5 1e-10 up to each), and there the eigenvalues of the Jacobian
// (Scene::jacobian, in the driver's scaled variables z = x / scale: the same spectrum) with the
// largest modulus, and the step dopri5 can take stably on that eigenvalue: its stability region
// reaches |h lambda| ~ 3.3 on the negative real axis and ~ 3.4 on the imaginary axis.
//
//   ./build/bench/rodend-eigen [scene ...]
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

int main(int argc, char** argv) {
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
      s.method = "dopri5";
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
