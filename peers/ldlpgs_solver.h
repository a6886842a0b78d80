#pragma once
// ldlpgs's block LDL^T behind the competitors' interface (competitors.h), so that benchmarks and
// `ldlpgs bench` time every solver with the same loop. The symbolic phase runs in the
// constructor, outside any timed loop, as the competitors' analyses do.
#include <string>
#include <string_view>

#include "peers/competitors.h"
#include "ldlpgs/factor/numeric.h"

namespace ldlpgs {

class LdlpgsSolver final : public DirectSolver {
 public:
  LdlpgsSolver(const SymmetricCsc& a, const BlockPattern& blocks, const Ordering& ordering,
               const SymbolicOptions& options = {})
      : a_(a), symbolic_(Symbolic::analyze(a, blocks, ordering, options)), numeric_(symbolic_) {}
  LdlpgsSolver(const LdlpgsSolver&) = delete;  // numeric_ points at symbolic_
  LdlpgsSolver& operator=(const LdlpgsSolver&) = delete;

  std::string_view name() const override { return "ldlpgs"; }
  bool factor() override { return numeric_.factorize(a_).usable(); }
  std::string failure() const override { return numeric_.info().usable() ? "" : numeric_.info().message(); }
  void solve(std::span<double> b) override { numeric_.solve(b); }
  const Symbolic& symbolic() const { return symbolic_; }
  const FactorInfo& info() const { return numeric_.info(); }

 private:
  SymmetricCsc a_;
  Symbolic symbolic_;
  Numeric numeric_;
};

}  // namespace ldlpgs
