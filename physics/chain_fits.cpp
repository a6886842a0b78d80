// One fit per joint chain and pose, shared by the constraints that carry it (chain_fits.h).
#include "ldlpgs/physics/chain_fits.h"

#include <cassert>

namespace ldlpgs {

namespace {

bool same_joint(const ChainJoint& x, const ChainJoint& y) {
  return x.type == y.type && x.axis == y.axis && x.anchor == y.anchor;
}

// The same chain between the same bodies: the same fit at every pose.
bool same_chain(const Constraint& x, const Constraint& y) {
  if (x.body_a != y.body_a || x.body_b != y.body_b) return false;
  if (x.chain == y.chain) return true;
  const JointChain &p = *x.chain, &q = *y.chain;
  if (p.joints.size() != q.joints.size()) return false;
  for (size_t k = 0; k < p.joints.size(); ++k)
    if (!same_joint(p.joints[k], q.joints[k])) return false;
  return p.rotation == q.rotation && p.translation == q.translation && p.parent_origin == q.parent_origin &&
         p.child_origin == q.child_origin;
}

std::array<double, 14> pose_key(const RigidBody& a, const RigidBody& b) {
  std::array<double, 14> key;
  int i = 0;
  for (const RigidBody* body : {&a, &b}) {
    for (int x = 0; x < 3; ++x) key[i++] = body->position[x];
    for (int x = 0; x < 4; ++x) key[i++] = body->orientation.coeffs()[x];
  }
  return key;
}

}  // namespace

ChainFits::ChainFits(const Mechanism& m)
    : constraint_slot_(m.constraints.size(), -1), dof_slot_(m.dofs.size(), -1) {
  // (linear in the chains per body pair, which are few: a body's one set and its copies)
  std::vector<const Constraint*> representative;
  const auto slot_of = [&](const Constraint& c) {
    for (size_t s = 0; s < representative.size(); ++s)
      if (same_chain(*representative[s], c)) return static_cast<int>(s);
    representative.push_back(&c);
    slots_.emplace_back();
    return static_cast<int>(slots_.size()) - 1;
  };
  for (size_t k = 0; k < m.constraints.size(); ++k) {
    if (!m.constraints[k].chain) continue;
    constraint_slot_[k] = slot_of(m.constraints[k]);
    slots_[constraint_slot_[k]].constraints.push_back(static_cast<int>(k));
  }
  for (size_t d = 0; d < m.dofs.size(); ++d) {
    if (!m.dofs[d].coordinate.chain) continue;
    dof_slot_[d] = slot_of(m.dofs[d].coordinate);
    slots_[dof_slot_[d]].dofs.push_back(static_cast<int>(d));
  }
}

const ChainFit& ChainFits::fit(const Mechanism& m, const Constraint& carrier, Slot* slot) {
  const RigidBody &a = m.bodies[carrier.body_a], &b = m.bodies[carrier.body_b];
  const std::array<double, 14> pose = pose_key(a, b);
  if (slot->fitted && pose == slot->pose) return slot->fit;
  ChainCoordinates q = slot->fitted ? slot->fit.q : carrier.coordinates;
  slot->fit = fit_chain(*carrier.chain, a, b, &q);
  slot->pose = pose;
  slot->fitted = true;
  for (const int k : slot->constraints) m.constraints[k].coordinates = q;
  for (const int d : slot->dofs) m.dofs[d].coordinate.coordinates = q;
  return slot->fit;
}

const ChainFit* ChainFits::constraint(const Mechanism& m, int k) {
  assert(constraint_slot_.size() == m.constraints.size());
  const int s = constraint_slot_[k];
  return s < 0 ? nullptr : &fit(m, m.constraints[k], &slots_[s]);
}

const ChainFit* ChainFits::dof(const Mechanism& m, int d) {
  assert(dof_slot_.size() == m.dofs.size());
  const int s = dof_slot_[d];
  return s < 0 ? nullptr : &fit(m, m.dofs[d].coordinate, &slots_[s]);
}

}  // namespace ldlpgs
