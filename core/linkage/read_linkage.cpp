// Reading the planar linkage from its parameters (core/linkage/read_linkage.hpp).
#include "core/linkage/read_linkage.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>

#include "core/linkage/linkage_choices.hpp"
#include "core/linkage/make_body.hpp"
#include "core/scenes/parts.hpp"
#include "core/scenes/planar_slider_crank_options.hpp"

namespace rodend::linkage {

std::vector<std::string> parameter_groups(const ParameterSet& p, const std::string& prefix) {
  std::vector<std::string> names;
  const std::string head = prefix + ".";
  for (const std::string& path : p.paths()) {
    if (path.compare(0, head.size(), head) != 0) continue;
    const std::string rest = path.substr(head.size());
    const std::string name = rest.substr(0, rest.find('.'));
    if (names.empty() || names.back() != name) names.push_back(name);
  }
  names.erase(std::unique(names.begin(), names.end()), names.end());
  return names;
}

namespace {

struct Reader {
  const ParameterSet& p;
  LinkageModel& m;
  std::map<std::string, int> bodies, ground;
  std::vector<std::map<std::string, int>> points;

  /// "body.point" or "ground.point" at `path`.
  PointRef point(const std::string& path) const {
    const std::string s = p.text(path);
    const auto dot = s.find('.');
    const std::string body = s.substr(0, dot), name = dot == s.npos ? "" : s.substr(dot + 1);
    if (body == "ground" && ground.count(name)) return {-1, ground.at(name)};
    if (const auto b = bodies.find(body); b != bodies.end()) {
      const auto& pts = points[static_cast<std::size_t>(b->second)];
      if (const auto q = pts.find(name); q != pts.end()) return {b->second, q->second};
    }
    throw InputError(
        path,
        "expected \"<body>.<point>\": a body of linkage.bodies and one of its "
        "linkage.bodies.<body>.points, or \"ground.<point>\" of linkage.ground; got \"" +
            s + "\"");
  }
  PointRef ground_point(const std::string& path) const {
    const PointRef r = point(path);
    if (r.body >= 0) throw InputError(path, "expected a ground point, \"ground.<point>\"");
    return r;
  }

  void read_bodies();
  void read_joint(const std::string& name);
  void read_prismatic(const std::string& k, PointRef a, JointModel model);
  /// The guide's play: the slider-crank's guide law with the keys under `k` (Guide::read's).
  Guide read_play(const std::string& k, PointRef a) const;
  void read_actuator();
  void read_rotary_drive(const InputPtr& motion);
};

void Reader::read_bodies() {
  for (const std::string& g : parameter_groups(p, "linkage.ground"))
    ground[g] = m.linkage.add_ground_point(read_plane_point(p, "linkage.ground." + g));
  std::vector<double> guess;
  for (const std::string& name : parameter_groups(p, "linkage.bodies")) {
    const std::string prefix = "linkage.bodies." + name;
    const std::vector<std::string> names = parameter_groups(p, prefix + ".points");
    std::map<std::string, int> index;
    double radius = 0.0;
    for (std::size_t i = 0; i < names.size(); ++i) {
      index[names[i]] = static_cast<int>(i);
      radius = std::max(radius, read_plane_point(p, prefix + ".points." + names[i]).norm());
    }
    std::unique_ptr<Body> body = make_body(p, prefix, names);
    const Eigen::Vector2d origin = read_plane_point(p, prefix + ".origin");
    guess.insert(guess.end(), {origin.x(), origin.y(), p.number(prefix + ".angle")});
    guess.resize(guess.size() + static_cast<std::size_t>(body->coordinate_count() - 3), 0.0);
    bodies[name] = m.linkage.add_body(std::move(body));
    points.push_back(std::move(index));
    m.body_names.push_back(name);
    m.body_radius.push_back(std::max(radius, 1e-3));
  }
  if (bodies.empty()) throw InputError("linkage.bodies", "expected at least one body");
  m.initial_guess = Eigen::Map<Eigen::VectorXd>(guess.data(), static_cast<long>(guess.size()));
}

void Reader::read_joint(const std::string& name) {
  const std::string k = "linkage.joints." + name;
  const JointType type = read_choice<JointType>(p, k + ".type");
  const JointModel model = read_choice<JointModel>(p, k + ".model");
  const PointRef a = point(k + ".a");
  if (type == JointType::prismatic) return read_prismatic(k, a, model);
  const PointRef b = point(k + ".b");
  if (model == JointModel::ideal) return m.linkage.add_revolute(a, b);
  if (a.body < 0) throw InputError(k + ".a", "expected the journal on a body, not the ground");
  ClearanceContactModel c = read_clearance_contact(p, "contact", "friction", k + ".clearance");
  if (c.clearance >= c.ball_radius)
    throw InputError(k + ".clearance",
                     "expected a clearance smaller than the journal radius contact.ball_radius");
  m.length_scale = m.length_scale > 0.0 ? std::min(m.length_scale, c.clearance) : c.clearance;
  m.linkage.add_clearance_joint({a, b, std::move(c)});
  m.clearance_joint_names.push_back(name);
}

void Reader::read_prismatic(const std::string& k, PointRef a, JointModel model) {
  if (a.body < 0) throw InputError(k + ".a", "expected a point of a body, not of the ground");
  const Vec3 axis = p.vec3(k + ".axis");
  if (!(axis.head<2>().norm() > 0.0) || axis.z() != 0.0)
    throw InputError(k + ".axis", "expected a non-zero direction in the plane (z = 0)");
  const double angle = m.initial_guess[m.linkage.body_offset(a.body) + 2];
  const Guide play = model == JointModel::clearance ? read_play(k, a) : Guide{};
  m.linkage.add_prismatic(a, ground_point(k + ".b"), axis.head<2>(), angle, play);
  if (m.slider.body == -2) {
    m.slider = a;
    m.slider_axis = axis.head<2>().normalized();
  }
}

Guide Reader::read_play(const std::string& k, PointRef a) const {
  Guide g;
  g.model = GuideModel::clearance;
  g.clearance = read_positive(p, k + ".clearance");
  g.stiffness = read_positive(p, k + ".stiffness");
  // the body's mass: its mass matrix's translation entry (at the initial guess)
  const Body& body = m.linkage.body(a.body);
  const double mass = body.mass_matrix(
      m.initial_guess.segment(m.linkage.body_offset(a.body), body.coordinate_count()))(0, 0);
  g.damping = 2.0 * read_positive(p, k + ".damping_ratio", true) * std::sqrt(g.stiffness * mass);
  g.friction = read_positive(p, k + ".friction_coefficient", true);
  g.speed = read_positive(p, k + ".friction_speed");
  return g;
}

void Reader::read_rotary_drive(const InputPtr& motion) {
  const PointRef a = m.actuator = point("linkage.actuator.point");
  if (a.body < 0) throw InputError("linkage.actuator.point", "expected a point of a body");
  const double angle0 = m.initial_guess[m.linkage.body_offset(a.body) + 2];
  m.drive_radius = m.body_radius[static_cast<std::size_t>(a.body)];
  if (m.drive == LinkageDrive::crank_angle) {
    m.linkage.add_rotary_drive(a, angle0, [motion](double t) {
      const Input::Sample s = motion->at(t);
      return DriveSample{s.value, s.rate, s.acceleration};
    });
    return;
  }
  if (!p.has("linkage.actuator.speed"))
    throw InputError("linkage.actuator.speed",
                     "expected the crank speed [rad/s] of a \"crank_speed\" or \"motor\" drive in "
                     "the part file (linkage.actuator.speed)");
  const double w = m.crank_speed = p.number("linkage.actuator.speed");
  if (!(std::abs(w) > 0.0) || !std::isfinite(w))
    throw InputError("linkage.actuator.speed", "expected a finite non-zero crank speed [rad/s]");
  if (m.drive == LinkageDrive::motor)
    return m.linkage.add_motor(a, angle0, w, read_positive(p, "linkage.actuator.motor_slope"),
                               read_positive(p, "linkage.actuator.flywheel_inertia", true));
  m.linkage.add_rotary_drive(a, angle0, [w](double t) { return DriveSample{w * t, w, 0.0}; });
}

void Reader::read_actuator() {
  m.motion = read_motion(p, "motion");
  m.drive = read_choice<LinkageDrive>(p, "linkage.actuator.kind");
  const bool commanded = m.drive == LinkageDrive::linear || m.drive == LinkageDrive::crank_angle;
  if (commanded && read_choice<MotionShape>(p, "motion.shape") == MotionShape::step)
    throw InputError("motion.shape", "expected a shape with a velocity (not \"step\")");
  if (m.drive != LinkageDrive::linear) return read_rotary_drive(m.motion);
  const Vec3 dir = p.vec3("linkage.actuator.direction");
  if (!(dir.head<2>().norm() > 0.0) || dir.z() != 0.0)
    throw InputError("linkage.actuator.direction",
                     "expected a non-zero direction in the plane (z = 0)");
  const PointRef a = m.actuator = point("linkage.actuator.point");
  if (a.body >= 0 && a.body == m.slider.body &&
      !(std::abs(m.slider_axis.dot(dir.head<2>().normalized())) > 1e-6))
    throw InputError("linkage.actuator.direction",
                     "expected a direction along the guide of the driven body (the guide holds "
                     "it across), not normal to it");
  m.linkage.add_drive(a, ground_point("linkage.actuator.rest"), dir.head<2>(),
                      [motion = m.motion](double t) {
                        const Input::Sample s = motion->at(t);
                        return DriveSample{s.value, s.rate, s.acceleration};
                      });
}

}  // namespace

LinkageModel read_linkage(const ParameterSet& p) {
  LinkageModel m;
  Reader r{p, m, {}, {}, {}};
  r.read_bodies();
  for (const std::string& j : parameter_groups(p, "linkage.joints")) r.read_joint(j);
  r.read_actuator();
  m.output = r.point("linkage.output");
  if (m.output.body < 0) throw InputError("linkage.output", "expected a point of a body");
  const Vec3 g = p.vec3("gravity");
  if (g.z() != 0.0) throw InputError("gravity", "expected a vector in the plane (z = 0)");
  m.linkage.set_gravity(g.head<2>());
  m.linkage.set_baumgarte_rate(read_positive(p, "linkage.baumgarte_rate", true));
  if (m.length_scale == 0.0) m.length_scale = 1e-4;
  m.linkage.finish();
  return m;
}

}  // namespace rodend::linkage
