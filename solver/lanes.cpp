// The contact points' lanes: manifolds coloured and dealt four to a group (update), and the
// sweep that steps a group's four manifolds at once, a point of each per vector operation.
#include "ldlpgs/solver/lanes.h"

#include <algorithm>
#include <bit>
#include <cstring>

#include "ldlpgs/factor/numeric.h"
#include "ldlpgs/solver/row_cache.h"
#include "lanes_sweep.h"

namespace ldlpgs {

bool contact_point_at(const System& system, int k) {
  if (k + 1 >= static_cast<int>(system.blocks.size())) return false;
  const RowBlock &n = system.blocks[k], &f = system.blocks[k + 1];
  return n.size == 1 && !n.in_factor() && n.friction_row < 0 && f.size == 2 && f.friction_row == n.position &&
         !f.friction_pyramid && !f.in_factor() && f.column_a == n.column_a && f.column_b == n.column_b &&
         !(n.column_a >= 0 && n.column_a == n.column_b);
}

namespace {

constexpr int kLanes = ContactLanes::kLanes;

bool same_columns(const RowBlock& a, const RowBlock& b) {
  return a.column_a == b.column_a && a.column_b == b.column_b;
}

// Row r of a point (0: the normal block's row, 1-2: its friction block's) into lane l of slot s.
void fill_row(const System& system, const RowCache& rows, int block, int r, int row, int l, ContactLanes::Slot* s) {
  const double *ja = system.cell_a(block) + 6 * r, *jb = system.cell_b(block) + 6 * r;
  const double* w = rows.wjt.data() + 12 * static_cast<size_t>(system.blocks[block].position + r);
  for (int c = 0; c < 6; ++c) {
    s->j[row][c][l] = ja[c];
    s->j[row][6 + c][l] = jb[c];
  }
  for (int c = 0; c < 12; ++c) s->wjt[row][c][l] = w[c];
  s->diag[row][l] = rows.diag[system.blocks[block].position + r];
  s->row[row][l] = system.blocks[block].position + r;
}

void fill_point(const System& system, const RowCache& rows, int normal_block, int l, ContactLanes::Slot* s) {
  s->normal_block[l] = normal_block;
  fill_row(system, rows, normal_block, 0, 0, l, s);
  fill_row(system, rows, normal_block + 1, 0, 1, l, s);
  fill_row(system, rows, normal_block + 1, 1, 2, l, s);
  // (summed as pgs_friction_disk sums it; a missing column's W J^T is zero)
  const RowBlock& f = system.blocks[normal_block + 1];
  const double* w1 = rows.wjt.data() + 12 * static_cast<size_t>(f.position + 1);
  s->k12[l] = dot6(system.cell_a(normal_block + 1), w1) + dot6(system.cell_b(normal_block + 1), w1 + 6);
}

void clear_lane(int l, ContactLanes::Slot* s) {
  s->normal_block[l] = -1;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 12; ++c) s->j[r][c][l] = s->wjt[r][c][l] = 0;
    s->diag[r][l] = 0;
    s->row[r][l] = -1;
  }
  s->k12[l] = 0;
}

}  // namespace

void ContactLanes::update(const System& system, const RowCache& rows) {
  scalar_blocks.clear();
  groups.clear();
  slots.clear();
  // Each bounded by the blocks (a point is two), so that a step allocates only when its system
  // outgrows every earlier one, whatever the colouring.
  const int num_blocks = static_cast<int>(system.blocks.size());
  scalar_blocks.reserve(num_blocks);
  groups.reserve(num_blocks / 2);
  slots.reserve(num_blocks / 2);
  by_colour_.reserve(num_blocks / 2);
  manifolds_.reserve(num_blocks / 2);
  find_manifolds(system);
  const int colours = colour_manifolds(system);
  std::sort(scalar_blocks.begin(), scalar_blocks.end());
  for (int c = 0; c < colours; ++c) deal_colour(system, rows, c);
}

// The runs of contact points on one pair of columns; every other block to scalar_blocks.
void ContactLanes::find_manifolds(const System& system) {
  manifolds_.clear();
  const int num_blocks = static_cast<int>(system.blocks.size());
  for (int k = 0; k < num_blocks;) {
    if (!contact_point_at(system, k)) {
      scalar_blocks.push_back(k++);
      continue;
    }
    Manifold m{k, 0, -1};
    while (k < num_blocks && contact_point_at(system, k) && same_columns(system.blocks[k], system.blocks[m.first_block])) {
      ++m.points;
      k += 2;
    }
    manifolds_.push_back(m);
  }
}

// Greedy colouring: a manifold takes the first colour neither of its columns has; past 64
// colours it is swept row by row. Returns the number of colours.
int ContactLanes::colour_manifolds(const System& system) {
  colours_of_column_.assign(system.num_columns, 0);
  int colours = 0;
  for (Manifold& m : manifolds_) {
    const RowBlock& b = system.blocks[m.first_block];
    unsigned long long used = 0;
    if (b.column_a >= 0) used |= colours_of_column_[b.column_a];
    if (b.column_b >= 0) used |= colours_of_column_[b.column_b];
    if (~used == 0) {
      for (int k = m.first_block; k < m.first_block + 2 * m.points; ++k) scalar_blocks.push_back(k);
      continue;
    }
    m.colour = std::countr_one(used);
    if (b.column_a >= 0) colours_of_column_[b.column_a] |= 1ull << m.colour;
    if (b.column_b >= 0) colours_of_column_[b.column_b] |= 1ull << m.colour;
    colours = std::max(colours, m.colour + 1);
  }
  return colours;
}

// Colour c's manifolds, in block order, four to a group, its lanes' points into slots (a
// shorter manifold's lane padded).
void ContactLanes::deal_colour(const System& system, const RowCache& rows, int colour) {
  by_colour_.clear();
  for (int i = 0; i < static_cast<int>(manifolds_.size()); ++i)
    if (manifolds_[i].colour == colour) by_colour_.push_back(i);
  for (size_t first = 0; first < by_colour_.size(); first += kLanes) {
    const Manifold* lane[kLanes];
    Group g;
    g.first_slot = static_cast<int>(slots.size());
    for (int l = 0; l < kLanes; ++l) {
      lane[l] = first + l < by_colour_.size() ? &manifolds_[by_colour_[first + l]] : nullptr;
      g.slots = std::max(g.slots, lane[l] ? lane[l]->points : 0);
      g.column[0][l] = lane[l] ? system.blocks[lane[l]->first_block].column_a : -1;
      g.column[1][l] = lane[l] ? system.blocks[lane[l]->first_block].column_b : -1;
    }
    slots.resize(slots.size() + g.slots);
    for (int l = 0; l < kLanes; ++l)
      for (int p = 0; p < g.slots; ++p) {
        Slot* s = &slots[g.first_slot + p];
        if (lane[l] && p < lane[l]->points)
          fill_point(system, rows, lane[l]->first_block + 2 * p, l, s);
        else
          clear_lane(l, s);
      }
    groups.push_back(g);
  }
}

void ContactLanes::load(const System& system) {
  for (Slot& s : slots)
    for (int l = 0; l < kLanes; ++l) {
      const int k = s.normal_block[l];
      if (k < 0) {  // (a padding lane: zero steps)
        for (int r = 0; r < 3; ++r) s.rhs[r][l] = s.eps_diag[r][l] = 0;
        s.lower[l] = s.upper[l] = s.inverse_n[l] = s.mu[l] = s.k11[l] = s.k22[l] = s.inverse_det[l] = 0;
        continue;
      }
      const RowBlock &n = system.blocks[k], &f = system.blocks[k + 1];
      double eps[3];
      for (int r = 0; r < 3; ++r) {
        eps[r] = system.compliance[s.row[r][l]];
        s.rhs[r][l] = system.rhs[s.row[r][l]];
        s.eps_diag[r][l] = eps[r] * s.diag[r][l];
      }
      const double d = s.diag[0][l];
      const bool active = d > 0;  // (pgs_row skips a row with H_ii = 0)
      s.lower[l] = active ? system.lower[n.position] : -kUnbounded;
      s.upper[l] = active ? system.upper[n.position] : kUnbounded;
      s.inverse_n[l] = active ? 1 / ((1 + eps[0] + n.regularization) * d) : 0;
      s.mu[l] = f.friction;
      s.k11[l] = s.diag[1][l] * (1 + eps[1]);
      s.k22[l] = s.diag[2][l] * (1 + eps[2]);
      s.inverse_det[l] = 1 / (s.k11[l] * s.k22[l] - s.k12[l] * s.k12[l]);
    }
}

void ContactLanes::sweep_order(std::vector<int>* blocks) const {
  blocks->clear();
  for (int k : scalar_blocks) blocks->push_back(k);
  for (const Group& g : groups)
    for (int p = 0; p < g.slots; ++p)
      for (int l = 0; l < kLanes; ++l) {
        const int k = slots[g.first_slot + p].normal_block[l];
        if (k < 0) continue;
        blocks->push_back(k);
        blocks->push_back(k + 1);
      }
}

void sweep_lane_groups(const System& system, const RowCache& rows, std::span<double> lambda, std::span<double> dv) {
  const ContactLanes& lanes = rows.lanes;
  const lanes::SweepData data{lanes.groups.data(), static_cast<int>(lanes.groups.size()), lanes.slots.data(),
                              system.blocks.data(), system.compliance.data(), lambda.data(), dv.data()};
#ifdef LDLPGS_HAVE_AVX2_LANES
  if (kernels_use_avx2()) {  // (factor/'s choice of kernels: one dispatch for both libraries)
    lanes::sweep_groups_avx2(data);
    return;
  }
#endif
  lanes::sweep_groups_sse2(data);
}

}  // namespace ldlpgs
