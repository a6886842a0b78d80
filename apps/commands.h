#pragma once
// The subcommands of the ldlpgs program. Each registers its options on the CLI11 app and
// returns the function that runs it (exit code 0, 1 for a failed check, 2 for bad input).
#include <CLI/CLI.hpp>

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

// ldlpgs::load_mechanism (physics/scenes.h), printing what an MJCF conversion dropped on stderr.
Mechanism load_mechanism(const std::string& spec);

}  // namespace ldlpgs::cli
