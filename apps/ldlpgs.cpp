// ldlpgs: the command-line program. Subcommands: order, report, verify, bench, step, export, spy, sweep, peers (ldlpgs SUBCOMMAND --help).
// Bad input ends with a one-line message naming the file, line and problem, and exit code 2.
#include <cstdio>
#include <map>

#include "apps/commands.h"
#include "ldlpgs/sparse/error.h"

int main(int argc, char** argv) {
  CLI::App app{"ldlpgs: block-sparse LDL^T with graph-elimination orderings, for mechanisms"};
  app.require_subcommand(1);
  std::map<CLI::App*, ldlpgs::cli::Command> commands;
  auto add = [&](ldlpgs::cli::Command (*make)(CLI::App&)) {
    const size_t before = app.get_subcommands({}).size();
    ldlpgs::cli::Command run = make(app);
    commands[app.get_subcommands({})[before]] = std::move(run);
  };
  add(ldlpgs::cli::add_order_command);
  add(ldlpgs::cli::add_report_command);
  add(ldlpgs::cli::add_verify_command);
  add(ldlpgs::cli::add_bench_command);
  add(ldlpgs::cli::add_step_command);
  add(ldlpgs::cli::add_export_command);
  add(ldlpgs::cli::add_spy_command);
  add(ldlpgs::cli::add_sweep_command);
  add(ldlpgs::cli::add_peers_command);
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "ldlpgs: %s\n", e.what());
    return 2;
  }
  try {
    for (CLI::App* sub : app.get_subcommands()) return commands.at(sub)();
  } catch (const ldlpgs::InputError& e) {
    std::fprintf(stderr, "ldlpgs: %s\n", e.what());
    return 2;
  }
  return 2;
}
