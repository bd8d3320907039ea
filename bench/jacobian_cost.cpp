// rodend-jacobian: the cost of one Jacobian of a scene's right-hand side, exact (the scene's
// jacobian()) or by the default forward differences (Scene::jacobian), at a state in loaded
// contact: the scene under a -100 N m hinge moment, cvode_bdf 1e-8 up to t = 0.2 s. Run it under
// callgrind with `count` Jacobians and with none; the difference over `count` is the cost of one
// Jacobian:
//
//   valgrind --tool=callgrind ./build/bench/rodend-jacobian rod-end-kinematic exact 1000
//   valgrind --tool=callgrind ./build/bench/rodend-jacobian rod-end-kinematic fd 1000
//   valgrind --tool=callgrind ./build/bench/rodend-jacobian rod-end-kinematic fd 0
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "core/integrator.hpp"
#include "core/params.hpp"
#include "core/scene.hpp"

using namespace rodend;

int main(int argc, char** argv) {
  if (argc != 4) {
    std::fprintf(stderr, "usage: rodend-jacobian SCENE exact|fd COUNT\n");
    return 2;
  }
  const std::string name = argv[1], mode = argv[2];
  const int count = std::atoi(argv[3]);
  ParameterSet p = ParameterSet::defaults_for(name);
  p.set("hinge.kind", Json("constant"));
  p.set("hinge.constant_moment", Json(-100.0));
  const auto scene = make_scene(name, p);
  IntegratorSettings s;
  s.method = IntegratorMethod::cvode_bdf;
  s.abs_tol = s.rel_tol = 1e-8;
  s.max_step = 1e-3;
  RunObserver none;
  const double t = 0.2;
  const RunResult r = simulate(*scene, s, TimeSettings{t, t}, none);
  DiscreteState d;
  d.contacts.resize(static_cast<std::size_t>(scene->contact_count()));
  if (!d.contacts.empty()) {
    const ContactGap g = scene->contact_gap(0, r.final_state.data());
    d.contacts[0].in_contact = g.penetration > 0.0;
    d.contacts[0].impact_speed = 1e-3;
  }
  const auto n = static_cast<std::size_t>(scene->state_size());
  std::vector<double> J(n * n);
  double sum = 0.0;
  for (int k = 0; k < count; ++k) {
    if (mode == "exact")
      scene->jacobian(t, r.final_state.data(), d, J.data());
    else
      scene->Scene::jacobian(t, r.final_state.data(), d, J.data());
    sum += J[n + 3];
  }
  std::printf("%s %s: %d Jacobians (exact_jacobian %d), checksum %g\n", name.c_str(), mode.c_str(),
              count, scene->exact_jacobian() ? 1 : 0, sum);
}
