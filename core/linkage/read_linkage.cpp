// Reading the planar linkage from its parameters (core/linkage/read_linkage.hpp).
#include "core/linkage/read_linkage.hpp"

#include <algorithm>
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
  void read_actuator();
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
  if (type == JointType::prismatic) {
    if (a.body < 0) throw InputError(k + ".a", "expected a point of a body, not of the ground");
    if (model != JointModel::ideal)
      throw InputError(k + ".model", "expected \"ideal\" for a prismatic guide");
    const Vec3 axis = p.vec3(k + ".axis");
    if (!(axis.head<2>().norm() > 0.0) || axis.z() != 0.0)
      throw InputError(k + ".axis", "expected a non-zero direction in the plane (z = 0)");
    const double angle = m.initial_guess[m.linkage.body_offset(a.body) + 2];
    m.linkage.add_prismatic(a, ground_point(k + ".b"), axis.head<2>(), angle);
    return;
  }
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

void Reader::read_actuator() {
  m.motion = read_motion(p, "motion");
  if (read_choice<MotionShape>(p, "motion.shape") == MotionShape::step)
    throw InputError("motion.shape", "expected a shape with a velocity (not \"step\")");
  const Vec3 dir = p.vec3("linkage.actuator.direction");
  if (!(dir.head<2>().norm() > 0.0) || dir.z() != 0.0)
    throw InputError("linkage.actuator.direction",
                     "expected a non-zero direction in the plane (z = 0)");
  m.linkage.add_drive(point("linkage.actuator.point"), ground_point("linkage.actuator.rest"),
                      dir.head<2>(), [motion = m.motion](double t) {
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
