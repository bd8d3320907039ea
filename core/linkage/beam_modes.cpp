#include "core/linkage/beam_modes.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include <Eigen/Eigenvalues>

namespace rodend::linkage {
namespace {

/// The mesh: node stations and each element's section.
struct Mesh {
  std::vector<double> nodes;
  std::vector<double> ea, ei, rho_a, rho_i;  ///< per element
};

Mesh build_mesh(const BeamModes::Spec& spec) {
  if (spec.segments.empty()) throw std::invalid_argument("beam: expected at least one segment");
  if (!(spec.material.youngs_modulus > 0.0) || !(spec.material.density > 0.0))
    throw std::invalid_argument("beam: expected a Young's modulus and a density > 0");
  double total = 0.0;
  for (const auto& g : spec.segments) {
    if (!(g.length > 0.0) || !(g.area > 0.0) || !(g.second_moment > 0.0))
      throw std::invalid_argument("beam: expected each segment's length, area, second moment > 0");
    total += g.length;
  }
  const int n_seg = static_cast<int>(spec.segments.size());
  if (spec.elements < n_seg)
    throw std::invalid_argument("beam: expected at least one element per segment");
  Mesh m;
  m.nodes.push_back(0.0);
  double s = 0.0;
  for (const auto& g : spec.segments) {
    // elements in proportion to the segment's share of the length, at least one
    const int n = std::max(1, static_cast<int>(std::lround(spec.elements * g.length / total)));
    for (int k = 1; k <= n; ++k) {
      m.nodes.push_back(s + g.length * k / n);
      m.ea.push_back(spec.material.youngs_modulus * g.area);
      m.ei.push_back(spec.material.youngs_modulus * g.second_moment);
      m.rho_a.push_back(spec.material.density * g.area);
      m.rho_i.push_back(spec.material.density * g.second_moment);
    }
    s += g.length;
  }
  return m;
}

using Dofs = std::vector<int>;

/// Solves K phi = omega^2 M phi on the free dofs (those not in `fixed`), skipping the first
/// `rigid` eigenpairs (the rigid-body motions), and returns `wanted` (omega, phi on all dofs).
std::vector<std::pair<double, Eigen::VectorXd>> solve(const Eigen::MatrixXd& k,
                                                      const Eigen::MatrixXd& m, const Dofs& fixed,
                                                      int rigid, int wanted) {
  const int n = static_cast<int>(k.rows());
  Dofs free;
  for (int i = 0; i < n; ++i)
    if (std::find(fixed.begin(), fixed.end(), i) == fixed.end()) free.push_back(i);
  const int nf = static_cast<int>(free.size());
  if (wanted + rigid > nf)
    throw std::invalid_argument("beam: " + std::to_string(wanted) + " modes asked of a mesh with " +
                                std::to_string(nf - rigid) + "; use more elements");
  std::vector<std::pair<double, Eigen::VectorXd>> out;
  if (wanted <= 0) return out;
  Eigen::MatrixXd kf(nf, nf), mf(nf, nf);
  for (int i = 0; i < nf; ++i)
    for (int j = 0; j < nf; ++j) {
      kf(i, j) = k(free[i], free[j]);
      mf(i, j) = m(free[i], free[j]);
    }
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> es(kf, mf);
  if (es.info() != Eigen::Success) throw std::runtime_error("beam: the eigensolver failed");
  for (int r = rigid; r < rigid + wanted; ++r) {
    Eigen::VectorXd phi = Eigen::VectorXd::Zero(n);
    for (int i = 0; i < nf; ++i) phi(free[i]) = es.eigenvectors()(i, r);
    out.emplace_back(std::sqrt(std::max(0.0, es.eigenvalues()(r))), phi);
  }
  return out;
}

/// Bending: dofs (v, dv/ds) per node, Hermite elements with consistent mass.
std::vector<std::pair<double, Eigen::VectorXd>> bending(const Mesh& g, BeamSupport bc, int wanted) {
  const int nn = static_cast<int>(g.nodes.size());
  Eigen::MatrixXd k = Eigen::MatrixXd::Zero(2 * nn, 2 * nn), m = k;
  for (int e = 0; e + 1 < nn; ++e) {
    const double h = g.nodes[e + 1] - g.nodes[e];
    Eigen::Matrix4d ke, me;
    ke << 12, 6 * h, -12, 6 * h, 6 * h, 4 * h * h, -6 * h, 2 * h * h, -12, -6 * h, 12, -6 * h,
        6 * h, 2 * h * h, -6 * h, 4 * h * h;
    me << 156, 22 * h, 54, -13 * h, 22 * h, 4 * h * h, 13 * h, -3 * h * h, 54, 13 * h, 156, -22 * h,
        -13 * h, -3 * h * h, -22 * h, 4 * h * h;
    k.block<4, 4>(2 * e, 2 * e) += g.ei[e] / (h * h * h) * ke;
    m.block<4, 4>(2 * e, 2 * e) += g.rho_a[e] * h / 420.0 * me;
  }
  Dofs fixed;
  int rigid = 0;
  switch (bc) {
    case BeamSupport::free_free:
      rigid = 2;
      break;
    case BeamSupport::pinned_pinned:
      fixed = {0, 2 * (nn - 1)};
      break;
    case BeamSupport::clamped_free:
      fixed = {0, 1};
      break;
  }
  return solve(k, m, fixed, rigid, wanted);
}

/// Axial: dof u per node, linear bar elements with consistent mass.
std::vector<std::pair<double, Eigen::VectorXd>> axial(const Mesh& g, BeamSupport bc, int wanted) {
  const int nn = static_cast<int>(g.nodes.size());
  Eigen::MatrixXd k = Eigen::MatrixXd::Zero(nn, nn), m = k;
  for (int e = 0; e + 1 < nn; ++e) {
    const double h = g.nodes[e + 1] - g.nodes[e];
    Eigen::Matrix2d ke, me;
    ke << 1, -1, -1, 1;
    me << 2, 1, 1, 2;
    k.block<2, 2>(e, e) += g.ea[e] / h * ke;
    m.block<2, 2>(e, e) += g.rho_a[e] * h / 6.0 * me;
  }
  const bool free = bc == BeamSupport::free_free;
  return solve(k, m, free ? Dofs{} : Dofs{0}, free ? 1 : 0, wanted);
}

/// Signs a mode so that its largest nodal displacement (u or v, not the slope) is positive.
void fix_sign(Eigen::VectorXd& phi) {
  double big = 0.0;
  for (int i = 0; i < phi.size(); ++i)
    if (i % 3 != 2 && std::abs(phi(i)) > std::abs(big) + 1e-12 * std::abs(big)) big = phi(i);
  if (big < 0.0) phi = -phi;
}

}  // namespace

BeamModes BeamModes::compute(const Spec& spec) {
  if (spec.bending_modes < 0 || spec.axial_modes < 0)
    throw std::invalid_argument("beam: expected mode counts >= 0");
  const Mesh g = build_mesh(spec);
  const int nn = static_cast<int>(g.nodes.size());
  BeamModes b;
  b.nodes_ = g.nodes;
  b.rho_a_ = g.rho_a;
  b.rho_i_ = g.rho_i;
  struct Found {
    double omega;
    bool axial;
    Eigen::VectorXd phi;
  };
  std::vector<Found> all;
  for (auto& [w, v] : bending(g, spec.support, spec.bending_modes)) {
    Eigen::VectorXd phi = Eigen::VectorXd::Zero(3 * nn);
    for (int i = 0; i < nn; ++i) phi.segment<2>(3 * i + 1) = v.segment<2>(2 * i);
    all.push_back({w, false, phi});
  }
  for (auto& [w, v] : axial(g, spec.support, spec.axial_modes)) {
    Eigen::VectorXd phi = Eigen::VectorXd::Zero(3 * nn);
    for (int i = 0; i < nn; ++i) phi(3 * i) = v(i);
    all.push_back({w, true, phi});
  }
  std::stable_sort(all.begin(), all.end(),
                   [](const Found& a, const Found& c) { return a.omega < c.omega; });
  for (auto& f : all) {
    fix_sign(f.phi);
    b.omega_.push_back(f.omega);
    b.axial_.push_back(f.axial);
    b.shapes_.push_back(std::move(f.phi));
  }
  return b;
}

BeamModes BeamModes::given(std::vector<double> nodes, std::vector<double> mass_per_length,
                           std::vector<double> frequencies, std::vector<Eigen::VectorXd> shapes) {
  const std::size_t nn = nodes.size();
  if (nn < 2 || nodes.front() != 0.0 || !std::is_sorted(nodes.begin(), nodes.end()) ||
      std::adjacent_find(nodes.begin(), nodes.end()) != nodes.end())
    throw std::invalid_argument("beam: expected node stations increasing from 0");
  if (mass_per_length.size() + 1 != nn)
    throw std::invalid_argument("beam: expected one mass per length per element");
  if (frequencies.size() != shapes.size())
    throw std::invalid_argument("beam: expected one shape per frequency");
  for (const auto& s : shapes)
    if (static_cast<std::size_t>(s.size()) != 3 * nn)
      throw std::invalid_argument("beam: expected 3 values (u, v, dv/ds) per node in each shape");
  BeamModes b;
  b.nodes_ = std::move(nodes);
  b.rho_a_ = std::move(mass_per_length);
  b.rho_i_.assign(b.rho_a_.size(), 0.0);
  b.omega_ = std::move(frequencies);
  for (const auto& s : shapes) {
    double u = 0.0, v = 0.0;
    for (std::size_t i = 0; i < nn; ++i) {
      u += std::abs(s(static_cast<int>(3 * i)));
      v += std::abs(s(static_cast<int>(3 * i + 1)));
    }
    b.axial_.push_back(u > v);
  }
  b.shapes_ = std::move(shapes);
  return b;
}

ModeShapeAt BeamModes::at(int mode, double s) const {
  const auto it = std::upper_bound(nodes_.begin(), nodes_.end(), s);
  const int e =
      std::clamp(static_cast<int>(it - nodes_.begin()) - 1, 0, static_cast<int>(nodes_.size()) - 2);
  const double h = nodes_[e + 1] - nodes_[e], x = (s - nodes_[e]) / h;
  const Eigen::VectorXd& p = shape(mode);
  const double u0 = p(3 * e), v0 = p(3 * e + 1), t0 = p(3 * e + 2);
  const double u1 = p(3 * e + 3), v1 = p(3 * e + 4), t1 = p(3 * e + 5);
  ModeShapeAt r;
  r.axial = (1.0 - x) * u0 + x * u1;
  r.transverse = (1 - 3 * x * x + 2 * x * x * x) * v0 + h * (x - 2 * x * x + x * x * x) * t0 +
                 (3 * x * x - 2 * x * x * x) * v1 + h * (x * x * x - x * x) * t1;
  r.slope = (6 * x * x - 6 * x) / h * v0 + (1 - 4 * x + 3 * x * x) * t0 +
            (6 * x - 6 * x * x) / h * v1 + (3 * x * x - 2 * x) * t1;
  return r;
}

}  // namespace rodend::linkage
