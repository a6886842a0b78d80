#include "view/recording.h"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace ldlpgs::view {

Eigen::Vector3d box_from_inertia(double mass, const Eigen::Vector3d& inertia) {
  const double sum = inertia.sum();
  Eigen::Vector3d squared;  // a^2, b^2, c^2
  for (int i = 0; i < 3; ++i) squared[i] = 3 * (sum - 2 * inertia[i]) / (2 * mass);
  const double floor = 1e-4 * std::max(squared.maxCoeff(), 0.0);  // (a hundredth of the longest side)^2
  Eigen::Vector3d half;
  for (int i = 0; i < 3; ++i) half[i] = std::sqrt(std::max(squared[i], floor));
  if (!(half.maxCoeff() > 0) || !half.allFinite()) half.setConstant(0.05);  // nothing to go by: a 10 cm cube
  return half;
}

namespace {

// A unit quaternion component in units of 1/32767, rounded.
int16_t quantized(double x) { return static_cast<int16_t>(std::lround(std::clamp(x, -1.0, 1.0) * 32767)); }

// What shatter() returns for a mechanism it leaves whole: every body its own shard.
ShatterResult unshattered(const Mechanism& m) {
  ShatterResult r;
  r.mechanism = m;
  for (size_t i = 0; i < m.bodies.size(); ++i) r.shards.push_back({static_cast<int>(i)});
  return r;
}

// A hull or a heightfield drawn as its bounding box in its frame (the page draws no meshes).
Solid bounding_box(Solid solid, const Shape& s) {
  Eigen::Vector3d low, high;
  if (s.type == ShapeType::convex) {
    low = high = s.hull->vertices.front();
    for (const Eigen::Vector3d& v : s.hull->vertices) {
      low = low.cwiseMin(v);
      high = high.cwiseMax(v);
    }
  } else {
    const HeightField& f = *s.field;
    low = Eigen::Vector3d(-f.half_x, -f.half_y, -f.base);
    high = Eigen::Vector3d(f.half_x, f.half_y, *std::max_element(f.heights.begin(), f.heights.end()));
  }
  solid.type = ShapeType::box;
  solid.position += solid.orientation * (0.5 * (low + high));
  solid.size = 0.5 * (high - low);
  return solid;
}

}  // namespace

Recording::Recording(const Mechanism& original, const ShatterResult& shattered, const RecordOptions& options)
    : options_(options) {
  const Mechanism& m = shattered.mechanism;
  assert(shattered.shards.size() == original.bodies.size());
  assert(m.constraints.size() >= original.constraints.size());
  name_ = original.name;
  gravity_ = m.gravity;
  timestep_ = m.timestep;
  size_ = mechanism_size(m);
  period_ = 1 / options_.frame_rate;
  for (const RigidBody& b : m.bodies) static_.push_back(b.is_static ? 1 : 0);
  for (size_t i = 0; i < original.bodies.size(); ++i) {
    const RigidBody& body = original.bodies[i];
    const std::vector<int>& shards = shattered.shards[i];
    groups_.push_back(body.name);
    const int group = static_cast<int>(i);
    if (!body.shapes.empty()) {
      // The body's shapes on its first shard, which has the body's orientation and sits off its
      // centre of mass by `offset` (body frame).
      const RigidBody& first = m.bodies[shards.front()];
      const Eigen::Vector3d offset = body.orientation.conjugate() * (first.position - body.position);
      for (const Shape& s : body.shapes) {
        Solid solid{shards.front(), group, s.type, s.position - offset, s.orientation, Eigen::Vector3d::Zero(), false};
        switch (s.type) {
          case ShapeType::plane: solid.size = s.normal.normalized(); break;
          case ShapeType::sphere: solid.size = {s.radius, 0, 0}; break;
          case ShapeType::capsule: solid.size = {s.radius, s.half_length, 0}; break;
          case ShapeType::box:
          case ShapeType::ellipsoid: solid.size = s.half_extents; break;
          case ShapeType::cylinder: solid.size = {s.radius, s.half_length, 0}; break;
          case ShapeType::convex:
          case ShapeType::heightfield: solid = bounding_box(solid, s); break;
        }
        solids_.push_back(solid);
      }
    } else if (!body.is_static) {  // a static body without shapes is the world: nothing to draw
      for (int shard : shards) {
        const RigidBody& b = m.bodies[shard];
        solids_.push_back({shard, group, ShapeType::box, Eigen::Vector3d::Zero(), Eigen::Quaterniond::Identity(),
                           box_from_inertia(b.mass, b.inertia), true});
      }
    }
  }
  // The scene's own constraints (shattering appends its welds after them).
  for (size_t k = 0; k < original.constraints.size(); ++k) {
    const Constraint& c = m.constraints[k];
    joints_.push_back({c.type, c.body_a, c.body_b, c.anchor_a, c.anchor_b, c.frame_a.col(2)});
  }
  // Frame 0: the initial pose, no contacts yet.
  time_.push_back(0);
  push_poses(m);
  separation_.push_back(0);
  penetration_.push_back(0);
  contact_start_.push_back(0);
}

Recording::Recording(const Simulation& sim, const RecordOptions& options)
    : Recording(sim.mechanism(), unshattered(sim.mechanism()), options) {
  last_time_ = sim.time();
  time_[0] = static_cast<float>(sim.time());
}

void Recording::add(const Simulation& sim, const StepReport& report) {
  ++steps_;
  // (a NaN error, a blow-up, stays NaN until the frame: std::max(NaN, x) is NaN)
  const float separation = static_cast<float>(report.error.position_max);
  pending_separation_ = std::isnan(separation) ? NAN : std::max(pending_separation_, separation);
  pending_penetration_ = std::max(pending_penetration_, static_cast<float>(report.penetration_max_m));
  // (1e-9: a period that is a multiple of the timestep is not missed by rounding)
  if (sim.time() - last_time_ >= period_ * (1 - 1e-9)) take_frame(sim);
}

void Recording::finish(const Simulation& sim) {
  if (static_cast<float>(sim.time()) != time_.back()) take_frame(sim);
}

void Recording::push_poses(const Mechanism& m) {
  for (const RigidBody& b : m.bodies) {
    for (int d = 0; d < 3; ++d) positions_.push_back(static_cast<float>(b.position[d]));
    const Eigen::Quaterniond& q = b.orientation;
    for (double x : {q.w(), q.x(), q.y(), q.z()}) orientations_.push_back(quantized(x));
  }
}

void Recording::take_frame(const Simulation& sim) {
  const Mechanism& m = sim.mechanism();
  assert(m.bodies.size() == static_.size());
  last_time_ = sim.time();
  time_.push_back(static_cast<float>(sim.time()));
  push_poses(m);
  for (const Contact& c : sim.contacts()) {
    // The impulse on body b: normal along n (a to b), friction along t1, t2, a frame fixed in a,
    // taken where the step used it: turned back from a's pose now onto the detected normal (a
    // wheel turns by w dt in the step; the shortest turn undoes a turn about an axis across n).
    Eigen::Matrix3d frame = m.bodies[c.body_a].orientation * c.frame_a;
    frame = Eigen::Quaterniond::FromTwoVectors(frame.col(2), c.point.normal) * frame;
    // (against a static body, the impulse on a: the push of the ground, not into it)
    const double sign = m.bodies[c.body_b].is_static ? -1 : 1;
    const Eigen::Vector3d impulse =
        sign * (frame.col(2) * c.impulse[0] + frame.col(0) * c.impulse[1] + frame.col(1) * c.impulse[2]);
    for (int d = 0; d < 3; ++d) contacts_.push_back(static_cast<float>(c.point.position[d]));
    for (int d = 0; d < 3; ++d) contacts_.push_back(static_cast<float>(impulse[d]));
  }
  contact_start_.push_back(static_cast<uint32_t>(contacts_.size() / 6));
  separation_.push_back(pending_separation_);
  penetration_.push_back(pending_penetration_);
  pending_separation_ = pending_penetration_ = 0;
  if (frames() > options_.max_frames) halve();
}

void Recording::halve() {
  const size_t n = static_cast<size_t>(bodies());
  std::vector<float> contacts;
  std::vector<uint32_t> start{0};
  size_t kept = 0;
  for (size_t f = 0; f < time_.size(); f += 2, ++kept) {
    // frame f stands for (f - 2, f]: it keeps the larger separation of the dropped frame f - 1
    if (f > 0) {
      separation_[kept] = std::max(separation_[f - 1], separation_[f]);
      if (std::isnan(separation_[f - 1]) || std::isnan(separation_[f])) separation_[kept] = NAN;
      penetration_[kept] = std::max(penetration_[f - 1], penetration_[f]);
    }
    time_[kept] = time_[f];
    std::copy_n(positions_.begin() + static_cast<std::ptrdiff_t>(3 * n * f), 3 * n,
                positions_.begin() + static_cast<std::ptrdiff_t>(3 * n * kept));
    std::copy_n(orientations_.begin() + static_cast<std::ptrdiff_t>(4 * n * f), 4 * n,
                orientations_.begin() + static_cast<std::ptrdiff_t>(4 * n * kept));
    contacts.insert(contacts.end(), contacts_.begin() + 6 * contact_start_[f], contacts_.begin() + 6 * contact_start_[f + 1]);
    start.push_back(static_cast<uint32_t>(contacts.size() / 6));
  }
  if (time_.size() % 2 == 0) {  // the last frame is dropped: its maxima go to the next one
    const float last = separation_[time_.size() - 1];
    pending_separation_ = std::isnan(last) ? NAN : std::max(pending_separation_, last);
    pending_penetration_ = std::max(pending_penetration_, penetration_[time_.size() - 1]);
  }
  time_.resize(kept);
  separation_.resize(kept);
  penetration_.resize(kept);
  positions_.resize(3 * n * kept);
  orientations_.resize(4 * n * kept);
  contacts_ = std::move(contacts);
  contact_start_ = std::move(start);
  // The next frame is due a period (now twice as long) after the last one kept.
  last_time_ = time_.back();
  period_ *= 2;
}

}  // namespace ldlpgs::view
