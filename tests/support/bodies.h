#pragma once
// Bodies and mechanisms the physics tests build by hand: a static ground, a dynamic body at rest,
// numbered names.
#include <Eigen/Dense>
#include <string>

#include "ldlpgs/physics/mechanism.h"

namespace ldlpgs::testing {

// "link3": built by appending (GCC 12 warns falsely on "literal" + std::string at -O3).
inline std::string numbered(const char* prefix, int i) {
  std::string name = prefix;
  name += std::to_string(i);
  return name;
}

// A static body (infinite mass, never moves) at `position`.
inline RigidBody static_body(const std::string& name, const Eigen::Vector3d& position = Eigen::Vector3d::Zero()) {
  RigidBody b;
  b.name = name;
  b.is_static = true;
  b.position = position;
  return b;
}

// A dynamic body at rest, unrotated: mass (kg), principal moments (kg m^2) and centre of mass.
inline RigidBody dynamic_body(const std::string& name, double mass, const Eigen::Vector3d& inertia,
                              const Eigen::Vector3d& position) {
  RigidBody b;
  b.name = name;
  b.mass = mass;
  b.inertia = inertia;
  b.position = position;
  return b;
}

// A mechanism named `name` whose body 0 is a static "ground" at the origin.
inline Mechanism grounded(const std::string& name) {
  Mechanism m;
  m.name = name;
  m.add_body(static_body("ground"));
  return m;
}

}  // namespace ldlpgs::testing
