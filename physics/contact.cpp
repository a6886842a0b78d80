// Contact rows and the matching of contact points across steps (contact.h).
#include "ldlpgs/physics/contact.h"

#include <algorithm>
#include <limits>

#include <Eigen/Geometry>

namespace ldlpgs {

namespace {

using Eigen::Vector3d;

ContactKey key_of(const ContactPoint& p, int index) { return {p.body_a, p.body_b, p.shape_a, p.shape_b, index}; }

// What a contact takes from its pair (friction and restitution by the pair rules of shape.h)
// and from its normal (the tangent frame in body a's frame): the same for every point of a pair
// that shares its normal, as a box on a face does, so computed once for them.
struct PairFrame {
  double friction = 0, restitution = 0;
  Vector3d normal = Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());  // (matches none)
  Eigen::Matrix3d frame_a = Eigen::Matrix3d::Identity();
};

// The tangent frame of normal n in body a's frame (rotation ra): t1 from n by Eigen's
// unitOrthogonal (deterministic), t2 = n x t1.
Eigen::Matrix3d frame_in_a(const Eigen::Matrix3d& ra, const Vector3d& n) {
  Eigen::Matrix3d world;
  world.col(0) = n.unitOrthogonal();
  world.col(1) = n.cross(world.col(0));
  world.col(2) = n;
  return ra.transpose() * world;
}

// The contact of a detected point: witness points depth/2 either side of the point along n, and
// the pair's frame and rules.
void fill_contact(const Mechanism& m, std::span<const Eigen::Matrix3d> rotations, const ContactPoint& p,
                  const PairFrame& pair, Contact* out) {
  const RigidBody &a = m.bodies[p.body_a], &b = m.bodies[p.body_b];
  const Eigen::Matrix3d &ra = rotations[p.body_a], &rb = rotations[p.body_b];
  Contact& c = *out;
  c.body_a = p.body_a;
  c.body_b = p.body_b;
  c.shape_a = p.shape_a;
  c.shape_b = p.shape_b;
  c.point = p;
  const Vector3d on_a = p.position + 0.5 * p.depth * p.normal, on_b = p.position - 0.5 * p.depth * p.normal;
  c.anchor_a = ra.transpose() * (on_a - a.position);
  c.anchor_b = rb.transpose() * (on_b - b.position);
  c.frame_a = pair.frame_a;
  c.friction = pair.friction;
  c.restitution = pair.restitution;
}

// Last step's impulse carried over: the normal one as it is, the friction one as a vector
// re-expressed in the new tangents, both frames body a's (the pair matched: the same body a).
void inherit(const Contact& old, Contact* c) {
  const Vector3d friction = old.frame_a.col(0) * old.impulse[1] + old.frame_a.col(1) * old.impulse[2];
  c->impulse = {old.impulse[0], friction.dot(c->frame_a.col(0)), friction.dot(c->frame_a.col(1))};
  c->pushing_steps = old.pushing_steps;
}

}  // namespace

double separation(const Contact& contact, const RigidBody& a, const Eigen::Matrix3d& ra, const RigidBody& b,
                  const Eigen::Matrix3d& rb) {
  const Vector3d r_a = ra * contact.anchor_a, r_b = rb * contact.anchor_b;
  const Vector3d d = (b.position + r_b) - (a.position + r_a);
  return (ra * contact.frame_a.col(2)).dot(d);
}

double separation(const Contact& contact, const RigidBody& a, const RigidBody& b) {
  return separation(contact, a, a.orientation.toRotationMatrix(), b, b.orientation.toRotationMatrix());
}

void evaluate(const Contact& contact, const RigidBody& a, const Eigen::Matrix3d& ra, const RigidBody& b,
              const Eigen::Matrix3d& rb, ContactRows* out) {
  const Vector3d r_a = ra * contact.anchor_a, r_b = rb * contact.anchor_b;
  const Vector3d d = (b.position + r_b) - (a.position + r_a);
  const int axis_of_row[3] = {2, 0, 1};  // n, t1, t2
  for (int row = 0; row < 3; ++row) {
    const Vector3d t = ra * contact.frame_a.col(axis_of_row[row]);
    out->c[row] = t.dot(d);
    const Vector3d w_a = t.cross(d + r_a), w_b = r_b.cross(t);
    double* j = out->jacobian.data() + 12 * row;
    for (int k = 0; k < 3; ++k) {
      j[k] = -t[k];
      j[3 + k] = w_a[k];
      j[6 + k] = t[k];
      j[9 + k] = w_b[k];
    }
  }
}

ConstraintRows evaluate(const Contact& contact, const RigidBody& a, const Eigen::Matrix3d& ra, const RigidBody& b,
                        const Eigen::Matrix3d& rb) {
  ContactRows rows;
  evaluate(contact, a, ra, b, rb, &rows);
  ConstraintRows out;
  out.rows = 3;
  std::copy(rows.c.begin(), rows.c.end(), out.c.begin());
  std::copy(rows.jacobian.begin(), rows.jacobian.end(), out.jacobian.begin());
  return out;
}

ConstraintRows evaluate(const Contact& contact, const RigidBody& a, const RigidBody& b) {
  return evaluate(contact, a, a.orientation.toRotationMatrix(), b, b.orientation.toRotationMatrix());
}

void body_rotations(const Mechanism& mechanism, std::vector<Eigen::Matrix3d>* out) {
  out->resize(mechanism.bodies.size());
  for (size_t i = 0; i < mechanism.bodies.size(); ++i) (*out)[i] = mechanism.bodies[i].orientation.toRotationMatrix();
}

void make_contacts(const Mechanism& m, std::span<const Eigen::Matrix3d> rotations, std::span<const ContactPoint> points,
                   std::span<const Contact> previous, double match_distance, std::vector<ContactKey>* keys,
                   std::vector<Contact>* out) {
  out->clear();
  keys->resize(previous.size());
  for (size_t i = 0; i < previous.size(); ++i) (*keys)[i] = key_of(previous[i].point, static_cast<int>(i));
  std::sort(keys->begin(), keys->end());
  auto pair_first = keys->end();
  ContactKey pair;
  PairFrame frame;
  for (const ContactPoint& p : points) {
    const ContactKey key = key_of(p, -1);
    const bool new_pair = !key.same_pair(pair);
    if (new_pair) {  // (a pair's points come together: one search per pair)
      pair = key;
      pair_first = std::lower_bound(keys->begin(), keys->end(), key);
      const Shape &sa = m.bodies[p.body_a].shapes[p.shape_a], &sb = m.bodies[p.body_b].shapes[p.shape_b];
      frame.friction = combined_friction(sa, sb);
      frame.restitution = combined_restitution(sa, sb);
    }
    if (new_pair || p.normal != frame.normal) {
      frame.normal = p.normal;
      frame.frame_a = frame_in_a(rotations[p.body_a], p.normal);
    }
    // (built on the stack, where the compiler drops the default initializers it overwrites;
    // emplace_back would zero the element first: a sixth of this function, perf)
    Contact c;
    fill_contact(m, rotations, p, frame, &c);
    const Contact* best = nullptr;
    double best_squared = match_distance * match_distance;
    for (auto it = pair_first; it != keys->end() && it->same_pair(key); ++it) {
      // along the contact plane only: where a detector puts a point across the gap varies
      const Vector3d diff = previous[it->index].anchor_a - c.anchor_a, n = c.frame_a.col(2);
      const double squared = (diff - n.dot(diff) * n).squaredNorm();
      if (squared <= best_squared) {
        best_squared = squared;
        best = &previous[it->index];
      }
    }
    if (best) inherit(*best, &c);
    out->push_back(c);
  }
}

}  // namespace ldlpgs
