// The built-in scenes. Units SI, y up, gravity (0, -9.81, 0) (driven-crank: off). Masses and
// inertias are those of uniform solids of the stated dimensions; every joint is built at a world
// point and axis of the initial pose (constraint.h), so the equality constraints hold there
// exactly, and the bodies are laid out so that the joints sit where the bodies meet.
#include "ldlpgs/physics/io/scenes.h"

#include <charconv>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <string>
#include <string_view>
#include <vector>

#include "ldlpgs/physics/io/mjcf.h"
#include "ldlpgs/physics/io/scene.h"
#include "ldlpgs/sparse/error.h"

namespace ldlpgs {

namespace {

using Eigen::Vector3d;
constexpr double kPi = std::numbers::pi;
const Vector3d kX = Vector3d::UnitX(), kY = Vector3d::UnitY(), kZ = Vector3d::UnitZ();

// Principal moments of uniform solids about their centre, body frame.
Vector3d box_inertia(double mass, double x, double y, double z) {
  return mass / 12 * Vector3d(y * y + z * z, x * x + z * z, x * x + y * y);
}
// A cylinder of radius r and length h along body axis `axis` (0 = x, 1 = y, 2 = z).
Vector3d cylinder_inertia(double mass, double r, double h, int axis) {
  Vector3d i = Vector3d::Constant(mass * (3 * r * r + h * h) / 12);
  i[axis] = mass * r * r / 2;
  return i;
}
Vector3d sphere_inertia(double mass, double r) { return Vector3d::Constant(2 * mass * r * r / 5); }

RigidBody static_body(const std::string& name, const Vector3d& position) {
  RigidBody b;
  b.name = name;
  b.is_static = true;
  b.position = position;
  return b;
}

RigidBody dynamic_body(const std::string& name, double mass, const Vector3d& inertia, const Vector3d& position,
                       const Eigen::Quaterniond& orientation = Eigen::Quaterniond::Identity()) {
  RigidBody b;
  b.name = name;
  b.mass = mass;
  b.inertia = inertia;
  b.position = position;
  b.orientation = orientation;
  return b;
}

// Body frame x along the segment p -> q in the plane z = const (links, planks).
Eigen::Quaterniond along_xy(const Vector3d& p, const Vector3d& q) {
  return Eigen::Quaterniond(Eigen::AngleAxisd(std::atan2(q.y() - p.y(), q.x() - p.x()), kZ));
}

void ball(Mechanism* m, int a, int b, const Vector3d& anchor) {
  m->add_constraint(m->ball(a, b, anchor));
}
void axial(Mechanism* m, ConstraintType type, int a, int b, const Vector3d& anchor, const Vector3d& axis) {
  m->add_constraint(m->axial(type, a, b, anchor, axis));
}

std::string numbered(const char* prefix, int i) {
  std::string s = prefix;
  s += std::to_string(i);
  return s;
}

// A 1 kg bob (a sphere of radius 5 cm) on a 1 m ball joint, released 0.1 rad from the vertical:
// a compound pendulum of small-angle period 2 pi sqrt((I + m l^2) / (m g l)).
Mechanism pendulum() {
  Mechanism m;
  m.name = "pendulum";
  const double l = 1, angle = 0.1;
  m.add_body(static_body("ground", Vector3d::Zero()));
  m.add_body(dynamic_body("bob", 1, sphere_inertia(1, 0.05), Vector3d(l * std::sin(angle), -l * std::cos(angle), 0)));
  ball(&m, 0, 1, Vector3d::Zero());
  return m;
}

// n links (bars 0.5 x 0.05 x 0.05 m, 1 kg) hanging straight down at rest from a ball joint at
// the origin, each joined to the next by a ball joint. A heavy chain's last link, "load", weighs
// `load` times a link (mass and inertia).
Mechanism chain(const std::string& name, int n, bool heavy, double load) {
  const double l = 0.5, t = 0.05;
  Mechanism m;
  m.name = name;
  m.bodies.reserve(n + 1);
  m.constraints.reserve(n);
  m.add_body(static_body("ground", Vector3d::Zero()));
  for (int i = 0; i < n; ++i) {
    const bool last = heavy && i == n - 1;
    const double mass = last ? load : 1.0;
    m.add_body(dynamic_body(last ? "load" : numbered("link", i), mass, box_inertia(mass, t, l, t),
                            Vector3d(0, -l * (i + 0.5), 0)));
    ball(&m, i, i + 1, Vector3d(0, -l * i, 0));
  }
  return m;
}

// A 72 kg humanoid in a T-pose, facing +z, pelvis 3 m up, thrown tumbling (a rigid motion, so
// every joint's velocity constraint holds): ball joints at the lower back, neck, shoulders and
// hips; hinges at the elbows (about the vertical) and knees (about x), each with an angular
// limit letting it bend one way (forearms forward, shins backward), as a ragdoll of a game has.
Mechanism ragdoll() {
  Mechanism m;
  m.name = "ragdoll";
  const double y0 = 3.0;
  const int pelvis = m.add_body(dynamic_body("pelvis", 10, box_inertia(10, 0.30, 0.20, 0.20), Vector3d(0, y0, 0)));
  const int torso = m.add_body(dynamic_body("torso", 25, box_inertia(25, 0.36, 0.50, 0.22), Vector3d(0, y0 + 0.35, 0)));
  const int head = m.add_body(dynamic_body("head", 5, sphere_inertia(5, 0.11), Vector3d(0, y0 + 0.73, 0)));
  ball(&m, pelvis, torso, Vector3d(0, y0 + 0.10, 0));  // lower back
  ball(&m, torso, head, Vector3d(0, y0 + 0.60, 0));    // neck
  struct Side {
    const char* name;
    double s;  // +1 left (+x), -1 right
  };
  for (const Side side : {Side{"left", 1}, Side{"right", -1}}) {
    const double s = side.s;
    const std::string n = side.name;
    // arm along +-x: shoulder at the torso's side, upper arm 0.30 m, forearm and hand 0.28 m
    const double ya = y0 + 0.52;
    const int upper_arm = m.add_body(dynamic_body(std::string("upper_arm_") + n, 2.5,
                                                  cylinder_inertia(2.5, 0.045, 0.30, 0), Vector3d(s * 0.33, ya, 0)));
    const int lower_arm = m.add_body(dynamic_body(std::string("lower_arm_") + n, 1.5,
                                                  cylinder_inertia(1.5, 0.04, 0.28, 0), Vector3d(s * 0.62, ya, 0)));
    ball(&m, torso, upper_arm, Vector3d(s * 0.18, ya, 0));
    // a positive angle about (0, -s, 0) turns the forearm from +-x towards +z (forward)
    const Vector3d elbow_axis(0, -s, 0), elbow(s * 0.48, ya, 0);
    axial(&m, ConstraintType::hinge, upper_arm, lower_arm, elbow, elbow_axis);
    m.add_constraint(m.angular_limit(upper_arm, lower_arm, elbow_axis,
                                        -0.05, 2.6));
    // leg along -y: hip under the pelvis, thigh 0.44 m, shin and foot 0.46 m
    const int upper_leg = m.add_body(dynamic_body(std::string("upper_leg_") + n, 8, cylinder_inertia(8, 0.07, 0.44, 1),
                                                  Vector3d(s * 0.10, y0 - 0.32, 0)));
    const int lower_leg = m.add_body(dynamic_body(std::string("lower_leg_") + n, 4, cylinder_inertia(4, 0.05, 0.46, 1),
                                                  Vector3d(s * 0.10, y0 - 0.77, 0)));
    ball(&m, pelvis, upper_leg, Vector3d(s * 0.10, y0 - 0.10, 0));
    // a positive angle about +x turns the shin from -y towards -z (backward)
    const Vector3d knee(s * 0.10, y0 - 0.54, 0);
    axial(&m, ConstraintType::hinge, upper_leg, lower_leg, knee, kX);
    m.add_constraint(
        m.angular_limit(upper_leg, lower_leg, kX, -0.05, 2.4));
  }
  // thrown: v = v0 + w x (p - centre of mass), the same w for every body
  Vector3d centre = Vector3d::Zero();
  double total = 0;
  for (const RigidBody& b : m.bodies) {
    centre += b.mass * b.position;
    total += b.mass;
  }
  centre /= total;
  const Vector3d v0(0.5, 2.0, 0), w(0.5, 1.0, 2.0);
  for (RigidBody& b : m.bodies) {
    b.linear_velocity = v0 + w.cross(b.position - centre);
    b.angular_velocity = w;
  }
  return m;
}

// A Grashof crank-rocker in the plane z = 0: ground A-D 2 m, crank A-B 0.6 m (vertical at the
// start), coupler B-C 2 m, rocker C-D 1.2 m, hinges about z at A, B, C, D: 20 rows on 18
// freedoms, 3 redundant (a planar loop) and H singular without compliance. Links are bars of
// 2 kg/m, 5 x 5 cm; the crank turns at 2 rad/s and the coupler and rocker move with it.
Mechanism four_bar() {
  Mechanism m;
  m.name = "four-bar";
  const double crank_length = 0.6, coupler = 2.0, rocker = 1.2;
  const Vector3d a(0, 0, 0), d(2, 0, 0), b(0, crank_length, 0);
  // C: the upper intersection of the circles |C - B| = coupler, |C - D| = rocker
  const Vector3d bd = d - b;
  const double dist = bd.norm();
  const double along = (coupler * coupler - rocker * rocker + dist * dist) / (2 * dist);
  const double across = std::sqrt(coupler * coupler - along * along);
  const Vector3d c = b + along * bd / dist + across * Vector3d(-bd.y(), bd.x(), 0) / dist;
  auto bar = [&](const char* name, const Vector3d& p, const Vector3d& q, double l) {
    const double mass = 2 * l;
    return m.add_body(dynamic_body(name, mass, box_inertia(mass, l, 0.05, 0.05), 0.5 * (p + q), along_xy(p, q)));
  };
  const int ground = m.add_body(static_body("ground", Vector3d::Zero()));
  const int crank = bar("crank", a, b, crank_length), link = bar("coupler", b, c, coupler),
            rock = bar("rocker", c, d, rocker);
  // velocities of the loop: w1 z x (B - A) + w2 z x (C - B) = w3 z x (C - D), for w1 = 2 rad/s
  auto perp = [](const Vector3d& r) { return Eigen::Vector2d(-r.y(), r.x()); };  // z x r
  const double w1 = 2;
  const Eigen::Vector2d vb = w1 * perp(b - a);
  Eigen::Matrix2d k;
  k.col(0) = perp(c - b);
  k.col(1) = -perp(c - d);
  const Eigen::Vector2d w23 = k.lu().solve(-vb);
  auto spin = [&](int body, double w, const Vector3d& pivot, const Eigen::Vector2d& v_pivot) {
    const Eigen::Vector2d v = v_pivot + w * perp(m.bodies[body].position - pivot);
    m.bodies[body].linear_velocity = Vector3d(v.x(), v.y(), 0);
    m.bodies[body].angular_velocity = Vector3d(0, 0, w);
  };
  spin(crank, w1, a, Eigen::Vector2d::Zero());
  spin(link, w23[0], b, vb);
  spin(rock, w23[1], d, Eigen::Vector2d::Zero());
  axial(&m, ConstraintType::hinge, ground, crank, a, kZ);
  axial(&m, ConstraintType::hinge, crank, link, b, kZ);
  axial(&m, ConstraintType::hinge, link, rock, c, kZ);
  axial(&m, ConstraintType::hinge, rock, ground, d, kZ);
  return m;
}

// A slider-crank driven by its motor, in the plane z = 0, gravity off: crank A-B 0.3 m hinged
// to the ground at A = 0 (vertical at the start), coupler B-C 1 m, slider at C on a prismatic
// joint to the ground along x (the line through A), hinges about z at A, B and C: a closed loop
// of 20 rows on 18 freedoms, 3 redundant as in the four-bar. Crank and coupler are bars of
// 2 kg/m, 5 x 5 cm; the slider a 1 kg block of 20 x 10 x 10 cm. Everything starts at rest and
// a constant torque of 1 N m about z on the crank (its applied_torque) drives it; the coupler
// being longer than the crank, the crank turns fully and the slider's dead centres do not stop
// it. Gravity is off so that the torque is the only load: the kinetic energy at any time is
// the work tau (theta - theta_0) done on the crank (the test's work-energy balance).
Mechanism driven_crank() {
  Mechanism m;
  m.name = "driven-crank";
  m.gravity = Vector3d::Zero();
  const double crank_length = 0.3, coupler = 1.0, torque = 1.0;
  const Vector3d a = Vector3d::Zero(), b(0, crank_length, 0);
  const Vector3d c(std::sqrt(coupler * coupler - crank_length * crank_length), 0, 0);
  auto bar = [&](const char* name, const Vector3d& p, const Vector3d& q, double l) {
    const double mass = 2 * l;
    return m.add_body(dynamic_body(name, mass, box_inertia(mass, l, 0.05, 0.05), 0.5 * (p + q), along_xy(p, q)));
  };
  const int ground = m.add_body(static_body("ground", Vector3d::Zero()));
  const int crank = bar("crank", a, b, crank_length), link = bar("coupler", b, c, coupler);
  const int slider = m.add_body(dynamic_body("slider", 1, box_inertia(1, 0.2, 0.1, 0.1), c));
  m.bodies[crank].applied_torque = torque * kZ;
  axial(&m, ConstraintType::hinge, ground, crank, a, kZ);
  axial(&m, ConstraintType::hinge, crank, link, b, kZ);
  axial(&m, ConstraintType::hinge, link, slider, c, kZ);
  axial(&m, ConstraintType::prismatic, ground, slider, c, kX);
  return m;
}

// Ten planks (0.4 x 0.04 x 1 m of 600 kg/m^3 wood) between two static posts, each junction a
// 0.1 m rod on the centre line and two 0.1 m ropes at the sides (z = +-0.45). The deck starts
// on a circular arc of radius 8 m (a 5 m span sagging 0.4 m), the rods straight along it, so it
// hangs from the start and never sits on a straight, singular line; ropes are inequalities.
Mechanism rope_bridge() {
  Mechanism m;
  m.name = "rope-bridge";
  const int planks = 10;
  const double plank = 0.4, gap = 0.1, thickness = 0.04, width = 1.0, side = 0.45, radius = 8;
  const double mass = 600 * plank * thickness * width;
  // the junction points along the arc: gap, plank, gap, ..., plank, gap
  const double a_gap = 2 * std::asin(gap / (2 * radius)), a_plank = 2 * std::asin(plank / (2 * radius));
  const double total = (planks + 1) * a_gap + planks * a_plank;
  std::vector<Vector3d> p;  // (size 2 planks + 2)
  double phi = -total / 2;
  const double yc = radius * std::cos(total / 2);
  for (int k = 0; k < 2 * planks + 2; ++k) {
    p.emplace_back(radius * std::sin(phi), yc - radius * std::cos(phi), 0);
    phi += k % 2 == 0 ? a_gap : a_plank;
  }
  const int left = m.add_body(static_body("post_left", p.front()));
  const int right = m.add_body(static_body("post_right", p.back()));
  std::vector<int> body = {left};  // along the bridge: post, planks, post
  for (int k = 0; k < planks; ++k) {
    const Vector3d &s = p[2 * k + 1], &e = p[2 * k + 2];
    body.push_back(m.add_body(dynamic_body(numbered("plank", k), mass, box_inertia(mass, plank, thickness, width),
                                           0.5 * (s + e), along_xy(s, e))));
  }
  body.push_back(right);
  for (int j = 0; j <= planks; ++j) {
    const int a = body[j], b = body[j + 1];
    const Vector3d &pa = p[2 * j], &pb = p[2 * j + 1];
    m.add_constraint(m.distance(ConstraintType::rod, a, b, pa, pb));
    for (double z : {side, -side})
      m.add_constraint(m.distance(ConstraintType::rope, a, b, pa + z * kZ, pb + z * kZ));
  }
  return m;
}

// The talk's tracked vehicle: 40 hinges, dim(H) = 200. A chassis (2.2 x 0.5 x 1 m, 800 kg) on
// four sprocket wheels (radius 0.3 m, 0.12 m wide, 40 kg) hinged at (+-0.75, 1, +-0.6), and on
// each side a closed track of 16 links (0.3 x 0.03 x 0.2 m, 8 kg) hinged end to end around both
// wheels: 5 links along the top, 3 chords of 60 degrees around the front wheel, 5 along the
// bottom, 3 around the rear (every link 0.3 m = r: the chords of 60 degrees). The middle link
// of each arc is hinged at its centre to its wheel. Hinge axes are all z: each track is a planar
// loop with redundant rows. It drives forward at 2 m/s through the air: the tracks run around
// the wheels at 2 m/s relative to the chassis (top run 4 m/s, bottom run still, links on the
// arcs and the wheels turning at -2 / r rad/s about z), so the tracks' tension holds the links
// on their arcs. Every joint's velocity rows hold: a link crossing a tangent point has both
// ends moving along the stadium, which is a rigid motion of a 60-degree chord.
Mechanism tracked_vehicle() {
  Mechanism m;
  m.name = "tracked-vehicle";
  const double r = 0.3, half = 0.75, y = 1.0, track_z = 0.6, pitch = r;  // pitch: link length
  const double speed = 2;  // forward, and of the tracks relative to the chassis
  const Vector3d forward = speed * kX, spin = -speed / r * kZ;
  m.add_body(dynamic_body("chassis", 800, box_inertia(800, 2.2, 0.5, 1.0), Vector3d(0, y + 0.1, 0)));
  m.bodies[0].linear_velocity = forward;
  // the track's joints around a stadium, in (x, y) about the wheels' level: top run from the rear
  std::vector<Eigen::Vector2d> q;  // (size 16)
  for (int j = 0; j <= 5; ++j) q.emplace_back(-half + pitch * j, r);
  for (double deg : {30.0, -30.0}) q.emplace_back(half + r * std::cos(deg * kPi / 180), r * std::sin(deg * kPi / 180));
  for (int j = 0; j <= 5; ++j) q.emplace_back(half - pitch * j, -r);
  for (double deg : {-150.0, 150.0})
    q.emplace_back(-half + r * std::cos(deg * kPi / 180), r * std::sin(deg * kPi / 180));
  const int n = static_cast<int>(q.size());
  const int front_arc_link = 6, rear_arc_link = 14;  // q[6] -> q[7] and q[14] -> q[15]

  struct Side {
    const char* name;
    double z;
  };
  const Side sides[] = {{"left", -track_z}, {"right", track_z}};  // facing +x, y up: left is -z
  int wheel[2][2];                                                 // [side][rear, front]
  for (int s = 0; s < 2; ++s) {
    for (int f = 0; f < 2; ++f) {
      std::string name = "wheel_";
      name += sides[s].name;
      name += f ? "_front" : "_rear";
      wheel[s][f] = m.add_body(dynamic_body(name, 40, cylinder_inertia(40, r, 0.12, 2),
                                            Vector3d(f ? half : -half, y, sides[s].z)));
      axial(&m, ConstraintType::hinge, 0, wheel[s][f], m.bodies[wheel[s][f]].position, kZ);
      m.bodies[wheel[s][f]].linear_velocity = forward;
      m.bodies[wheel[s][f]].angular_velocity = spin;
    }
  }
  int first_link[2];
  for (int s = 0; s < 2; ++s) {
    auto world = [&](const Eigen::Vector2d& p) { return Vector3d(p.x(), y + p.y(), sides[s].z); };
    std::string prefix = "track_";
    prefix += sides[s].name;
    first_link[s] = static_cast<int>(m.bodies.size());
    for (int k = 0; k < n; ++k) {
      const Vector3d a = world(q[k]), b = world(q[(k + 1) % n]);
      RigidBody& link = m.bodies[m.add_body(dynamic_body(
          numbered(prefix.c_str(), k), 8, box_inertia(8, pitch, 0.03, 0.2), 0.5 * (a + b), along_xy(a, b)))];
      // links 0-4 run along the top, 8-12 along the bottom, 5-7 and 13-15 turn with a wheel
      if (k <= 4 || (k >= 8 && k <= 12)) {
        link.linear_velocity = forward + (k <= 4 ? 1 : -1) * speed * kX;
      } else {
        const Vector3d centre(k < 8 ? half : -half, y, sides[s].z);
        link.linear_velocity = forward + spin.cross(link.position - centre);
        link.angular_velocity = spin;
      }
    }
    for (int k = 0; k < n; ++k)  // link k-1 to link k at q[k]
      axial(&m, ConstraintType::hinge, first_link[s] + (k + n - 1) % n, first_link[s] + k, world(q[k]), kZ);
  }
  for (int s = 0; s < 2; ++s) {
    for (int f = 0; f < 2; ++f) {
      const int link = first_link[s] + (f ? front_arc_link : rear_arc_link);
      axial(&m, ConstraintType::hinge, wheel[s][f], link, m.bodies[link].position, kZ);
    }
  }
  return m;
}

// The talk's multi-wheeled vehicle: 20 wheel joints on one chassis, dim(H) = 88, H 100% dense.
// A chassis 6.4 x 0.8 x 2 m of 800 kg (20 wheels' mass) on ten axles 0.6 m apart, two wheels
// each (radius 0.28 m, 0.2 m wide, 40 kg) outside its sides: the two front and two rear axles'
// wheels on hinges (5 rows), the six middle axles' on cylindrical joints (4 rows, free to slide
// along the axle): 8 x 5 + 12 x 4 = 88. It is thrown through the air at 5 m/s, turning left at
// 0.3 rad/s about y, every wheel spinning as if rolling (-5 / r rad/s about its axle): the turn
// tilts the spinning wheels, whose gyroscopic torques the joints carry.
Mechanism multi_wheeled_vehicle() {
  Mechanism m;
  m.name = "multi-wheeled-vehicle";
  const double y = 1.0, r = 0.28, width = 0.2, wheel_mass = 40;
  const int axles = 10;
  const Vector3d velocity(5, 0, 0), turn(0, 0.3, 0), spin = -5 / r * kZ;
  m.add_body(dynamic_body("chassis", 20 * wheel_mass, box_inertia(20 * wheel_mass, 6.4, 0.8, 2.0), Vector3d(0, y, 0)));
  m.bodies[0].linear_velocity = velocity;
  m.bodies[0].angular_velocity = turn;
  for (int i = 0; i < axles; ++i) {
    const bool hinged = i < 2 || i >= axles - 2;
    for (const char* side : {"left", "right"}) {
      const double z = std::string_view(side) == "left" ? -1.15 : 1.15;
      std::string name = "wheel_";
      name += side;
      const Vector3d centre(-2.7 + 0.6 * i, y - 0.4, z);
      const int w = m.add_body(
          dynamic_body(numbered(name.c_str(), i), wheel_mass, cylinder_inertia(wheel_mass, r, width, 2), centre));
      axial(&m, hinged ? ConstraintType::hinge : ConstraintType::cylindrical, 0, w, centre, kZ);
      m.bodies[w].linear_velocity = velocity + turn.cross(centre - m.bodies[0].position);
      m.bodies[w].angular_velocity = turn + spin;
    }
  }
  return m;
}

// ---- planar linkages (the mechanism-50 walker): points and velocities in the plane z = const ----

using Eigen::Vector2d;

double cross2(const Vector2d& a, const Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); }
Vector2d perp(const Vector2d& r) { return Vector2d(-r.y(), r.x()); }  // z x r

// The point at distance rp from p and rq from q, left (side +1) or right (-1) of the line p -> q.
Vector2d circle_intersection(const Vector2d& p, double rp, const Vector2d& q, double rq, int side) {
  const Vector2d pq = q - p;
  const double d2 = pq.squaredNorm(), d = std::sqrt(d2);
  const double along = (rp * rp - rq * rq + d2) / (2 * d);
  const Vector2d u = pq / d;
  return p + along * u + side * std::sqrt(rp * rp - along * along) * perp(u);
}

// The velocity of a point x held at fixed distances from p and q (a dyad):
// (x - p).(v - vp) = 0 and (x - q).(v - vq) = 0, solved by Cramer's rule.
Vector2d dyad_velocity(const Vector2d& x, const Vector2d& p, const Vector2d& vp, const Vector2d& q, const Vector2d& vq) {
  const Vector2d a = x - p, b = x - q;
  const double ra = a.dot(vp), rb = b.dot(vq), det = cross2(a, b);
  return Vector2d(ra * b.y() - rb * a.y(), a.x() * rb - b.x() * ra) / det;
}

// Sets the body's velocities to the planar rigid motion (rotation about z) that moves point p
// at vp and point q at vq; (q - p).(vq - vp) = 0, as the dyads above give.
void move_planar(RigidBody* body, const Vector2d& p, const Vector2d& vp, const Vector2d& q, const Vector2d& vq) {
  const double w = cross2(q - p, vq - vp) / (q - p).squaredNorm();
  const Vector2d v = vp + w * perp(body->position.head<2>() - p);
  body->linear_velocity = Vector3d(v.x(), v.y(), 0);
  body->angular_velocity = Vector3d(0, 0, w);
}

// A uniform triangular plate of the given mass and thickness with corners p, q, r in the plane
// z: centre of mass at the centroid, body frame on its principal axes. About the centroid the
// plate's second moment is S = m/12 sum v v^T over the corners v (integrating x x^T over the
// triangle in barycentric coordinates); its principal directions in the plane are at angle phi, tan 2 phi = 2 S_xy /
// (S_xx - S_yy); I = trace(S) Id - S, the thickness adding m t^2 / 12 to the in-plane axes.
RigidBody triangle_plate(const std::string& name, double mass, double thickness, const Vector2d& p, const Vector2d& q,
                         const Vector2d& r, double z) {
  const Vector2d c = (p + q + r) / 3;
  Eigen::Matrix2d s = Eigen::Matrix2d::Zero();
  const Vector2d corners[] = {p - c, q - c, r - c};
  for (const Vector2d& v : corners) s += mass / 12 * v * v.transpose();
  const double phi = 0.5 * std::atan2(2 * s(0, 1), s(0, 0) - s(1, 1));
  const Vector2d u(std::cos(phi), std::sin(phi));
  const double s1 = u.dot(s * u), s2 = perp(u).dot(s * perp(u)), t = mass * thickness * thickness / 12;
  return dynamic_body(name, mass, Vector3d(s2 + t, s1 + t, s1 + s2), Vector3d(c.x(), c.y(), z),
                      Eigen::Quaterniond(Eigen::AngleAxisd(phi, kZ)));
}

// A Strandbeest on a test stand, the talk's 50-constraint mechanism in size and shape: 48 hinges
// and 2 ball joints, dim(H) = 246, H 12% dense. Five Theo Jansen legs (Jansen's "holy numbers"
// in cm, as metres / 100: crank 0.15, a = 0.38, l = 0.078, b 0.415, c 0.393, d 0.401, e 0.558,
// f 0.394, g 0.367, h 0.657, i 0.49, j 0.5, k 0.619) in the planes z = -0.4 .. 0.4, driven by
// one crankshaft (20 kg, a 1.4 m shaft of radius 2.5 cm along z through O = (0, 1, 0)) whose
// five throws are 72 degrees apart. It turns in two self-aligning bearings of the static frame,
// ball joints at z = +-0.6 (together a hinge about z; the ball rows along z are one redundant
// pair). Legs 0, 2, 4 face -x, legs 1, 3 are mirrored (their fixed pivot B at +x), so that all
// feet push the same way. Each leg is six bodies and nine hinges (axes z): the links j (crank
// pin A - C) and k (A - E), the plate B-C-D hinged to the frame at B, the rocker c (B - E), the
// link f (D - F) and the foot plate E-F-G hinged to the rocker at E; its three loops close
// through the crankshaft and the frame. Links are aluminium bars 2 x 2 cm (1.08 kg/m), plates
// 1 cm aluminium (27 kg/m^2). A motor's rotor (a 12 kg disc, radius 0.25 m, 4 cm thick, hinged
// to the frame 6 cm beside the crankshaft's axis, beyond its end at z = -0.75) drives an
// overhung throw (0.2 m, z = -0.7) through a 0.22 m connecting rod (0.5 kg) pinned 0.2 m from
// the rotor's axis: a drag link (the frame is its shortest bar, so both cranks turn fully and
// never reach a dead centre). The crankshaft turns at 4 rad/s and every other body moves with it
// (velocities from the derivatives of the dyads), the legs swinging under gravity through the
// air, the feet 8 cm above y = 0 at the bottom of their stride. The frame is static, so the
// crankshaft joins 13 constraints (a dense 61 x 61 block of H) and the frame's own couple
// nothing: 34 bodies, 33 dynamic. (Long: the parts listed in the order the paragraph names them.)
Mechanism mechanism_50() {
  Mechanism m;
  m.name = "mechanism-50";
  const Vector2d o(0, 1);  // crank axis, in the plane (x, y)
  const double w = 4, theta0 = 0.3;
  const double crank = 0.15, a = 0.38, l = 0.078, b = 0.415, c = 0.393, d = 0.401, e = 0.558, f = 0.394, g = 0.367,
               h = 0.657, i = 0.49, j = 0.5, k = 0.619;
  const double bar_density = 1.08, plate_density = 27, bar_section = 0.02, plate_thickness = 0.01;
  const int frame = m.add_body(static_body("frame", Vector3d(o.x(), o.y(), 0)));
  const int shaft = m.add_body(dynamic_body("crankshaft", 20, cylinder_inertia(20, 0.025, 1.4, 2), Vector3d(o.x(), o.y(), 0)));
  m.bodies[shaft].angular_velocity = w * kZ;
  for (double z : {-0.6, 0.6}) ball(&m, frame, shaft, Vector3d(o.x(), o.y(), z));
  auto at = [](const Vector2d& p, double z) { return Vector3d(p.x(), p.y(), z); };
  auto bar = [&](const std::string& name, const Vector2d& p, const Vector2d& q, double z) {
    const double length = (q - p).norm(), mass = bar_density * length;
    return m.add_body(dynamic_body(name, mass, box_inertia(mass, length, bar_section, bar_section), at(0.5 * (p + q), z),
                                   along_xy(at(p, z), at(q, z))));
  };
  auto plate = [&](const std::string& name, const Vector2d& p, const Vector2d& q, const Vector2d& r, double z) {
    const double mass = plate_density * 0.5 * std::abs(cross2(q - p, r - p));
    return m.add_body(triangle_plate(name, mass, plate_thickness, p, q, r, z));
  };
  auto hinge = [&](int body_a, int body_b, const Vector2d& p, double z) {
    axial(&m, ConstraintType::hinge, body_a, body_b, at(p, z), kZ);
  };
  for (int leg = 0; leg < 5; ++leg) {
    const double z = -0.4 + 0.2 * leg, s = leg % 2 == 0 ? 1 : -1;  // s = -1: mirrored, x -> -x
    // the leg in its own coordinates (crank axis at the origin, B at (-a, -l)), where the crank
    // pin is at angle phi and turns at s w; the sides of the intersections give Jansen's shape
    const double theta = theta0 + 2 * kPi * leg / 5, phi = s > 0 ? theta : kPi - theta;
    const Vector2d pa = crank * Vector2d(std::cos(phi), std::sin(phi)), pb(-a, -l), zero = Vector2d::Zero();
    const Vector2d pc = circle_intersection(pa, j, pb, b, -1), pd = circle_intersection(pb, d, pc, e, 1),
                   pe = circle_intersection(pb, c, pa, k, -1), pf = circle_intersection(pd, f, pe, g, -1),
                   pg = circle_intersection(pe, i, pf, h, 1);
    const Vector2d va = s * w * perp(pa), vc = dyad_velocity(pc, pa, va, pb, zero),
                   vd = dyad_velocity(pd, pb, zero, pc, vc), ve = dyad_velocity(pe, pb, zero, pa, va),
                   vf = dyad_velocity(pf, pd, vd, pe, ve);
    // to the world: mirrored, then moved to the crank axis
    auto point = [&](const Vector2d& p) { return Vector2d(o.x() + s * p.x(), o.y() + p.y()); };
    auto velocity = [&](const Vector2d& v) { return Vector2d(s * v.x(), v.y()); };
    const Vector2d A = point(pa), B = point(pb), C = point(pc), D = point(pd), E = point(pe), F = point(pf), G = point(pg);
    const Vector2d vA = velocity(va), vC = velocity(vc), vD = velocity(vd), vE = velocity(ve), vF = velocity(vf);
    const std::string prefix = numbered("leg", leg);
    auto part = [&](const char* name) {
      std::string full = prefix;
      full += '_';
      full += name;
      return full;
    };
    const int upper = bar(part("upper"), A, C, z), hip = plate(part("hip"), B, C, D, z), lower = bar(part("lower"), A, E, z),
              rocker = bar(part("rocker"), B, E, z), tie = bar(part("tie"), D, F, z), foot = plate(part("foot"), E, F, G, z);
    move_planar(&m.bodies[upper], A, vA, C, vC);
    move_planar(&m.bodies[hip], B, zero, C, vC);
    move_planar(&m.bodies[lower], A, vA, E, vE);
    move_planar(&m.bodies[rocker], B, zero, E, vE);
    move_planar(&m.bodies[tie], D, vD, F, vF);
    move_planar(&m.bodies[foot], E, vE, F, vF);
    hinge(shaft, upper, A, z);
    hinge(shaft, lower, A, z);
    hinge(frame, hip, B, z);
    hinge(frame, rocker, B, z);
    hinge(upper, hip, C, z);
    hinge(hip, tie, D, z);
    hinge(lower, rocker, E, z);
    hinge(rocker, foot, E, z);
    hinge(tie, foot, F, z);
  }
  // the drive: the rotor's pin r, the overhung throw p and the rod between them (a drag link)
  const double z_rotor = -0.75, z_rod = -0.7, ground = 0.06, rotor_pin = 0.2, rod = 0.22, throw_drive = 0.2;
  const Vector2d centre = o + Vector2d(ground, 0);
  const Vector2d p = o + throw_drive * Vector2d(std::cos(theta0), std::sin(theta0)), vp = w * perp(p - o);
  const Vector2d r = circle_intersection(centre, rotor_pin, p, rod, 1), vr = dyad_velocity(r, centre, Vector2d::Zero(), p, vp);
  const int rotor = m.add_body(dynamic_body("rotor", 12, cylinder_inertia(12, 0.25, 0.04, 2), at(centre, z_rotor)));
  m.bodies[rotor].angular_velocity = Vector3d(0, 0, cross2(r - centre, vr) / (r - centre).squaredNorm());
  const int link = m.add_body(dynamic_body("rod", 0.5, box_inertia(0.5, rod, bar_section, bar_section),
                                           at(0.5 * (p + r), z_rod), along_xy(at(p, z_rod), at(r, z_rod))));
  move_planar(&m.bodies[link], p, vp, r, vr);
  hinge(frame, rotor, centre, z_rotor);
  hinge(rotor, link, r, z_rod);
  hinge(link, shaft, p, z_rod);
  return m;
}

// "<digits>" in 1..100000, no sign, no leading zero.
// --- Scenes with contacts: y up, a ground plane at y = 0, 1/60 s steps, friction 0.6 ---------

constexpr double kContactFriction = 0.6;

int add_ground(Mechanism* m) {
  RigidBody ground = static_body("ground", Vector3d::Zero());
  Shape plane;
  plane.type = ShapeType::plane;
  plane.normal = kY;
  plane.friction = kContactFriction;
  ground.shapes.push_back(plane);
  return m->add_body(ground);
}

Shape box_shape(const Vector3d& half_extents) {
  Shape s;
  s.type = ShapeType::box;
  s.half_extents = half_extents;
  s.friction = kContactFriction;
  return s;
}

// A unit cube (half extents 0.5) of `mass` resting at centre height y, 1 mm into what is below.
int add_cube(Mechanism* m, const std::string& name, double mass, const Vector3d& centre) {
  RigidBody b = dynamic_body(name, mass, box_inertia(mass, 1, 1, 1), centre);
  b.shapes.push_back(box_shape(Vector3d::Constant(0.5)));
  return m->add_body(b);
}

// A 1 kg cube on the ground carrying a cube `ratio` times heavier: what PGS lets sink.
Mechanism box_stack(const std::string& name, double ratio) {
  Mechanism m;
  m.name = name;
  m.timestep = 1.0 / 60;
  add_ground(&m);
  add_cube(&m, "light", 1, Vector3d(0, 0.499, 0));
  add_cube(&m, "heavy", ratio, Vector3d(0, 1.498, 0));
  return m;
}

// `layers` layers of 1 kg unit cubes, layer i holding layers - i cubes side by side (1 mm gaps),
// each layer centred on the one below: 55 cubes for 10 layers.
Mechanism pyramid(const std::string& name, int layers) {
  Mechanism m;
  m.name = name;
  m.timestep = 1.0 / 60;
  m.bodies.reserve(1 + layers * (layers + 1) / 2);
  add_ground(&m);
  for (int i = 0; i < layers; ++i)
    for (int j = 0; j < layers - i; ++j) {
      const double x = (j - 0.5 * (layers - i - 1)) * 1.001;
      add_cube(&m, numbered("box", static_cast<int>(m.bodies.size()) - 1), 1, Vector3d(x, 0.499 + 0.999 * i, 0));
    }
  return m;
}

// n capsule links (radius 5 cm, 0.5 m between joints, 1 kg) held horizontal from a ball joint
// 2 m above the ground, a ball of radius 0.25 m and `ratio` times a link's mass centred on the
// free end (the last joint at its centre, as a pendulum's bob: a joint on its surface would roll
// under the ball and pull the last link into the ground, which no solver can hold); released, it
// swings down onto the ground and lies on it.
Mechanism ball_chain(const std::string& name, int n, double ratio) {
  const double l = 0.5, r = 0.05, ball_radius = 0.25, height = 2;
  Mechanism m;
  m.name = name;
  m.timestep = 1.0 / 60;
  m.bodies.reserve(n + 3);
  add_ground(&m);
  const int pivot = m.add_body(static_body("pivot", Vector3d(0, height, 0)));
  Shape capsule;
  capsule.type = ShapeType::capsule;
  capsule.radius = r;
  capsule.half_length = l / 2 - r;
  capsule.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 2, kY));  // the capsule's z along the link's x
  capsule.friction = kContactFriction;
  int previous = pivot;
  for (int i = 0; i < n; ++i) {
    RigidBody link = dynamic_body(numbered("link", i), 1, cylinder_inertia(1, r, l, 0), Vector3d(l * (i + 0.5), height, 0));
    link.shapes.push_back(capsule);
    const int k = m.add_body(link);
    ball(&m, previous, k, Vector3d(l * i, height, 0));
    previous = k;
  }
  const double mass = ratio;
  RigidBody bob = dynamic_body("ball", mass, sphere_inertia(mass, ball_radius), Vector3d(l * n, height, 0));
  Shape sphere;
  sphere.type = ShapeType::sphere;
  sphere.radius = ball_radius;
  sphere.friction = kContactFriction;
  bob.shapes.push_back(sphere);
  const int k = m.add_body(bob);
  ball(&m, previous, k, Vector3d(l * n, height, 0));
  return m;
}

// A vehicle of the talk standing on a ground plane, at rest, driven: every wheel `w` carries the
// torque -torque z (forward, +x) and the chassis the reaction, as a motor between them would.
// `ground_y` is where the ground touches the lowest shape (1 mm deep).
Mechanism on_ground(Mechanism m, const std::string& name, double ground_y, double torque) {
  m.name = name;
  m.timestep = 1.0 / 60;
  int wheels = 0;
  for (RigidBody& b : m.bodies) {
    b.linear_velocity = b.angular_velocity = Vector3d::Zero();
    if (b.name.starts_with("wheel_") && !b.shapes.empty()) {
      b.applied_torque = -torque * kZ;
      ++wheels;
    }
  }
  m.bodies[m.find_body("chassis")].applied_torque = wheels * torque * kZ;
  const int ground = add_ground(&m);
  m.bodies[ground].position = Vector3d(0, ground_y + 0.001, 0);
  return m;
}

// The tracked vehicle on the ground: its track links are boxes (the links' length, 3 cm thick,
// 20 cm wide) that touch the ground and the wheels but not each other (conaffinity 0); the four
// wheels are spheres inside the tracks, which keep the loops from folding under the load (each
// wheel is hinged to one link, which it does not touch); 300 N m on each. A link where the track
// wraps round a wheel is a chord of the 0.3 m circle, its inner face 0.245 m from the wheel's
// centre: a sphere of 0.24 m clears it at rest (papers/physics.md, "Vehicles on the ground").
Mechanism tracked_vehicle_on_ground() {
  Mechanism m = tracked_vehicle();
  for (RigidBody& b : m.bodies) {
    if (b.name.starts_with("track_")) {
      b.shapes.push_back(box_shape(Vector3d(0.15, 0.015, 0.1)));
      b.shapes.back().conaffinity = 0;
    } else if (b.name.starts_with("wheel_")) {
      Shape s;
      s.type = ShapeType::sphere;
      s.radius = 0.24;
      s.friction = kContactFriction;
      b.shapes.push_back(s);
    }
  }
  return on_ground(std::move(m), "tracked-vehicle-on-ground", 1.0 - 0.3 - 0.015, 300);
}

// The multi-wheeled vehicle on the ground: its 20 wheels are spheres of the wheels' radius,
// friction 1; 100 N m on each.
Mechanism multi_wheeled_vehicle_on_ground() {
  Mechanism m = multi_wheeled_vehicle();
  for (RigidBody& b : m.bodies)
    if (b.name.starts_with("wheel_")) {
      Shape s;
      s.type = ShapeType::sphere;
      s.radius = 0.28;
      s.friction = 1;
      b.shapes.push_back(s);
    }
  return on_ground(std::move(m), "multi-wheeled-vehicle-on-ground", 1.0 - 0.4 - 0.28, 100);
}

bool parse_count(std::string_view s, int* n) {
  if (s.empty() || s.size() > 6 || s[0] == '0') return false;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), *n);
  return ec == std::errc() && end == s.data() + s.size() && *n >= 1 && *n <= 100000;
}

// A positive finite number, the whole of s.
bool parse_ratio(std::string_view s, double* r) {
  if (s.empty()) return false;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), *r);
  return ec == std::errc() && end == s.data() + s.size() && std::isfinite(*r) && *r > 0;
}

// "N-R": a count and a ratio (heavy-chain-N-R, ball-chain-N-R).
bool parse_count_ratio(std::string_view s, int* n, double* r) {
  const size_t dash = s.find('-');
  return dash != std::string_view::npos && parse_count(s.substr(0, dash), n) && parse_ratio(s.substr(dash + 1), r);
}

}  // namespace

std::vector<std::string> builtin_scene_names() {
  return {"pendulum", "chain-10", "heavy-chain-10-1000", "ragdoll", "four-bar",
          "rope-bridge", "tracked-vehicle", "multi-wheeled-vehicle", "mechanism-50", "driven-crank",
          "box-stack-1000", "pyramid-10", "ball-chain-20-1000", "tracked-vehicle-on-ground",
          "multi-wheeled-vehicle-on-ground"};
}

bool builtin_scene(std::string_view name, Mechanism* mechanism) {
  constexpr std::string_view kChain = "chain-", kHeavy = "heavy-chain-", kStack = "box-stack-", kPyramid = "pyramid-",
                             kBallChain = "ball-chain-";
  if (name == "pendulum") {
    *mechanism = pendulum();
  } else if (name == "ragdoll") {
    *mechanism = ragdoll();
  } else if (name == "four-bar") {
    *mechanism = four_bar();
  } else if (name == "rope-bridge") {
    *mechanism = rope_bridge();
  } else if (name == "tracked-vehicle-on-ground") {
    *mechanism = tracked_vehicle_on_ground();
  } else if (name == "multi-wheeled-vehicle-on-ground") {
    *mechanism = multi_wheeled_vehicle_on_ground();
  } else if (name == "tracked-vehicle") {
    *mechanism = tracked_vehicle();
  } else if (name == "multi-wheeled-vehicle") {
    *mechanism = multi_wheeled_vehicle();
  } else if (name == "mechanism-50") {
    *mechanism = mechanism_50();
  } else if (name == "driven-crank") {
    *mechanism = driven_crank();
  } else if (name.starts_with(kStack)) {
    double ratio = 0;
    if (!parse_ratio(name.substr(kStack.size()), &ratio)) return false;
    *mechanism = box_stack(std::string(name), ratio);
  } else if (name.starts_with(kPyramid)) {
    int n = 0;
    if (!parse_count(name.substr(kPyramid.size()), &n) || n > 100) return false;  // (100 layers: 5050 cubes)
    *mechanism = pyramid(std::string(name), n);
  } else if (name.starts_with(kBallChain)) {
    int n = 0;
    double ratio = 0;
    if (!parse_count_ratio(name.substr(kBallChain.size()), &n, &ratio)) return false;
    *mechanism = ball_chain(std::string(name), n, ratio);
  } else if (name.starts_with(kChain)) {
    int n = 0;
    if (!parse_count(name.substr(kChain.size()), &n)) return false;
    *mechanism = chain(std::string(name), n, false, 1);
  } else if (name.starts_with(kHeavy)) {
    int n = 0;
    double ratio = 0;
    if (!parse_count_ratio(name.substr(kHeavy.size()), &n, &ratio)) return false;
    *mechanism = chain(std::string(name), n, true, ratio);
  } else {
    return false;
  }
  return true;
}

Mechanism load_mechanism(const std::string& spec, MjcfDropped* dropped, bool allow_dropped) {
  // An MJCF model by its extension, even if missing: MuJoCo names the problem.
  if (is_mjcf_path(spec)) return load_mjcf(spec, dropped, allow_dropped);
  if (std::filesystem::exists(spec)) return load_scene(spec);
  Mechanism m;
  if (builtin_scene(spec, &m)) {
    check_ranges(m, spec);  // heavy-chain-N-R takes any R
    return m;
  }
  std::string known;
  for (const std::string& name : builtin_scene_names()) known += " " + name;
  throw InputError(spec + ": no such file and no built-in scene of that name (built-in:" + known +
                   "; chain-N and heavy-chain-N-R take N in 1..100000 and any R > 0)");
}

}  // namespace ldlpgs
