// The finite-element beam modes of the planar linkage's flexible bodies
// (core/linkage/beam_modes.hpp) against the Euler-Bernoulli beam's and the bar's closed forms.
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>

#include "core/linkage/beam_modes.hpp"

using namespace rodend::linkage;

namespace {

constexpr double kPi = std::numbers::pi;

// A steel-like strip 0.3 m long, 20 mm x 4 mm (bending about the 4 mm side): the numbers only
// set the scale; the closed forms are checked as ratios.
constexpr double kL = 0.3, kE = 200e9, kRho = 7800.0;
constexpr double kA = 0.020 * 0.004, kI = 0.020 * 0.004 * 0.004 * 0.004 / 12.0;
constexpr int kElements = 40;

BeamModes::Spec spec(BeamSupport bc, int bending, int axial) {
  BeamModes::Spec s;
  s.segments = {{kL, kA, kI}};
  s.material = {kE, kRho};
  s.support = bc;
  s.bending_modes = bending;
  s.axial_modes = axial;
  s.elements = kElements;
  return s;
}

double bending_omega(double beta_l) {
  return beta_l * beta_l / (kL * kL) * std::sqrt(kE * kI / (kRho * kA));
}
double axial_omega(double k_l) {
  return k_l / kL * std::sqrt(kE / kRho);
}

// Discretisation error bounds. Hermite cubic elements with consistent mass converge in frequency
// as (beta h)^4 from above; the leading term is (beta h)^4 / 1440 (omega_h^2 / omega^2 - 1 =
// (beta h)^4 / 720, Strang & Fix). Linear bars with consistent mass: omega_h / omega - 1 =
// (k h)^2 / 24 + O((k h)^4) (the bar's discrete dispersion relation). The bounds are these leading
// terms with a factor 2 for the higher-order terms and the boundary elements.
double bending_tolerance(double beta_l) {
  const double bh = beta_l / kElements;
  return 2.0 * bh * bh * bh * bh / 1440.0;
}
double axial_tolerance(double k_l) {
  const double kh = k_l / kElements;
  return 2.0 * kh * kh / 24.0;
}

void check_bending(BeamSupport bc, const std::vector<double>& beta_l) {
  const BeamModes m = BeamModes::compute(spec(bc, static_cast<int>(beta_l.size()), 0));
  REQUIRE(m.count() == static_cast<int>(beta_l.size()));
  for (int i = 0; i < m.count(); ++i) {
    const double exact = bending_omega(beta_l[static_cast<std::size_t>(i)]);
    const double err = m.frequency(i) / exact - 1.0;
    INFO("mode " << i << " omega " << m.frequency(i) << " exact " << exact << " rel " << err);
    CHECK_FALSE(m.is_axial(i));
    CHECK(err >= -1e-12);  // consistent mass: the discrete beam is stiffer
    CHECK(err <= bending_tolerance(beta_l[static_cast<std::size_t>(i)]));
  }
}

void check_axial(BeamSupport bc, const std::vector<double>& k_l) {
  const BeamModes m = BeamModes::compute(spec(bc, 0, static_cast<int>(k_l.size())));
  for (int i = 0; i < m.count(); ++i) {
    const double exact = axial_omega(k_l[static_cast<std::size_t>(i)]);
    const double err = m.frequency(i) / exact - 1.0;
    INFO("mode " << i << " omega " << m.frequency(i) << " exact " << exact << " rel " << err);
    CHECK(m.is_axial(i));
    CHECK(err >= -1e-12);
    CHECK(err <= axial_tolerance(k_l[static_cast<std::size_t>(i)]));
  }
}

/// int rho A (u^2 + v^2) ds of one mode by 4-point Gauss per element: 1 for mass-normalised modes.
double modal_mass(const BeamModes& m, int mode) {
  static constexpr double g[4] = {-0.8611363115940526, -0.3399810435848563, 0.3399810435848563,
                                  0.8611363115940526};
  static constexpr double w[4] = {0.3478548451374538, 0.6521451548625461, 0.6521451548625461,
                                  0.3478548451374538};
  double sum = 0.0;
  for (std::size_t e = 0; e + 1 < m.nodes().size(); ++e) {
    const double a = m.nodes()[e], h = m.nodes()[e + 1] - a;
    for (int k = 0; k < 4; ++k) {
      const ModeShapeAt p = m.at(mode, a + 0.5 * h * (1.0 + g[k]));
      sum += 0.5 * h * w[k] * m.mass_per_length()[e] *
             (p.axial * p.axial + p.transverse * p.transverse);
    }
  }
  return sum;
}

}  // namespace

TEST_CASE("beam modes: free-free bending frequencies are Euler-Bernoulli's", "[beam_modes]") {
  check_bending(BeamSupport::free_free, {4.730040745, 7.853204624, 10.99560784, 14.13716549});
}

TEST_CASE("beam modes: clamped-free bending frequencies are Euler-Bernoulli's", "[beam_modes]") {
  check_bending(BeamSupport::clamped_free, {1.875104069, 4.694091133, 7.854757438, 10.99554073});
}

TEST_CASE("beam modes: pinned-pinned bending frequencies are n pi", "[beam_modes]") {
  check_bending(BeamSupport::pinned_pinned, {kPi, 2 * kPi, 3 * kPi, 4 * kPi});
}

TEST_CASE("beam modes: axial frequencies are the bar's", "[beam_modes]") {
  // free-free: n pi / L sqrt(E / rho); fixed at s = 0 (pinned-pinned and clamped-free frames):
  // (2n - 1) pi / (2 L) sqrt(E / rho)
  check_axial(BeamSupport::free_free, {kPi, 2 * kPi, 3 * kPi});
  check_axial(BeamSupport::pinned_pinned, {kPi / 2, 3 * kPi / 2, 5 * kPi / 2});
  check_axial(BeamSupport::clamped_free, {kPi / 2, 3 * kPi / 2, 5 * kPi / 2});
}

TEST_CASE("beam modes: bending and axial modes interleave by frequency, mass-normalised",
          "[beam_modes]") {
  const BeamModes m = BeamModes::compute(spec(BeamSupport::free_free, 3, 2));
  REQUIRE(m.count() == 5);
  for (int i = 0; i + 1 < m.count(); ++i) CHECK(m.frequency(i) <= m.frequency(i + 1));
  for (int i = 0; i < m.count(); ++i) {
    INFO("mode " << i);
    // the consistent mass matrix is the exact integral of the shape functions: 1 to rounding
    CHECK(modal_mass(m, i) == Approx(1.0).epsilon(1e-10));
  }
  // the slender strip's first axial mode (k L = pi) lies far above its bending modes
  CHECK(m.is_axial(3));
  CHECK(m.is_axial(4));
}

TEST_CASE("beam modes: a beam in two equal segments is the uniform beam", "[beam_modes]") {
  BeamModes::Spec two = spec(BeamSupport::clamped_free, 3, 1);
  two.segments = {{0.12, kA, kI}, {0.18, kA, kI}};  // the same 40 elements
  const BeamModes a = BeamModes::compute(spec(BeamSupport::clamped_free, 3, 1));
  const BeamModes b = BeamModes::compute(two);
  // the same mesh to rounding of the stations; the eigensolver resolves the lowest eigenvalue to
  // ~ epsilon x lambda_max / lambda_1 ~ 1e-16 x 1e7
  for (int i = 0; i < a.count(); ++i) CHECK(b.frequency(i) == Approx(a.frequency(i)).epsilon(1e-7));
}

TEST_CASE("beam modes: a stepped beam is stiffer where it is thicker", "[beam_modes]") {
  // doubling the root half's second moment raises the clamped-free first frequency, and a
  // section four times as deep everywhere (I x 64, A x 4) raises every bending frequency by 4
  BeamModes::Spec stepped = spec(BeamSupport::clamped_free, 1, 0);
  stepped.segments = {{kL / 2, kA, 2 * kI}, {kL / 2, kA, kI}};
  const double uniform = BeamModes::compute(spec(BeamSupport::clamped_free, 1, 0)).frequency(0);
  CHECK(BeamModes::compute(stepped).frequency(0) > uniform * 1.05);
  BeamModes::Spec deep = spec(BeamSupport::clamped_free, 1, 0);
  deep.segments = {{kL, 4 * kA, 64 * kI}};
  CHECK(BeamModes::compute(deep).frequency(0) == Approx(4 * uniform).epsilon(1e-9));
}

TEST_CASE("beam modes: modes given directly interpolate as computed ones", "[beam_modes]") {
  const BeamModes a = BeamModes::compute(spec(BeamSupport::pinned_pinned, 2, 1));
  std::vector<double> f;
  std::vector<Eigen::VectorXd> shapes;
  for (int i = 0; i < a.count(); ++i) {
    f.push_back(a.frequency(i));
    shapes.push_back(a.shape(i));
  }
  const BeamModes b = BeamModes::given(a.nodes(), a.mass_per_length(), f, shapes);
  for (int i = 0; i < a.count(); ++i) {
    CHECK(b.is_axial(i) == a.is_axial(i));
    for (double s : {0.0, 0.0123, 0.15, 0.2999, kL}) {
      CHECK(b.at(i, s).transverse == a.at(i, s).transverse);
      CHECK(b.at(i, s).slope == a.at(i, s).slope);
    }
  }
  // pinned at both ends: no transverse displacement there
  CHECK(std::abs(a.at(0, 0.0).transverse) < 1e-12);
  CHECK(std::abs(a.at(0, kL).transverse) < 1e-12);
  CHECK_THROWS_AS(BeamModes::given({0.0, 0.1}, {1.0, 2.0}, {}, {}), std::invalid_argument);
}

TEST_CASE("beam modes: asking more modes than the mesh has is refused", "[beam_modes]") {
  BeamModes::Spec s = spec(BeamSupport::free_free, 200, 0);
  CHECK_THROWS_AS(BeamModes::compute(s), std::invalid_argument);
}

namespace {

/// A flap part (docs/flexible-bodies.md, "The flap linkage's flexible parts"): joint-to-joint
/// length [m] and the first two eigenfrequencies of Wan et al., Machines 2022, 10, 1098, Table 6
/// [Hz]: the first is the in-plane bending, the second taken as the out-of-plane bending.
struct FlapPart {
  const char* name;
  double length, f1, f2;
};
constexpr FlapPart kFlapParts[] = {{"auxiliary lever arm", 0.100, 3715.8, 5437.1},
                                   {"auxiliary rod", 0.250, 690.40, 1648.66},
                                   {"lever arm", 0.075, 5839.3, 6201.3}};
// magnesium-aluminium alloy AZ31B (ASM Handbook vol. 2: E = 45 GPa, 1.77-1.78 g/cm^3)
constexpr double kMgE = 45e9, kMgRho = 1780.0;

/// The rectangular section (in-plane depth h, width b) whose free-free first bending frequency
/// is f1: f1 = (beta L)^2 / (2 pi L^2) sqrt(E / rho) h / sqrt(12), beta L = 4.7300; the width
/// puts the out-of-plane bending at f2 (b / h = f2 / f1).
BeamSegment flap_section(const FlapPart& p) {
  const double c = std::sqrt(kMgE / kMgRho), bl = 4.730040745;
  const double h = 2 * kPi * p.f1 * p.length * p.length * std::sqrt(12.0) / (bl * bl * c);
  const double b = h * p.f2 / p.f1;
  return {p.length, b * h, b * h * h * h / 12.0};
}

double first_frequency_hz(const BeamSegment& g, BeamSupport bc, int mode = 0) {
  BeamModes::Spec s;
  s.segments = {g};
  s.material = {kMgE, kMgRho};
  s.support = bc;
  s.bending_modes = mode + 1;
  s.elements = 40;
  return BeamModes::compute(s).frequency(mode) / (2 * kPi);
}

}  // namespace

TEST_CASE("beam modes: the flap parts' sections give Table 6's first eigenfrequencies",
          "[beam_modes]") {
  for (const FlapPart& p : kFlapParts) {
    INFO(p.name);
    // 40 elements: (beta h)^4 / 1440 ~ 1.4e-7 of the frequency
    CHECK(first_frequency_hz(flap_section(p), BeamSupport::free_free) ==
          Approx(p.f1).epsilon(1e-6));
  }
  // Why free-free: the auxiliary rod's Table 6 list has in-plane modes at 1869.88 and 3588.54 Hz,
  // 2.71 and 5.20 times the first, as the free-free beam's 2.76 and 5.40 (the shortfall of a
  // real rod's heavier eyes and shear); pinned-pinned would put the second at 4 times the first
  // (2762 Hz), where Table 6 has none
  const BeamSegment rod = flap_section(kFlapParts[1]);
  const double f2 = first_frequency_hz(rod, BeamSupport::free_free, 1);
  const double f3 = first_frequency_hz(rod, BeamSupport::free_free, 2);
  CHECK(std::abs(f2 / 1869.88 - 1.0) < 0.02);
  CHECK(std::abs(f3 / 3588.54 - 1.0) < 0.04);
  const double pinned = first_frequency_hz(rod, BeamSupport::pinned_pinned, 1) /
                        first_frequency_hz(rod, BeamSupport::pinned_pinned, 0);
  for (double table : {1648.66, 1869.88, 2143.10, 3588.54})
    CHECK(std::abs(table / 690.40 - pinned) > 0.5);
}
