// ldlpgs sweep: speed against error on the hard cases (apps/sweep.h), as Markdown tables and,
// with --json or --json-file FILE, the points papers/scripts/plot_speed_vs_error.py draws.
#include <fstream>
#include <limits>

#include "apps/commands.h"
#include "apps/options.h"
#include "apps/sweep.h"
#include "ldlpgs/sparse/error.h"

namespace ldlpgs::cli {

Command add_sweep_command(CLI::App& app) {
  struct Options {
    std::vector<std::string> cases;
    std::vector<int> iterations;
    double seconds = 0;
    bool full = false, stability = false;
    std::string json = "-", json_file;  // --json's value, "-" when absent: the old --json FILE is refused
  };
  auto o = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand("sweep", "Speed against error of pgs, block-gs, ldl-pgs and direct on the hard cases");
  add_list_option(cmd, "--cases", &o->cases, "Scenes (files or built-in names); default: the hard cases");
  add_list_option(cmd, "--iterations", &o->iterations, "Iteration counts (default 1,4,16,64; --full: 1,2,4,...,128)")
      ->check(integer_in(1, std::numeric_limits<int>::max()));
  // (at most 10^4 s: 10^6 steps of the scenes' 0.01 s, hours of wall time per run)
  cmd->add_option("--seconds", o->seconds, "Simulated time per run (default 1, --full 2; at most 10^4)")
      ->check(finite_in(0, 1e4, true));
  cmd->add_flag("--full", o->full, "The paper's sweep (papers/speed-vs-error.md)");
  cmd->add_flag("--stability", o->stability, "Also raise the mass ratio by 10x until each solver breaks");
  cmd->add_option("--json", o->json, "Print one JSON object on standard output instead of the tables")
      ->expected(0, 1)
      ->type_name("");
  cmd->add_option("--json-file", o->json_file, "Write the points papers/scripts/plot_speed_vs_error.py draws to this file");
  return [o] {
    if (!o->json.empty() && o->json != "-") throw InputError("sweep: --json " + o->json + " is now --json-file " + o->json);
    const bool json = o->json.empty();
    const std::vector<std::string> cases = o->cases.empty() ? sweep_cases(o->full) : o->cases;
    const std::vector<int> iterations = o->iterations.empty() ? sweep_iterations(o->full) : o->iterations;
    for (int it : iterations)
      if (it < 1) throw InputError("--iterations: every count must be at least 1");
    const double seconds = o->seconds > 0 ? o->seconds : (o->full ? 2.0 : 1.0);
    for (const std::string& c : cases) load_mechanism(c);  // refuse a bad name before the long work
    const std::vector<SweepPoint> points = speed_vs_error(cases, iterations, seconds, true);
    nlohmann::json j = sweep_json(points, seconds);
    if (!json) {
      std::printf("### Speed against error (%g s simulated per run)\n\n", seconds);
      print_sweep_markdown(stdout, points);
    }
    if (o->stability) {
      const std::vector<Breakdown> breaks = stability(cases, 10, seconds, true);
      if (json) {
        j["stability"] = to_json(breaks);
      } else {
        std::printf("\n### Mass ratio at which each solver breaks (10 iterations, dt <= 2.5 ms, %g s)\n\n", seconds);
        print_stability_markdown(stdout, breaks);
      }
    }
    if (!o->json_file.empty()) {
      std::ofstream out(o->json_file);
      out << j.dump(1) << '\n';
      finish_writing(out, o->json_file, "the sweep");
    }
    if (json) print_json(j);
    return 0;
  };
}

}  // namespace ldlpgs::cli
