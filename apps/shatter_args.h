#pragma once
// The shattering options that spy, step and export share: --shatter T (bodies of more than T
// constraint rows are candidates; the number of shards chosen by the flops the ordering
// predicts), --shards K (every candidate in K shards instead) and --no-shatter
// (physics/shatter.h). Shattering is on by default: it is part of the talk's symbolic phase,
// and shatter() leaves a mechanism whole unless splitting lowers the flops.
#include <string>

#include <CLI/CLI.hpp>

#include "ldlpgs/physics/shatter.h"

namespace ldlpgs::cli {

struct ShatterArgs {
  int threshold = ShatterOptions{}.threshold;
  int shards = 0;  // 0: shatter() chooses by flops
  bool none = false;
};

void add_shatter_options(CLI::App* cmd, ShatterArgs* args);

// Validates the options (InputError) and shatters `m` as they say; with --no-shatter the result
// holds `m` itself, each body its own single shard. `ordering` chooses the number of shards.
ShatterResult shatter_as_told(const Mechanism& m, const ShatterArgs& args, const std::string& ordering);

}  // namespace ldlpgs::cli
