#pragma once
// Body shattering (the talk): a body carrying many constraints makes a dense block of H, since
// every pair of its constraints shares it. Shattering splits such a body into k equal shards
// joined in a chain by welds and spreads its constraints over them: H grows by the welds' rows
// but loses the dense block. The motion does not change (welds are rigid): the shards together
// have the body's mass, centre of mass and inertia tensor.
//
// Part of the symbolic phase: k is chosen by the flops the ordering predicts for the block
// LDL^T of H_0 (ordering/metrics.h), trying several, including not shattering at all.
#include <string>
#include <vector>

#include "ldlpgs/physics/mechanism.h"

namespace ldlpgs {

struct ShatterOptions {
  int threshold = 20;             // candidates: total constraint degree (rows) above this
  // The ordering whose block flops choose k: best, as everywhere (under a millisecond per
  // candidate k on the talk's mechanisms). The programs pass their --ordering.
  std::string ordering = "best";
  int shards = 0;                 // 0: k chosen by flops; 2..kMaxShards: every candidate in k shards
};

inline constexpr int kMaxShards = 64;

struct ShatterResult {
  Mechanism mechanism;                    // shattered (a copy of the input if nothing was)
  // shards[b] = the bodies of `mechanism` that original body b became, in chain order (size
  // original bodies; a single index for a body left whole)
  std::vector<std::vector<int>> shards;
  int shattered_bodies = 0;               // bodies split
  int welds = 0;                          // weld constraints added
  double flops_before = 0, flops_after = 0;  // block LDL^T flops of H_0, unshattered and chosen
  // Every candidate tried: shard degree target (0 = not shattered; -k: options.shards = k) and
  // its flops.
  std::vector<std::pair<int, double>> tried;
};

// Splits body `body` (dynamic) into k >= 2 shards along its principal axis of least inertia,
// joined by k - 1 welds; its constraints are spread over the shards so that each carries about
// the same degree (rows, welds included). shard_indices receives the k bodies in chain order.
Mechanism shatter_body(const Mechanism& mechanism, int body, int k, std::vector<int>* shard_indices);

// Shatters every body whose degree exceeds the threshold into ceil(degree / t) shards, for the
// target degree t among several candidates (and no shattering) that gives the fewest flops; or,
// with options.shards = k, into k shards each.
ShatterResult shatter(const Mechanism& mechanism, const ShatterOptions& options = {});

// The original body as its shards move: centre of mass and momentum of the shards, orientation
// of the first shard (welds keep them equal), mass and inertia of the original.
RigidBody whole_body(const Mechanism& shattered, const std::vector<int>& shards, const RigidBody& original);

}  // namespace ldlpgs
