// The step's collide stage and the contacts' part of the others: contact points, their rows'
// blocks and warm start, their rows at velocity and position level, and their impulses kept.
#include "ldlpgs/physics/step_stages.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "ldlpgs/sparse/error.h"

namespace ldlpgs {

using namespace step_stages;

// This step's contact points, matched with the last step's, as two blocks each past the
// constraints' (normal: impulse >= 0; friction: bounded by the normal impulse), warm-started with
// the matched impulses. A contact pushing for ContactOptions::factor_after steps in a row joins
// ldl-pgs's LDL block with its normal row; those come first, so that a repeated set of factored
// contacts is the same blocks and its symbolic phase is reused (solver.h).
void Simulation::detect_contacts() {
  const ContactOptions& o = options_.contacts;
  collision_->detect(mechanism_, o.margin, mechanism_.timestep, &points_);
  std::swap(contacts_, previous_contacts_);
  body_rotations(mechanism_, &rotations_);
  make_contacts(mechanism_, rotations_, points_, previous_contacts_, o.match_distance, &contact_keys_, &contacts_);
  mark_factored_contacts();
  order_factored_first();
  system_.truncate(joint_blocks_);
  for (const Contact& c : contacts_) {
    const int normal = system_.add_block(1, column_[c.body_a], column_[c.body_b]);
    system_.set_bounds(normal, 0, kUnbounded);
    system_.blocks[normal].factored = c.factored;
    const int friction = system_.add_block(2, column_[c.body_a], column_[c.body_b]);
    system_.set_friction(friction, system_.blocks[normal].position, c.friction, o.friction_pyramid);
  }
  const size_t rows = system_.num_rows;
  lambda_.resize(rows);
  mu_.resize(rows);
  predicted_.resize(rows);
  for (size_t i = 0; i < contacts_.size(); ++i) {
    const int first = system_.blocks[joint_blocks_ + 2 * i].position;
    for (int r = 0; r < 3; ++r) lambda_[first + r] = contacts_[i].impulse[r];
  }
}

// Which contacts ldl-pgs factors this step (ContactOptions: factor_after, factor_jointed,
// factor_mass_ratio). carrying_[b]: body b touches a dynamic body factor_mass_ratio times its mass.
void Simulation::mark_factored_contacts() {
  const ContactOptions& o = options_.contacts;
  const bool factoring = options_.solver.kind == SolverKind::ldl_pgs && o.factor_after > 0;
  std::fill(carrying_.begin(), carrying_.end(), char{o.factor_mass_ratio <= 0});
  if (factoring && o.factor_mass_ratio > 0)
    for (const Contact& c : contacts_) {
      const RigidBody &a = mechanism_.bodies[c.body_a], &b = mechanism_.bodies[c.body_b];
      if (a.is_static || b.is_static) continue;
      if (b.mass >= o.factor_mass_ratio * a.mass) carrying_[c.body_a] = 1;
      if (a.mass >= o.factor_mass_ratio * b.mass) carrying_[c.body_b] = 1;
    }
  for (Contact& c : contacts_)
    c.factored = factoring && c.pushing_steps >= o.factor_after &&
                 (o.factor_jointed || !(jointed_[c.body_a] || jointed_[c.body_b])) &&
                 (carrying_[c.body_a] || carrying_[c.body_b]);
}

// Factored contacts first, in the order of their bodies, so that the same set of touching pairs
// is the same blocks whatever order the detector found them in; the rest in the detector's order.
// The permutation is sorted as small keys and applied through previous_contacts_, no longer
// needed once matched (std::sort on a total order: stable_sort would allocate every step).
void Simulation::order_factored_first() {
  const int n = static_cast<int>(contacts_.size());
  bool any_factored = false;
  for (int i = 0; i < n; ++i) {
    contacts_[i].point_index = i;
    any_factored = any_factored || contacts_[i].factored;
  }
  if (!any_factored) return;  // (the detector's order already: no sort, no copy)
  contact_keys_.resize(n);
  for (int i = 0; i < n; ++i) {
    const Contact& c = contacts_[i];
    // (unfactored: after every body, in the detector's order)
    contact_keys_[i] = c.factored ? ContactKey{c.body_a, c.body_b, c.shape_a, c.shape_b, i} : ContactKey{INT_MAX, 0, 0, 0, i};
  }
  std::sort(contact_keys_.begin(), contact_keys_.end());
  previous_contacts_.resize(n);
  for (int i = 0; i < n; ++i) previous_contacts_[i] = contacts_[contact_keys_[i].index];
  std::swap(contacts_, previous_contacts_);
}

// The contacts' rows at the current pose into system_: J (with_jacobian: the velocity level, or
// a refactoring position level; otherwise the step's J_0 stays, as post_stabilize needs), and
// the right-hand side. Velocity level: the normal row
// asks J V1 >= target, target = the gap closed in one step when apart (speculative), else
// baumgarte (depth - slop) / dt within max_correction_speed, and at least -e v_n when approaching
// faster than the restitution threshold; friction rows ask J V1 = 0 within their bound.
// Position level: (n . d + slop) >= 0 for the normal row; friction rows take no part (mu = 0).
// Returns the largest violation n . d + slop < 0 (m).
double Simulation::contact_rows(bool velocity, bool with_jacobian) {
  const ContactOptions& o = options_.contacts;
  const double dt = mechanism_.timestep;
  // The position level's rows of contact kn: its separation c and a slop, no friction.
  const auto position_row = [&](int kn, double c) {
    system_.blocks[kn + 1].friction = 0;
    const int in = system_.blocks[kn].position, if0 = system_.blocks[kn + 1].position;
    system_.rhs[in] = -(c + o.slop);
    system_.rhs[if0] = system_.rhs[if0 + 1] = 0;
    return -(c + o.slop);
  };
  double worst = 0;
  body_rotations(mechanism_, &rotations_);
  for (size_t i = 0; i < contacts_.size(); ++i) {
    const Contact& con = contacts_[i];
    const RigidBody &a = mechanism_.bodies[con.body_a], &b = mechanism_.bodies[con.body_b];
    const Eigen::Matrix3d &ra = rotations_[con.body_a], &rb = rotations_[con.body_b];
    const int kn = joint_blocks_ + 2 * static_cast<int>(i), kf = kn + 1;
    const int in = system_.blocks[kn].position, if0 = system_.blocks[kf].position;
    system_.blocks[kn].regularization = con.factored ? o.regularization : 0;
    if (con.factored) system_.compliance[in] = o.compliance;
    if (!velocity && !with_jacobian) {  // (the normal row's c is all it needs)
      worst = std::max(worst, position_row(kn, separation(con, a, ra, b, rb)));
      continue;
    }
    ContactRows rows;
    evaluate(con, a, ra, b, rb, &rows);
    const int ca = column_[con.body_a], cb = column_[con.body_b];
    for (int r = 0; r < 3 && with_jacobian; ++r) {
      const double* j = rows.jacobian.data() + 12 * r;
      const int k = r == 0 ? kn : kf, row = r == 0 ? 0 : r - 1;
      std::copy(j, j + 6, system_.cell_a(k) + 6 * row);
      std::copy(j + 6, j + 12, system_.cell_b(k) + 6 * row);
    }
    if (!velocity) {
      worst = std::max(worst, position_row(kn, rows.c[0]));
      continue;
    }
    system_.blocks[kf].friction = con.friction;
    // J V for the velocities before (now: a's and b's v and w) and after the free motion (v0_)
    const auto jv = [&](int r, const double* va, const double* vb) {
      const double* j = rows.jacobian.data() + 12 * r;
      double s = 0;
      for (int x = 0; x < 6; ++x) {
        if (va) s += j[x] * va[x];
        if (vb) s += j[6 + x] * vb[x];
      }
      return s;
    };
    const double* free_a = ca >= 0 ? v0_.data() + 6 * ca : nullptr;
    const double* free_b = cb >= 0 ? v0_.data() + 6 * cb : nullptr;
    const double gap = rows.c[0];
    double target = 0;
    if (con.factored) {
      // J V1 = 0: in the LDL block the targets must be consistent (in J's range), since the part
      // of them outside it (a clamp, a threshold, a slop) is divided by the compliance alone;
      // the post-stabilization corrects the depth (papers/physics.md, "Contacts in the factor").
      target = 0;
    } else {
      target = gap > 0 ? -gap / dt : std::min(o.baumgarte * std::max(0.0, -gap - o.slop) / dt, o.max_correction_speed);
      const double now_a[6] = {a.linear_velocity.x(),  a.linear_velocity.y(),  a.linear_velocity.z(),
                               a.angular_velocity.x(), a.angular_velocity.y(), a.angular_velocity.z()};
      const double now_b[6] = {b.linear_velocity.x(),  b.linear_velocity.y(),  b.linear_velocity.z(),
                               b.angular_velocity.x(), b.angular_velocity.y(), b.angular_velocity.z()};
      const double approach = jv(0, ca >= 0 ? now_a : nullptr, cb >= 0 ? now_b : nullptr);
      if (approach < -o.restitution_threshold) target = std::max(target, -con.restitution * approach);
    }
    system_.rhs[in] = target - jv(0, free_a, free_b);
    system_.rhs[if0] = -jv(1, free_a, free_b);
    system_.rhs[if0 + 1] = -jv(2, free_a, free_b);
  }
  return worst;
}

void Simulation::keep_contact_impulses() {
  for (size_t i = 0; i < contacts_.size(); ++i) {
    Contact& c = contacts_[i];
    const int first = system_.blocks[joint_blocks_ + 2 * i].position;
    for (int r = 0; r < 3; ++r) c.impulse[r] = lambda_[first + r];
    c.pushing_steps = c.impulse[0] > 0 ? c.pushing_steps + 1 : 0;
  }
}

double Simulation::penetration_max() const {
  double worst = 0;
  for (const Contact& c : contacts_)
    worst = std::max(worst, -separation(c, mechanism_.bodies[c.body_a], mechanism_.bodies[c.body_b]));
  return worst;
}

void Simulation::add_shape(int body, const Shape& shape) {
  RigidBody& b = writable(body, "add_shape", false);
  const std::string problem = shape_problem(shape, b.is_static);
  if (!problem.empty()) throw InputError("add_shape: body " + std::to_string(body) + " (" + b.name + "): " + problem);
  if (options_.solver.kind == SolverKind::direct)
    throw InputError("add_shape: the direct solver takes no contacts (use ldl-pgs)");
  b.shapes.push_back(shape);
  if (shape.type == ShapeType::plane) b.shapes.back().normal.normalize();
  collision_ = std::make_unique<CollisionWorld>(mechanism_);
  make_projector();  // (an exact projector takes no contacts)
}
}  // namespace ldlpgs
