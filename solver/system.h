#pragma once
// The impulse problem of one step, in rows (the talk's "velocity step"): find lambda with
//   (H + diag(eps_i H_ii)) lambda = R on equality rows,  H = J W J^T,
// and lambda_i in [lower_i, upper_i] with complementarity on bounded rows, where
// R = target - J (V0 + W F dt) and the velocity change is dV = W J^T lambda.
// The solver sees rows, blocks and bounds only: columns come in velocity blocks of 6 (a rigid
// body's v and w, but the solver does not know that) and W is block diagonal over them.
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

namespace ldlpgs {

constexpr int kVelocityBlock = 6;  // columns per velocity block
constexpr double kUnbounded = std::numeric_limits<double>::infinity();

// One constraint: `size` rows from `position`, coupling velocity blocks column_a and column_b
// (-1: none, e.g. a static body). Its Jacobian cells are two size x 6 row-major matrices, a then
// b, at `offset` in System::jacobian (a missing column's cell is stored and ignored).
struct RowBlock {
  int size = 0;
  int position = 0;
  int column_a = -1, column_b = -1;
  int64_t offset = 0;
  bool equality = true;  // every row unbounded: part of the LDL block in ldl-pgs
  // Friction: the block's rows (one or two tangents) are bounded together by friction times the
  // impulse of row `friction_row` (a contact's normal row): |lambda_block| <= mu lambda_n, a disk,
  // or each row in [-mu lambda_n, mu lambda_n] with friction_pyramid. -1: the bounds are lower/upper.
  int friction_row = -1;
  double friction = 0;
  bool friction_pyramid = false;
  // ldl-pgs: a bounded block whose rows join the LDL block, solved exactly with the equalities and
  // then projected onto their bounds (contacts in the factor: papers/physics.md, "Contacts").
  bool factored = false;
  // A relative diagonal that regularizes the steps on these rows without changing their solution
  // (a proximal point step: (H + r diag(H)) dlambda = R - H lambda, so the fixed point solves
  // H lambda = R exactly), unlike the compliance, which softens the rows. Factored contacts take
  // it: a manifold's points are redundant and H singular on them.
  double regularization = 0;
  bool in_factor() const { return equality || factored; }
};

struct System {
  int num_columns = 0;                // velocity blocks
  int num_rows = 0;
  std::vector<RowBlock> blocks;       // (size num_blocks), rows in block order
  std::vector<double> jacobian;       // cells (size 12 * num_rows)
  std::vector<double> inverse_mass;   // W: one 6x6 row-major symmetric block per column block (size 36 * num_columns)
  std::vector<double> lower, upper;   // bounds on lambda per row (size num_rows); equality rows +-kUnbounded
  std::vector<double> rhs;            // R per row (size num_rows)
  // The talk's compliance, scaled per row: eps_i (size num_rows); the solvers work on
  // H + diag(eps_i H_ii). 0 is a rigid row.
  std::vector<double> compliance;

  // Appends a block of `size` rows; returns its index. Its cells, bounds and rhs start at zero
  // and unbounded.
  int add_block(int size, int column_a, int column_b);
  double* cell_a(int block) { return jacobian.data() + blocks[block].offset; }
  double* cell_b(int block) { return cell_a(block) + 6 * blocks[block].size; }
  const double* cell_a(int block) const { return jacobian.data() + blocks[block].offset; }
  const double* cell_b(int block) const { return cell_a(block) + 6 * blocks[block].size; }
  // eps_i = eps on every row.
  void set_compliance(double eps) { compliance.assign(num_rows, eps); }
  // Marks a block as bounded on all its rows (an inequality).
  void set_bounds(int block, double lower_bound, double upper_bound);
  // Marks a block as friction rows bounded by mu times row `normal_row`'s impulse (RowBlock).
  void set_friction(int block, int normal_row, double mu, bool pyramid = false);
  // Drops the blocks from `num_blocks` on (a step's contacts), keeping the storage.
  void truncate(int num_blocks);
  // Same blocks, columns and bounds kinds (the structure a solver's symbolic phase depends on).
  bool same_structure(const System& other) const;
};

// H_ii = J_i W J_i^T of row r of block k.
double row_diagonal(const System& system, int block, int row);

// y = J x (x: num_columns * 6, y: num_rows) and x += W J^T lambda.
void multiply_jacobian(const System& system, std::span<const double> x, std::span<double> y);
void add_velocity_change(const System& system, std::span<const double> lambda, std::span<double> dv);

}  // namespace ldlpgs
