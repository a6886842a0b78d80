#pragma once
// The subcommands of the ldlpgs program. Each registers its options on the CLI11 app and
// returns the function that runs it (exit code 0, 1 for a failed check, 2 for bad input).
#include <CLI/CLI.hpp>

#include <cstdint>
#include <functional>
#include <string>

#include "ldlpgs/physics/mechanism.h"

namespace ldlpgs::cli {

using Command = std::function<int()>;

Command add_order_command(CLI::App& app);
Command add_report_command(CLI::App& app);
Command add_verify_command(CLI::App& app);
Command add_bench_command(CLI::App& app);
Command add_step_command(CLI::App& app);
Command add_view_command(CLI::App& app);
Command add_export_command(CLI::App& app);
Command add_spy_command(CLI::App& app);
Command add_sweep_command(CLI::App& app);
Command add_peers_command(CLI::App& app);
Command add_models_command(CLI::App& app);

// A scene stepped as `ldlpgs view SCENE --steps N --html-file FILE` steps it, nothing printed:
// the report's viewer pages. What the page shows, for the report's caption.
struct ViewPage {
  int frames = 0;
  int64_t bytes = 0;
  double simulated_s = 0, position_error_max_m = 0, penetration_max_m = 0;
  std::string failure;  // the first step that came apart (run_failure), or empty
};
ViewPage write_view_page(const std::string& scene, int steps, const std::string& html_file);

// ldlpgs::load_mechanism (physics/io/scenes.h), printing what an MJCF conversion dropped on stderr.
Mechanism load_mechanism(const std::string& spec, bool allow_dropped = false);

}  // namespace ldlpgs::cli
