// Body shattering (the talk): a body carrying many constraints is split into a chain of welded
// shards, each carrying a share of the constraints, so that H loses the body's dense block.
//
// The shards are k bodies of mass m/k with the body's orientation q, centred at
// c_j = p + q (s_j e), s_j = spacing (j - (k-1)/2), e the body-frame principal axis of least
// inertia (the long axis). About the centre p their inertia tensor (body frame) is
//   sum_j [ I_j + (m/k) (s_j^2 Id - s_j^2 e e^T) ] = sum_j I_j + P (Id - e e^T),
//   P = (m/k) spacing^2 sum_j (j - (k-1)/2)^2 = m spacing^2 (k^2 - 1) / 12
// (the parallel-axis theorem; sum_j s_j = 0 keeps the centre at p). Shards of principal moments
// I_j = (I - P (Id - e e^T)) / k, diagonal in the same frame, give back exactly diag(I).
// P = min(I across e) / 2 keeps every I_j positive, and fixes the spacing, unless the chain would
// then reach beyond the body's farthest anchor: the spacing is then the shorter one and P follows
// from it (shatter_body: why).
//
// Every constraint on the body moves to one shard with its world anchors and axes unchanged
// (anchor_local -> anchor_local - s_j e in the shared orientation, frames as they were), so
// c, and J applied to the rigid velocity field the welds impose, are what they were.
//
// The body's constant load (applied force F through p, torque T) goes to the first shard alone,
// at its centre c_0: F through p is F through c_0 plus the couple (p - c_0) x F, so the shard
// carries F and T + (p - c_0) x F; the total force and the total moment about p are the body's.
// (Every shard a copy of the load would multiply it by k.)
#include "ldlpgs/physics/shatter.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <string>
#include <unordered_set>

#include "ldlpgs/ordering/metrics.h"
#include "ldlpgs/ordering/ordering.h"

namespace ldlpgs {

namespace {

// Constraint c's end on `body` moved onto shard `shard`, whose centre is `shift` from the body's
// (in the body's frame): its anchor, and its chain's frame (joint_set.h), follow.
void move_to_shard(Constraint* c, int body, int shard, const Eigen::Vector3d& shift) {
  const bool side_a = c->body_a == body;
  (side_a ? c->body_a : c->body_b) = shard;
  (side_a ? c->anchor_a : c->anchor_b) -= shift;
  if (c->chain) c->chain = shift_chain(*c->chain, side_a, shift);
}

// Shard targets the search tries: the degree (rows, welds included) a shard should carry.
constexpr int kTargetDegrees[] = {6, 10, 15, 20, 30, 40};
constexpr int kWeldRows = 6;

// Rows of all constraints touching each body (size bodies).
std::vector<int> body_degrees(const Mechanism& m) {
  std::vector<int> degree(m.bodies.size(), 0);
  for (const Constraint& c : m.constraints) {
    const int rows = num_rows(c);
    degree[c.body_a] += rows;
    degree[c.body_b] += rows;
  }
  return degree;
}

// Block LDL^T flops of H_0 (the equality constraints) under the named ordering; 0 when there
// are none. A scalar ordering may split blocks: its flops are those of the scalar LDL^T of the
// matrix with every block dense, which block_costs equals for a block ordering (metrics.h).
double equality_flops(const Mechanism& m, const OrderingInfo& info) {
  const BlockPattern pattern = m.constraint_graph(true);
  if (pattern.num_blocks() == 0) return 0;
  const SymmetricCsc a = pattern.expand();
  const Ordering o = compute_ordering(info, pattern, a);
  if (o.level == Level::block) return block_costs(pattern, o.pivots, o.elimination).flops;
  return scalar_counts(BlockPattern::unit(a).graph(), o.perm).flops;
}

// The world inertia tensor of bodies `ids` about their common centre of mass `centre`.
[[maybe_unused]] Eigen::Matrix3d inertia_about(const Mechanism& m, const std::vector<int>& ids,
                                               const Eigen::Vector3d& centre) {
  Eigen::Matrix3d total = Eigen::Matrix3d::Zero();
  for (int i : ids) {
    const RigidBody& b = m.bodies[i];
    const Eigen::Vector3d r = b.position - centre;
    total += b.inertia_world() + b.mass * (r.squaredNorm() * Eigen::Matrix3d::Identity() - r * r.transpose());
  }
  return total;
}

}  // namespace

// Long: the shattering in the talk's order (the axis, the spacing, the shards and their names, the
// constraints spread over them, the welds, the mass properties, the load), each step commented;
// the steps share the shard list and the axis.
Mechanism shatter_body(const Mechanism& mechanism, int body, int k, std::vector<int>* shard_indices) {
  assert(body >= 0 && body < static_cast<int>(mechanism.bodies.size()));
  assert(k >= 2);
  const RigidBody original = mechanism.bodies[body];
  assert(!original.is_static);

  // e: the axis of least inertia; P from the smaller of the two moments across it.
  int axis = 0;
  original.inertia.minCoeff(&axis);
  const Eigen::Vector3d e = Eigen::Vector3d::Unit(axis);
  double across = std::numeric_limits<double>::infinity();
  for (int i = 0; i < 3; ++i)
    if (i != axis) across = std::min(across, original.inertia[i]);
  // The spacing from P = min(I across e) / 2, but the chain no longer than the body's extent
  // along e as its constraints see it (twice the farthest anchor along e): a shard's position
  // carries rounding eps |c_j|, so the shards' mass-weighted centre (whole_body) and the welds'
  // lever arms (entries s in J, s^2 / I in H) lose eps s; where the body's radius of gyration
  // dwarfs its size (mass 1e-200, inertia 1: sqrt(I / m) = 1e100) the shards would be 1e100 m
  // apart and the body's position rounding. A shorter chain is still exact: P = m s^2 (k^2 - 1) / 12
  // below min(I across e) / 2 keeps every I_j positive, and I_j is computed from that P.
  double extent = 0;  // farthest anchor along e, body frame
  for (const Constraint& c : mechanism.constraints) {
    if (c.body_a == body) extent = std::max(extent, std::abs(c.anchor_a.dot(e)));
    if (c.body_b == body) extent = std::max(extent, std::abs(c.anchor_b.dot(e)));
  }
  const double k2 = static_cast<double>(k) * k - 1;
  const double spacing = std::min(std::sqrt(12 * (0.5 * across) / (original.mass * k2)), 2 * extent / (k - 1));
  const double parallel = original.mass * spacing * spacing * k2 / 12;  // P
  const Eigen::Vector3d shard_inertia = (original.inertia - parallel * (Eigen::Vector3d::Ones() - e)) / k;

  // Shard names "body#j", made unique against every other body's (a user's body named "hub#1"
  // would otherwise share a shard's name, and a scene written from the shattered mechanism be
  // refused for its duplicate names).
  std::unordered_set<std::string> taken;
  for (const RigidBody& b : mechanism.bodies) taken.insert(b.name);

  Mechanism m = mechanism;
  std::vector<int> ids(k);          // shard j -> body index (size k)
  std::vector<double> offset(k);    // s_j (size k)
  for (int j = 0; j < k; ++j) {
    offset[j] = spacing * (j - 0.5 * (k - 1));
    RigidBody shard = original;
    shard.name = original.name;
    shard.name += "#";
    shard.name += std::to_string(j);
    for (int n = 2; taken.contains(shard.name); ++n) {
      shard.name = original.name;
      shard.name += "#";
      shard.name += std::to_string(j);
      shard.name += "~";
      shard.name += std::to_string(n);
    }
    taken.insert(shard.name);
    shard.mass = original.mass / k;
    shard.inertia = shard_inertia;
    const Eigen::Vector3d r = original.orientation * (offset[j] * e);
    shard.position = original.position + r;
    // The rigid velocity field of the body, sampled at the shard's centre.
    shard.linear_velocity = original.linear_velocity + original.angular_velocity.cross(r);
    if (j == 0) {
      shard.applied_torque = original.applied_torque + (-r).cross(original.applied_force);  // (p - c_0) x F
    } else {
      shard.applied_force.setZero();
      shard.applied_torque.setZero();
    }
    if (j == 0) {
      ids[j] = body;
      m.bodies[body] = shard;
    } else {
      ids[j] = m.add_body(shard);
    }
  }

  // Degree of each shard: 6 rows per weld end, then the body's constraints spread greedily,
  // largest first (list scheduling), each on the least loaded shard, ties to the nearest shard.
  std::vector<int> degree(k, 0);  // (size k)
  for (int j = 0; j + 1 < k; ++j) {
    degree[j] += kWeldRows;
    degree[j + 1] += kWeldRows;
  }
  std::vector<int> on_body;  // constraints touching `body`, in decreasing rows, stable
  for (size_t c = 0; c < m.constraints.size(); ++c)
    if (m.constraints[c].body_a == body || m.constraints[c].body_b == body) on_body.push_back(static_cast<int>(c));
  std::stable_sort(on_body.begin(), on_body.end(), [&](int x, int y) {
    return num_rows(m.constraints[x]) > num_rows(m.constraints[y]);
  });
  for (int ci : on_body) {
    Constraint& c = m.constraints[ci];
    const Eigen::Vector3d& anchor = c.body_a == body ? c.anchor_a : c.anchor_b;
    int best = 0;
    double best_distance = std::numeric_limits<double>::infinity();
    for (int j = 0; j < k; ++j) {
      const double distance = (anchor - offset[j] * e).norm();
      if (degree[j] < degree[best] || (degree[j] == degree[best] && distance < best_distance)) {
        best = j;
        best_distance = distance;
      }
    }
    degree[best] += num_rows(c);
    move_to_shard(&c, body, ids[best], offset[best] * e);
  }
  // The dofs' coordinates (actuation.h) on the body are measured on its first shard: the shards
  // are welded, so any measures the same motion.
  for (DofDynamics& dof : m.dofs)
    if (dof.coordinate.body_a == body || dof.coordinate.body_b == body)
      move_to_shard(&dof.coordinate, body, ids[0], offset[0] * e);

  // Welds between consecutive shards at their midpoint (any axis: a weld removes all 6 dofs).
  const Eigen::Vector3d world_axis = original.orientation * e;
  for (int j = 0; j + 1 < k; ++j) {
    const RigidBody &a = m.bodies[ids[j]], &b = m.bodies[ids[j + 1]];
    m.add_constraint(
        make_axial(ConstraintType::weld, ids[j], a, ids[j + 1], b, 0.5 * (a.position + b.position), world_axis));
  }

#ifndef NDEBUG
  // The shards are the body: mass, centre of mass and inertia tensor about it.
  double mass = 0;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (int i : ids) {
    mass += m.bodies[i].mass;
    centre += m.bodies[i].mass * m.bodies[i].position;
  }
  centre /= mass;
  const double scale = original.inertia.maxCoeff();
  assert(std::abs(mass - original.mass) <= 1e-12 * original.mass);
  assert((centre - original.position).norm() <= 1e-12 * (1 + original.position.norm() + spacing * k));
  assert((inertia_about(m, ids, centre) - original.inertia_world()).norm() <= 1e-10 * scale);
  // and carry its load: total force, and total moment about its centre
  Eigen::Vector3d force = Eigen::Vector3d::Zero(), moment = Eigen::Vector3d::Zero();
  for (int i : ids) {
    const RigidBody& s = m.bodies[i];
    force += s.applied_force;
    moment += s.applied_torque + (s.position - original.position).cross(s.applied_force);
  }
  const double load = original.applied_force.norm() * (1 + spacing * k) + original.applied_torque.norm();
  assert((force - original.applied_force).norm() <= 1e-12 * (1 + load));
  assert((moment - original.applied_torque).norm() <= 1e-12 * (1 + load));
#endif
  if (shard_indices) *shard_indices = ids;
  return m;
}

namespace {

// Each candidate body split into its k_of shards (1: left whole).
ShatterResult shatter_each(const Mechanism& mechanism, const std::vector<int>& candidates, const std::vector<int>& k_of) {
  const int n = static_cast<int>(mechanism.bodies.size());
  ShatterResult r;
  r.mechanism = mechanism;
  r.shards.resize(n);
  for (int b = 0; b < n; ++b) r.shards[b] = {b};
  // One body at a time: each keeps its index for its first shard and appends the others, so
  // the indices of the bodies still to shatter stay valid.
  for (size_t i = 0; i < candidates.size(); ++i) {
    if (k_of[i] < 2) continue;
    r.mechanism = shatter_body(r.mechanism, candidates[i], k_of[i], &r.shards[candidates[i]]);
    ++r.shattered_bodies;
    r.welds += k_of[i] - 1;
  }
  return r;
}

}  // namespace

ShatterResult shatter(const Mechanism& mechanism, const ShatterOptions& options) {
  assert(options.shards == 0 || (options.shards >= 2 && options.shards <= kMaxShards));
  const OrderingInfo& info = find_ordering(options.ordering);
  const int n = static_cast<int>(mechanism.bodies.size());
  const std::vector<int> degree = body_degrees(mechanism);
  std::vector<int> candidates;
  for (int b = 0; b < n; ++b)
    if (!mechanism.bodies[b].is_static && degree[b] > options.threshold) candidates.push_back(b);

  const double flops_before = equality_flops(mechanism, info);
  if (options.shards) {
    ShatterResult r = shatter_each(mechanism, candidates, std::vector<int>(candidates.size(), options.shards));
    r.flops_before = flops_before;
    r.flops_after = equality_flops(r.mechanism, info);
    r.tried = {{0, flops_before}, {-options.shards, r.flops_after}};
    return r;
  }
  ShatterResult best = shatter_each(mechanism, {}, {});
  best.flops_before = best.flops_after = flops_before;
  best.tried.emplace_back(0, flops_before);
  for (int t : kTargetDegrees) {
    std::vector<int> k_of(candidates.size());  // shards per candidate (size candidates)
    bool any = false;
    for (size_t i = 0; i < candidates.size(); ++i) {
      k_of[i] = std::min(kMaxShards, (degree[candidates[i]] + t - 1) / t);
      any = any || k_of[i] >= 2;
    }
    if (!any) continue;
    ShatterResult r = shatter_each(mechanism, candidates, k_of);
    const double flops = equality_flops(r.mechanism, info);
    best.tried.emplace_back(t, flops);
    if (flops < best.flops_after) {
      r.tried = std::move(best.tried);
      r.flops_before = flops_before;
      r.flops_after = flops;
      best = std::move(r);
    }
  }
  return best;
}

RigidBody whole_body(const Mechanism& shattered, const std::vector<int>& shards, const RigidBody& original) {
  assert(!shards.empty());
  RigidBody whole = original;
  const RigidBody& first = shattered.bodies[shards.front()];
  double mass = 0;
  Eigen::Vector3d moment = Eigen::Vector3d::Zero(), momentum = Eigen::Vector3d::Zero();
  for (int i : shards) {
    const RigidBody& s = shattered.bodies[i];
    mass += s.mass;
    moment += s.mass * s.position;
    momentum += s.mass * s.linear_velocity;
  }
  // A massless body (MuJoCo's world, static) is never shattered: its one shard is itself, and
  // the mass-weighted means would be 0 / 0.
  const bool one = shards.size() == 1 || !(mass > 0);
  whole.position = one ? first.position : Eigen::Vector3d(moment / mass);
  whole.orientation = first.orientation;
  whole.linear_velocity = one ? first.linear_velocity : Eigen::Vector3d(momentum / original.mass);
  whole.angular_velocity = first.angular_velocity;
  return whole;
}

}  // namespace ldlpgs
