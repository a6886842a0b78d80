#pragma once
// Collision detection: the touching shapes of a mechanism's bodies as contact points. ODE's
// collision library does the narrow phase (dCollide's primitive pairs: up to 4 points per pair, a
// box on a plane gets its 4 corners; a cylinder's, hull's or heightfield's points are reduced to
// the 4 that span them), chosen by measurement against Bullet and libccd; ellipsoids, which ODE
// lacks, and pairs of shapes it cannot grow by a margin (hull on hull, hull on heightfield) go to
// libccd's MPR on support functions, one point per pair (per heightfield triangle). The broad
// phase is a sweep of ours, since ODE's spaces allocate on every pass (papers/physics.md,
// "Collision detection").
#include <memory>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "ldlpgs/physics/mechanism.h"

namespace ldlpgs {

// One point where two shapes touch or may touch within the step (a speculative contact). The
// normal points from body a into body b (moving b along it separates them); depth > 0 is the
// penetration (m), depth < 0 the gap. The points of a pair come together.
struct ContactPoint {
  int body_a = -1, body_b = -1;
  int shape_a = -1, shape_b = -1;  // indices into each body's shapes
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // world, between the two surfaces
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();   // world, unit
  double depth = 0;
};

inline constexpr int kMaxPointsPerPair = 4;

class CollisionWorld {
 public:
  // The geometry of every shape of `mechanism`, and the pairs of bodies that may not touch
  // (joined by a constraint without `collide`). Shapes are checked by the readers.
  explicit CollisionWorld(const Mechanism& mechanism);
  ~CollisionWorld();
  CollisionWorld(CollisionWorld&&) noexcept;
  CollisionWorld& operator=(CollisionWorld&&) noexcept;

  // The contact points at the bodies' current poses into `out` (cleared first; its storage is
  // reused, so a step allocates nothing once the largest count has been seen): the pairs that
  // touch, and those whose gap the two bodies can close in `horizon` (s): each dynamic body
  // reaches `margin` (m) plus what its points travel at its current velocities, a static one what
  // gravity's pull adds to a dynamic body's travel (speculative contacts, Catto's: a fast body is
  // stopped at the surface instead of being found inside it a step late). Gravity moves two
  // dynamic bodies alike, so resting neighbours a gap apart are no contact.
  void detect(const Mechanism& mechanism, double margin, double horizon, std::vector<ContactPoint>* out);
  bool empty() const;  // no shapes at all

  struct Geometry;  // ODE's space and geoms (collision.cpp)

 private:
  std::unique_ptr<Geometry> geometry_;
};

bool has_shapes(const Mechanism& mechanism);

}  // namespace ldlpgs
