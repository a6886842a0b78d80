#include "ldlpgs/sparse/mechanism_matrix.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cassert>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

namespace ldlpgs {

namespace {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using Mat6 = Eigen::Matrix<double, 6, 6>;
// The rows of one joint on one body: k x 6, k <= 6.
using BodyJacobian = Eigen::Matrix<double, Eigen::Dynamic, 6, Eigen::RowMajor, 6, 6>;

// Draws from the raw 32-bit outputs of mt19937 (which the standard fixes), not through
// std::uniform_real_distribution (whose algorithm each library chooses): the same seed gives
// the same values on every platform.
class Draw {
 public:
  explicit Draw(uint32_t seed) : rng_(seed) {}
  double uniform(double lo, double hi) { return lo + (hi - lo) * (rng_() * 0x1p-32); }
  // A uniformly distributed rotation: Shoemake's unit quaternion from three uniforms.
  Mat3 rotation() {
    const double u1 = uniform(0, 1), a = 2 * std::numbers::pi * uniform(0, 1),
                 b = 2 * std::numbers::pi * uniform(0, 1);
    const double s = std::sqrt(1 - u1), t = std::sqrt(u1);
    return Eigen::Quaterniond(t * std::cos(b), s * std::sin(a), s * std::cos(a), t * std::sin(b))
        .toRotationMatrix();
  }
  // A point uniformly on the sphere of the given radius (Archimedes: z is uniform).
  Vec3 on_sphere(double radius) {
    const double z = uniform(-1, 1), phi = 2 * std::numbers::pi * uniform(0, 1);
    const double rho = std::sqrt(1 - z * z);
    return radius * Vec3(rho * std::cos(phi), rho * std::sin(phi), z);
  }

 private:
  std::mt19937 rng_;
};

// W_b = blockdiag(I3 / m, R diag(1/I) R^T): the inverse mass of a body in world coordinates.
Mat6 inverse_mass(Draw& draw) {
  const double m = draw.uniform(0.5, 2);
  const Vec3 inertia(draw.uniform(0.05, 0.5), draw.uniform(0.05, 0.5), draw.uniform(0.05, 0.5));
  const Mat3 r = draw.rotation();
  Mat6 w = Mat6::Zero();
  w.topLeftCorner<3, 3>() = Mat3::Identity() / m;
  w.bottomRightCorner<3, 3>() = r * inertia.cwiseInverse().asDiagonal() * r.transpose();
  return w;
}

// The rows of a rigid-body joint. A translational row keeps the anchors' relative velocity
// along u at zero: u . (v_a + w_a x r_a - v_b - w_b x r_b), and u . (w x r) = w . (r x u). A
// rotational row keeps the relative angular velocity along u at zero: u . (w_a - w_b).
// Translational directions are the columns of one random rotation, rotational ones of another,
// so each kind is orthonormal and the rows are independent on either body.
void joint_jacobian(Draw& draw, int k, BodyJacobian& ja, BodyJacobian& jb) {
  assert(k >= 1 && k <= 6);
  const Mat3 translate = draw.rotation(), rotate = draw.rotation();
  const Vec3 ra = draw.on_sphere(draw.uniform(0.25, 0.75)),
             rb = draw.on_sphere(draw.uniform(0.25, 0.75));
  ja.setZero(k, 6);
  jb.setZero(k, 6);
  for (int i = 0; i < std::min(k, 3); ++i) {
    const Vec3 u = translate.col(i);
    ja.row(i) << u.transpose(), ra.cross(u).transpose();
    jb.row(i) << -u.transpose(), -rb.cross(u).transpose();
  }
  for (int i = 3; i < k; ++i) {
    const Vec3 u = rotate.col(i - 3);
    ja.row(i).tail<3>() = u;
    jb.row(i).tail<3>() = -u;
  }
}

}  // namespace

SymmetricCsc mechanism_matrix(const BodyGraph& mechanism, uint32_t seed, double regularization,
                              std::span<const double> mass_scale) {
  assert(regularization >= 0);
  assert(mass_scale.empty() || static_cast<int>(mass_scale.size()) == mechanism.num_bodies());
  Draw draw(seed);
  const int num_bodies = mechanism.num_bodies();
  const int m = static_cast<int>(mechanism.joints.size());
  // Inverse mass of each body, left unset for static ones (size num_bodies).
  std::vector<Mat6> w(num_bodies);
  for (int b = 0; b < num_bodies; ++b) {
    if (!mechanism.is_static[b]) w[b] = inverse_mass(draw);
    if (!mass_scale.empty()) w[b] /= mass_scale[b];
  }
  // The Jacobian by body: on_body[b] = the joints on dynamic body b, ascending, with their rows
  // on b (a joint from a body to itself has J_a + J_b there).
  struct Entry {
    int joint;
    BodyJacobian j;
  };
  std::vector<std::vector<Entry>> on_body(num_bodies);  // (size num_bodies)
  std::vector<int> position(m + 1, 0);                   // first row of each joint (size m+1)
  BodyJacobian ja, jb;
  for (int j = 0; j < m; ++j) {
    const BodyGraph::Joint& joint = mechanism.joints[j];
    position[j + 1] = position[j] + joint.rows;
    joint_jacobian(draw, joint.rows, ja, jb);
    for (auto [body, rows] : {std::pair{joint.body_a, &ja}, std::pair{joint.body_b, &jb}}) {
      if (mechanism.is_static[body]) continue;
      std::vector<Entry>& list = on_body[body];
      if (!list.empty() && list.back().joint == j) {
        list.back().j += *rows;
      } else {
        list.push_back({j, *rows});
      }
    }
  }
  // H = sum over dynamic bodies b of J_b W_b J_b^T: block (x, y) of H gets J_xb W_b J_yb^T for
  // every pair of joints x >= y on b, which are exactly the constraint graph's edges at b. Every
  // diagonal block is stored, even one of a joint between two static bodies (a zero block).
  // An entry sums at most two nonzero terms (a joint has two bodies), so the order in which
  // csc_from_triplets sums duplicates cannot change a bit.
  std::vector<Triplet> entries;
  for (int j = 0; j < m; ++j) {
    for (int c = position[j]; c < position[j + 1]; ++c) {
      for (int r = c; r < position[j + 1]; ++r) entries.push_back({r, c, 0.0});
    }
  }
  for (int b = 0; b < num_bodies; ++b) {
    const std::vector<Entry>& list = on_body[b];
    for (size_t y = 0; y < list.size(); ++y) {
      const Eigen::Matrix<double, 6, Eigen::Dynamic, 0, 6, 6> wjt = w[b] * list[y].j.transpose();
      for (size_t x = y; x < list.size(); ++x) {
        const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 6, 6> block =
            list[x].j * wjt;
        const int px = position[list[x].joint], py = position[list[y].joint];
        for (int c = 0; c < block.cols(); ++c) {
          for (int r = x == y ? c : 0; r < block.rows(); ++r) {
            entries.push_back({px + r, py + c, block(r, c)});
          }
        }
      }
    }
  }
  SymmetricCsc h = csc_from_triplets(position[m], entries);
  // Compliance eps * diag(H): the diagonal is first in each column (rows ascend from it).
  for (int c = 0; c < h.n; ++c) h.values[h.col_ptr[c]] += regularization * h.values[h.col_ptr[c]];
  return h;
}

}  // namespace ldlpgs
