#pragma once
// Each joint chain's fit (joint_set.h) at the bodies' current pose, computed once per pose however
// many constraints carry the chain (its set, its ranges, its dofs' rows and coordinates) and
// however often they are evaluated there (a step's rows, its joint dynamics, its diagnostics). A
// hip of three hinges with ranges and armature used to fit its chain ten times a step
// (papers/physics.md, "MJCF models").
//
// A slot's fit is current while the two bodies' poses are bit-identical to those it was fitted
// at, so nothing needs invalidating when a step, its projection or the API moves a body. Each fit
// starts from the slot's last coordinates, and leaves them in every constraint of the slot too, so
// that evaluations without the slots (constraint_error, build_system) continue from the same q.
#include <array>
#include <vector>

#include "ldlpgs/physics/mechanism.h"

namespace ldlpgs {

class ChainFits {
 public:
  ChainFits() = default;
  // One slot per distinct chain among the mechanism's constraints and dofs' coordinates: the
  // chains equal in content between the same two bodies (a set and its ranges, copied from one
  // another, also after body shattering moved them alike) share one.
  explicit ChainFits(const Mechanism& mechanism);
  // The fit of constraint k's chain (or dof d's coordinate's) at the bodies' current pose; null if
  // it carries no chain.
  const ChainFit* constraint(const Mechanism& mechanism, int k);
  const ChainFit* dof(const Mechanism& mechanism, int d);
  int chains() const { return static_cast<int>(slots_.size()); }  // distinct chains (slots)

 private:
  struct Slot {
    ChainFit fit;
    std::array<double, 14> pose{};  // a's then b's position and quaternion at the fit
    bool fitted = false;
    std::vector<int> constraints, dofs;  // those that carry the chain
  };
  const ChainFit& fit(const Mechanism& mechanism, const Constraint& carrier, Slot* slot);
  std::vector<int> constraint_slot_, dof_slot_;  // -1: no chain
  std::vector<Slot> slots_;
};

}  // namespace ldlpgs
