#pragma once
// A mechanism: rigid bodies and the constraints between them (the talk's unit of the symbolic
// phase). Its body graph has bodies as nodes and constraints as edges; its constraint graph (the
// edge graph of the body graph) has constraints as nodes, weighted by their row counts, and an
// edge wherever two constraints share a dynamic body: it is the block graph of H = J W J^T.
// Static bodies couple nothing (W = 0 there).
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "ldlpgs/physics/body.h"
#include "ldlpgs/physics/constraint.h"
#include "ldlpgs/sparse/block_pattern.h"

namespace ldlpgs {

struct Mechanism {
  std::string name;
  Eigen::Vector3d gravity{0, -9.81, 0};  // m/s^2
  double timestep = 0.01;                // s
  std::vector<RigidBody> bodies;
  std::vector<Constraint> constraints;

  int find_body(std::string_view body_name) const;  // -1 if none has that name
  int add_body(RigidBody body);                      // returns its index
  int add_constraint(Constraint constraint);         // returns its index
  int num_rows() const;                              // sum of the constraints' rows
  int num_dynamic_bodies() const;
  // The first limit or rope (an inequality row: the direct solver does not take it), -1 if none.
  int first_inequality() const;

  // Blocks = constraints (sizes = their rows), adjacency = a shared dynamic body. `equality_only`
  // keeps only the equality constraints (the block ldl-pgs factors), renumbered in order.
  BlockPattern constraint_graph(bool equality_only = false) const;
  // Edges (body_a, body_b) of the body graph, one per constraint.
  std::vector<std::pair<int, int>> body_graph() const;
};

}  // namespace ldlpgs
