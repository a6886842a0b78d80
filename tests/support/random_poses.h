#pragma once
// Random poses and velocities for the physics tests (seeded std::mt19937: the same draws on
// every run).
#include <Eigen/Geometry>
#include <random>

namespace ldlpgs::testing {

// Uniform in [-scale, scale]^3.
inline Eigen::Vector3d random_vector(std::mt19937& rng, double scale) {
  std::uniform_real_distribution<double> u(-scale, scale);
  return Eigen::Vector3d(u(rng), u(rng), u(rng));
}

// Uniform on the unit quaternions (normalized 4-d Gaussian).
inline Eigen::Quaterniond random_rotation(std::mt19937& rng) {
  std::normal_distribution<double> g;
  return Eigen::Quaterniond(g(rng), g(rng), g(rng), g(rng)).normalized();
}

}  // namespace ldlpgs::testing
