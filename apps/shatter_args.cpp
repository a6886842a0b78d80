// The shattering options of spy, step and export (apps/shatter_args.h).
#include "apps/shatter_args.h"

#include <limits>

#include "apps/options.h"
#include "ldlpgs/sparse/error.h"

namespace ldlpgs::cli {

void add_shatter_options(CLI::App* cmd, ShatterArgs* a) {
  CLI::Option* threshold = cmd->add_option("--shatter", a->threshold,
                                           "Shatter bodies of more constraint rows than this (physics/shatter.h); "
                                           "the number of shards is chosen by flops")
                                 ->capture_default_str()
                                 ->check(integer_in(1, std::numeric_limits<int>::max()));
  CLI::Option* shards = cmd->add_option("--shards", a->shards, "Split each of those bodies into this many shards "
                                        "instead (2..64)")
                             ->check(integer_in(2, kMaxShards));
  cmd->add_flag("--no-shatter", a->none, "Keep the mechanism whole")->excludes(threshold)->excludes(shards);
}

ShatterResult shatter_as_told(const Mechanism& m, const ShatterArgs& a, const std::string& ordering) {
  if (!a.none && a.threshold < 1) throw InputError("--shatter must be at least 1 (rows)");
  if (a.shards != 0 && (a.shards < 2 || a.shards > kMaxShards))
    throw InputError("--shards must be in 2.." + std::to_string(kMaxShards));
  ShatterOptions options{.threshold = a.none ? std::numeric_limits<int>::max() : a.threshold,
                         .ordering = ordering,
                         .shards = a.shards};
  return shatter(m, options);
}

}  // namespace ldlpgs::cli
