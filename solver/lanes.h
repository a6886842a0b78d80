#pragma once
// Internal to solver/: contact points swept four at a time. A sweep row by row waits, on every
// row, for the dV the row before it wrote (papers/physics.md, "The sweeps' latency"). Here the
// manifolds (runs of points on one pair of velocity blocks) are coloured so that no two of a
// colour share a block, dealt four to a group, and a group's four manifolds are swept side by
// side in the lanes of one vector: the graph colouring and wide contact solver of Box2D v3
// (papers/physics.md, "Contact points in lanes").
#include <memory>
#include <span>
#include <type_traits>
#include <utility>
#include <vector>

#include "ldlpgs/solver/system.h"

namespace ldlpgs {

struct RowCache;

// std::allocator, but growing a vector leaves its new elements default-initialized: update writes
// every field of every slot, and value-initializing (zeroing) 3 KB slots first took 40 % of its
// time (perf annotate on the pyramid).
template <class T>
struct DefaultInitAllocator : std::allocator<T> {
  template <class U>
  struct rebind {
    using other = DefaultInitAllocator<U>;
  };
  template <class U>
  void construct(U* p) noexcept(std::is_nothrow_default_constructible_v<U>) {
    ::new (static_cast<void*>(p)) U;
  }
  template <class U, class... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
};

// A contact point is a one-row block bounded on its own (the normal row) followed by a two-row
// friction disk bounded by it, on the same columns, neither in the factor.
bool contact_point_at(const System& system, int k);

struct ContactLanes {
  static constexpr int kLanes = 4;
  // One point of each lane's manifold: its normal row (r = 0) and two friction rows (1, 2).
  struct Slot {
    double j[3][12][kLanes];    // J: columns a (0-5) then b (6-11), lanes innermost
    double wjt[3][12][kLanes];  // W J^T likewise
    double diag[3][kLanes];     // H_ii
    double k12[kLanes];         // J_1 W J_2^T, the friction block's coupling
    int normal_block[kLanes];   // the normal row's block (its friction block follows); -1: padding
    int row[3][kLanes];         // the rows' indices in lambda; -1: padding
    // What a solve holds constant (load): the normal row's bounds and 1 / ((1 + eps + reg) H_ii)
    // (0 and unbounded where H_ii = 0: the row keeps its impulse), the rows' R and eps H_ii, mu,
    // and the friction block's K = N + E diag(N) with 1 / det K.
    double lower[kLanes], upper[kLanes], inverse_n[kLanes];
    double rhs[3][kLanes], eps_diag[3][kLanes];
    double mu[kLanes], k11[kLanes], k22[kLanes], inverse_det[kLanes];
  };
  struct Group {
    int first_slot = 0, slots = 0;  // the longest of its manifolds
    int column[2][kLanes];          // a and b per lane; -1: a static body or a padding lane
  };
  std::vector<int> scalar_blocks;  // every block not in a group, in order: swept first, row by row
  std::vector<Group> groups;       // colour by colour
  std::vector<Slot, DefaultInitAllocator<Slot>> slots;

  // From the blocks and the cache's W J^T and H_ii. Allocates only when the system outgrows it.
  void update(const System& system, const RowCache& rows);
  // The system's right-hand sides, bounds, compliances, regularizations and friction coefficients
  // into the slots, before a solve's sweeps (Solver::resolve): they may change without a new J
  // (a position level).
  void load(const System& system);
  // The blocks in the order a sweep takes them (the scalar ones, then each group's lanes point by
  // point): the order in which a row-by-row sweep gives the same result.
  void sweep_order(std::vector<int>* blocks) const;

 private:
  struct Manifold {
    int first_block, points, colour;
  };
  void find_manifolds(const System& system);
  int colour_manifolds(const System& system);
  void deal_colour(const System& system, const RowCache& rows, int colour);
  std::vector<Manifold> manifolds_;
  std::vector<unsigned long long> colours_of_column_;
  std::vector<int> by_colour_;
};

// The groups' part of a sweep: pgs_sweep and block_gs_sweep step scalar_blocks first (every
// block, in order, where the system has no contact points), each its own way.
void sweep_lane_groups(const System& system, const RowCache& rows, std::span<double> lambda, std::span<double> dv);

}  // namespace ldlpgs
