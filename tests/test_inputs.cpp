// Periodic inputs (issue 31; docs/inputs.md): the waveforms of the position command and the
// hinge moment.
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <string>

#include "core/errors.hpp"
#include "core/scenes/drivers.hpp"
#include "fixture.hpp"

using namespace rodend;
using namespace rodend::test;

namespace {

constexpr double kPi = std::numbers::pi;

}  // namespace

TEST_CASE("waveforms: values, derivatives and windows", "[inputs]") {
  for (auto kind : {Waveform::Kind::sine, Waveform::Kind::linear_chirp, Waveform::Kind::log_chirp,
                    Waveform::Kind::triangle}) {
    Waveform w;
    w.kind = kind;
    w.amplitude = 2.0, w.offset = 0.5, w.frequency = 3.0, w.cycles = 2, w.start_time = 0.1;
    w.start_frequency = 1.0, w.end_frequency = 8.0, w.chirp_duration = 1.5;
    CAPTURE(static_cast<int>(kind));
    // offset before the start, the end value after the end (offset after whole periods),
    // continuous at both
    CHECK(w.at(0.05).value == 0.5);
    CHECK(w.at(0.1).value == Approx(0.5).margin(1e-12));
    CHECK(w.at(w.end_time() + 1e-3).value == Approx(w.at(w.end_time()).value).margin(1e-12));
    CHECK(w.at(w.end_time() + 1e-3).rate == 0.0);
    if (w.single_frequency()) CHECK(w.at(w.end_time()).value == Approx(0.5).margin(1e-9));
    // the rate is the derivative of the value (central differences, away from the triangle's
    // corners), the acceleration that of the rate
    const double h = 1e-6;
    for (double t : {0.13, 0.31, 0.47, 0.58}) {
      CAPTURE(t);
      const double d = (w.at(t + h).value - w.at(t - h).value) / (2 * h);
      CHECK(w.at(t).rate == Approx(d).epsilon(1e-6).margin(1e-6));
      const double dd = (w.at(t + h).rate - w.at(t - h).rate) / (2 * h);
      CHECK(w.at(t).acceleration == Approx(dd).epsilon(1e-5).margin(1e-3));
    }
  }
  // a chirp's instantaneous frequency: the rate's peak is 2 pi A f(t); the end frequency reached
  Waveform c;
  c.kind = Waveform::Kind::log_chirp;
  c.amplitude = 1.0, c.start_frequency = 1.0, c.end_frequency = 16.0, c.chirp_duration = 4.0;
  // at tau = D/2 the log chirp runs at sqrt(f0 f1) = 4 Hz: w' = 2 pi f A cos(phase)
  const auto s = c.at(2.0);
  const double f = std::abs(s.rate) / (2 * kPi * std::sqrt(1.0 - s.value * s.value));
  CHECK(f == Approx(4.0).epsilon(1e-9));
  // the triangle reaches +-A at a quarter and three quarters of a period
  Waveform t;
  t.kind = Waveform::Kind::triangle;
  t.amplitude = 3.0, t.frequency = 0.5;
  CHECK(t.at(0.5).value == Approx(3.0));
  CHECK(t.at(1.5).value == Approx(-3.0));
}

TEST_CASE("waveform catalogues: one list for the command and the hinge moment", "[inputs]") {
  const auto shapes = motion_shape_names();
  const auto kinds = hinge_moment_names();
  const auto waves = waveform_names();
  REQUIRE(shapes.size() == 3 + waves.size());
  REQUIRE(kinds.size() == 3 + waves.size());
  for (std::size_t i = 0; i < waves.size(); ++i) {
    CHECK(shapes[3 + i] == waves[i]);
    CHECK(kinds[3 + i] == waves[i]);
  }
  // a sine command and a triangle moment are the scene's periodic inputs
  ParameterSet p = ParameterSet::defaults_for("rod-end-actuator");
  p.set("motion.shape", "sine");
  p.set("motion.frequency", 4.0);
  p.set("motion.cycles", 3);
  p.set("hinge.kind", "triangle");
  p.set("hinge.frequency", 0.5);
  const auto in = make_scene("rod-end-actuator", p)->periodic_inputs();
  REQUIRE(in.command);
  CHECK(in.command->frequency == 4.0);
  CHECK(in.command->cycles == 3);
  REQUIRE(in.load);
  CHECK(in.load->frequency == 0.5);
}
