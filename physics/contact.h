#pragma once
// Contacts: the inequality rows of a step where two shapes touch. Each contact point gives a
// normal row, impulse >= 0, and two friction rows bounded by mu times the normal impulse (a disk,
// or the pyramid |lambda_t| <= mu lambda_n per row). Points are matched from one step to the
// next (same bodies and shapes, nearest anchor on body a within ContactOptions::match_distance
// along the contact plane) so that
// their impulses warm-start the solver.
#include <array>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "ldlpgs/physics/collision.h"
#include "ldlpgs/physics/constraint.h"
#include "ldlpgs/solver/solver.h"

namespace ldlpgs {

struct ContactOptions {
  // Penetration left in place (m): the position correction stops there, so that a resting
  // contact keeps touching and is found again next step (Box2D's linear slop).
  double slop = 0.005;
  // Speculative contacts: pairs closer than what their points travel in a step, plus this
  // distance (m) for each dynamic body, become contacts whose normal row lets the gap close and
  // no more (collision.h). 0: motion alone decides, so a resting neighbour a gap away costs no
  // rows (papers/physics.md, "Speculative margin").
  double margin = 0;
  // Velocity-level correction of the penetration beyond the slop, a fraction per step
  // (Baumgarte), at most max_correction_speed (m/s); the post-stabilization removes the rest
  // without adding velocity (papers/physics.md, "Contacts").
  double baumgarte = 0.2;
  double max_correction_speed = 1;
  // Restitution applies to approach speeds above this (m/s): slower contacts come to rest.
  double restitution_threshold = 1;
  bool friction_pyramid = false;  // the pyramid instead of the disk
  double match_distance = 0.02;   // m, between a point's anchors on body a in two steps
  // ldl-pgs: a contact pushing (positive normal impulse) for this many steps in a row joins the
  // LDL block with its normal row (RowBlock::factored); 0: never, the talk's schedule.
  int factor_after = 2;
  // ... also on a body that an equality constraint holds. Off: such a contact is often redundant
  // with the joints (a chain lying on the ground) and their targets disagree, so it stays a
  // projected row (papers/physics.md, "Contacts in the factor").
  bool factor_jointed = false;
  // ... and only where PGS is slow: a contact of a body that touches a dynamic body at least this
  // many times heavier than itself (the light box under a heavy one; PGS converges between
  // comparable masses, and a pyramid of equal boxes stands as well without the factorization's
  // cost). 0: every contact that qualifies above (papers/physics.md, "Contacts in the factor").
  double factor_mass_ratio = 10;
  // ldl-pgs's schedule on a step with contacts (SolverOptions::schedule on steps without):
  // alternating the exact block and the contact rows converges where the talk's single block
  // sweep lets them feed each other (papers/physics.md, "Schedules with contacts").
  HybridSchedule schedule = HybridSchedule::block_gs;
  // ... and the post-stabilization's, with at most this many iterations (LDL^T solves), stopping
  // once the correction no longer changes, on a step with contacts.
  int position_iterations = 100;
  // With the block-gs schedule: where those have not converged after position_schur_after
  // iterations, on a step with at most position_iterations contact points, the contact rows'
  // Schur complement takes over (HybridSchedule::schur: a solve per row, then PGS with each row's
  // effective mass through the joints). Block Gauss-Seidel converges slowly on contacts pressing
  // on jointed bodies (papers/physics.md, "Vehicles on the ground"). 0: never.
  int position_schur_after = 10;
  // On a mechanism with shapes the post-stabilization refactors at each corrected pose (Newton,
  // StepOptions::post_stabilize_refactor): with J_0 the projection of joints and contacts on the
  // same bodies converges slowly or not at all (papers/physics.md, "The heavy ball on a chain").
  bool refactor_projection = true;
  // On, on a mechanism with shapes: the free motion takes the gyroscopic term w x I w implicitly
  // (one Newton step on I (w' - w) + dt w' x I w' = 0 in the body frame, as Bullet does) and a
  // body's rotation keeps w. Off (and without shapes) the rotation keeps each body's angular
  // momentum, exact for a free body, but a link or a wheel spinning fast against its joints gains
  // energy that way. Off by default: on, MuJoCo's 22 humanoids lying on their floor leave 0.7 mm
  // of joint error a step for the projection (papers/physics.md, "The implicit gyroscopic term").
  bool implicit_gyroscopic = false;
  // A factored normal row's regularization and compliance (RowBlock::regularization, System::
  // compliance): a manifold's points are redundant (4 rows, 3 degrees of freedom), and so are
  // contacts and joints holding the same body, so H is singular on them; what the exact solve
  // puts in that null space, when a projection has left the right-hand side outside J's range,
  // is that part divided by the compliance. The compliance softens the contact (a velocity
  // error of eps H_ii lambda); the regularization damps each step without softening it
  // (papers/physics.md, "Contacts in the factor").
  double regularization = 1e-3;
  double compliance = 1e-6;
};

struct Contact {
  int body_a = -1, body_b = -1;  // the normal points from a to b
  int shape_a = -1, shape_b = -1;
  // The witness points in each body's frame: n . ((p_b + R_b anchor_b) - (p_a + R_a anchor_a))
  // is -depth at detection.
  Eigen::Vector3d anchor_a = Eigen::Vector3d::Zero(), anchor_b = Eigen::Vector3d::Zero();
  Eigen::Matrix3d frame_a = Eigen::Matrix3d::Identity();  // columns t1, t2, n in a's frame
  double friction = 0, restitution = 0;
  ContactPoint point;                   // as detected this step (world frame)
  std::array<double, 3> impulse{};      // normal, t1, t2 (N s): the last solve's
  int pushing_steps = 0;                // steps in a row with a positive normal impulse
  bool factored = false;                // its normal row is in the LDL block this step
  int point_index = -1;                 // its place among this step's detected points
};

// Contact rows at the current pose, three slide rows c = t . d along n, t1, t2 of a's frame,
// d = (p_b + r_b) - (p_a + r_a), r = R anchor:
//   c_n = n . d (the separation; >= 0 apart),   J = [-t, t x (d + r_a), t, r_b x t]
// (t turns with body a: dt/dt = w_a x t). The friction rows' c is the tangential drift, unused.
ConstraintRows evaluate(const Contact& contact, const RigidBody& a, const RigidBody& b);
// The normal row's c alone (evaluate(...).c[0], the same operations): the separation along n,
// negative when the witness points have passed each other.
double separation(const Contact& contact, const RigidBody& a, const RigidBody& b);
// Both with the bodies' rotation matrices given (body_rotations): one per body per pass over the
// contacts instead of two per contact.
ConstraintRows evaluate(const Contact& contact, const RigidBody& a, const Eigen::Matrix3d& ra, const RigidBody& b,
                        const Eigen::Matrix3d& rb);
double separation(const Contact& contact, const RigidBody& a, const Eigen::Matrix3d& ra, const RigidBody& b,
                  const Eigen::Matrix3d& rb);
// evaluate's three rows alone, into storage the step reuses: a ConstraintRows is value-initialized
// (640 bytes zeroed per contact, a quarter of evaluate's time on the pyramid; perf).
struct ContactRows {
  std::array<double, 3> c;
  std::array<double, 36> jacobian;  // 3 x 12, as ConstraintRows::jacobian
};
void evaluate(const Contact& contact, const RigidBody& a, const Eigen::Matrix3d& ra, const RigidBody& b,
              const Eigen::Matrix3d& rb, ContactRows* out);
// Every body's orientation as a rotation matrix (allocates only when the mechanism has grown).
void body_rotations(const Mechanism& mechanism, std::vector<Eigen::Matrix3d>* out);

// A contact's pair (bodies, then shapes) and its place in a list: what the matching sorts, so that
// it moves 20 bytes per contact rather than a Contact. The index breaks ties.
struct ContactKey {
  int body_a = -1, body_b = -1, shape_a = -1, shape_b = -1;
  int index = -1;
  bool same_pair(const ContactKey& o) const {
    return body_a == o.body_a && body_b == o.body_b && shape_a == o.shape_a && shape_b == o.shape_b;
  }
  friend bool operator<(const ContactKey& x, const ContactKey& y) {
    if (x.body_a != y.body_a) return x.body_a < y.body_a;
    if (x.body_b != y.body_b) return x.body_b < y.body_b;
    if (x.shape_a != y.shape_a) return x.shape_a < y.shape_a;
    if (x.shape_b != y.shape_b) return x.shape_b < y.shape_b;
    return x.index < y.index;  // (a total order: std::sort then gives one result)
  }
};

// This step's contacts from the detected points, matched against last step's (`previous`):
// a matched contact keeps its impulse (friction re-expressed in the new tangents) and its count
// of pushing steps. `rotations`: body_rotations of the mechanism; `keys` is scratch. Allocates
// nothing once the vectors have grown.
void make_contacts(const Mechanism& mechanism, std::span<const Eigen::Matrix3d> rotations,
                   std::span<const ContactPoint> points, std::span<const Contact> previous, double match_distance,
                   std::vector<ContactKey>* keys, std::vector<Contact>* out);

}  // namespace ldlpgs
