// ldlpgs: the command-line program. Subcommands: order, report, verify, bench, step, view, export, spy, sweep, peers (ldlpgs SUBCOMMAND --help).
// Bad input ends with a one-line message naming the file, line and problem, and exit code 2; the
// options every subcommand shares, and their names, are in apps/options.h (docs/cli.md,
// "Command-line vocabulary"). The last line of defence: no exception ends in
// std::terminate. Running out of memory is exit 2 naming the input, as bad input is (a size line
// or a family size too large for this machine); any other exception is a bug of ours, exit 3,
// its message printed as one bounded line.
#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <map>
#include <new>
#include <stdexcept>
#include <optional>
#include <string>
#include <sstream>
#include <string_view>

#include "apps/commands.h"
#include "peers/competitors.h"
#include "ldlpgs/sparse/error.h"
#include "ldlpgs/sparse/limits.h"
#include "ldlpgs/sparse/text.h"
#include "ldlpgs/version.h"

namespace {

// Levenshtein distance: a misspelt name is a few insertions, deletions or substitutions away.
size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diagonal = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] != b[j - 1])});
      diagonal = up;
    }
  }
  return row[b.size()];
}

// "; did you mean X?" for the nearest of `names` within a third of the word's length, else "".
std::string suggestion(const std::string& word, const std::vector<std::string>& names) {
  const std::string* best = nullptr;
  size_t best_distance = word.size() / 3 + 1;
  for (const std::string& name : names) {
    const size_t d = edit_distance(word, name);
    if (d < best_distance) best = &name, best_distance = d;
  }
  return best ? "; did you mean " + *best + "?" : "";
}

// The long names a user may type on `cmd`, with dashes; old spellings (hidden) are not suggested.
std::vector<std::string> option_names(const CLI::App* cmd) {
  std::vector<std::string> names;
  for (const CLI::Option* o : cmd->get_options()) {
    if (o->get_group().empty()) continue;
    for (const std::string& n : o->get_lnames()) names.push_back("--" + n);
  }
  return names;
}

std::vector<std::string> subcommand_names(const CLI::App& app) {
  std::vector<std::string> names;
  for (const CLI::App* sub : app.get_subcommands({})) names.push_back(sub->get_name());
  return names;
}

// No subcommand, or one this program does not have: the usage, then what it got.
int usage_error(const CLI::App& app, const std::string& got) {
  std::fprintf(stderr, "%s", app.help().c_str());
  std::fprintf(stderr, "ldlpgs: %s\n", got.c_str());
  return 2;
}

// An argument CLI11 did not place (`what`: its ExtrasError's message, the arguments after the
// colon): an unknown subcommand, a misspelt option (the nearest one named), or a second list
// item after a space (lists are comma-separated).
int extras_error(const CLI::App& app, const std::string& what, int argc, char** argv) {
  // CLI11 lists the arguments in no particular order: the first in argv, an option before a word
  std::vector<std::string> extras;
  std::stringstream list(what.substr(what.rfind(": ") + 2));
  for (std::string word; list >> word;) extras.push_back(word);
  std::string extra;
  for (int pass = 0; pass < 2 && extra.empty(); ++pass)
    for (int i = 1; i < argc && extra.empty(); ++i)
      if ((pass == 1 || argv[i][0] == '-') && std::find(extras.begin(), extras.end(), argv[i]) != extras.end())
        extra = argv[i];
  if (extra.empty() && !extras.empty()) extra = extras.front();
  const std::vector<CLI::App*> parsed = app.get_subcommands();
  if (parsed.empty()) {
    if (extra.starts_with("-")) return usage_error(app, "unknown option " + extra + " (no subcommand given)");
    return usage_error(app, "unknown subcommand '" + extra + "'" + suggestion(extra, subcommand_names(app)));
  }
  const CLI::App* cmd = parsed.front();
  const std::string prefix = "ldlpgs " + cmd->get_name() + ": ";
  if (extra.starts_with("-")) {
    const std::string name = extra.substr(0, extra.find('='));
    std::fprintf(stderr, "%sunknown option %s%s\n", prefix.c_str(), name.c_str(),
                 suggestion(name, option_names(cmd)).c_str());
    return 2;
  }
  // the last option before the word: a list option means a list written with spaces
  int at = argc - 1;
  while (at > 0 && argv[at] != extra) --at;
  int k = at - 1;
  while (k > 0 && argv[k][0] != '-') --k;
  const CLI::Option* option = k > 0 ? cmd->get_option_no_throw(std::string(argv[k]).substr(0, std::string(argv[k]).find('='))) : nullptr;
  if (option && option->get_delimiter() == ',' && at > 1)
    std::fprintf(stderr, "%sunexpected argument '%s': lists are comma-separated (%s %s,%s)\n", prefix.c_str(),
                 extra.c_str(), argv[k], argv[at - 1], extra.c_str());
  else
    std::fprintf(stderr, "%sunexpected argument '%s'\n", prefix.c_str(), extra.c_str());
  return 2;
}

// `bench` times CHOLMOD supernodal, whose OpenMP threads only a thread limit set before the
// program starts bounds (peers/competitors.h): the one subcommand that re-executes itself with
// OMP_THREAD_LIMIT=1. (The subcommand is the first word; --no-size-limits takes no value.)
void limit_bench_to_one_thread(int argc, char** argv) {
  for (int i = 1; i < argc; ++i)
    if (argv[i][0] != '-') {
      if (std::string_view(argv[i]) == "bench") ldlpgs::limit_openmp_to_one_thread(argv);
      break;
    }
}

using Commands = std::map<CLI::App*, ldlpgs::cli::Command>;

// The subcommands on the app, each with the function that runs it.
Commands add_commands(CLI::App& app) {
  Commands commands;
  for (auto make : {ldlpgs::cli::add_order_command, ldlpgs::cli::add_report_command, ldlpgs::cli::add_verify_command,
                    ldlpgs::cli::add_bench_command, ldlpgs::cli::add_step_command, ldlpgs::cli::add_view_command,
                    ldlpgs::cli::add_export_command, ldlpgs::cli::add_spy_command, ldlpgs::cli::add_sweep_command,
                    ldlpgs::cli::add_peers_command, ldlpgs::cli::add_models_command}) {
    const size_t before = app.get_subcommands({}).size();
    ldlpgs::cli::Command run = make(app);
    commands[app.get_subcommands({})[before]] = std::move(run);
  }
  return commands;
}

// The command line parsed; an exit code when the program ends here (help, version, bad input).
std::optional<int> parse_arguments(CLI::App& app, int argc, char** argv) {
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ExtrasError& e) {
    return extras_error(app, e.what(), argc, argv);
  } catch (const CLI::ParseError& e) {
    const std::vector<CLI::App*> parsed = app.get_subcommands();
    std::fprintf(stderr, "ldlpgs%s: %s\n", parsed.empty() ? "" : (" " + parsed.front()->get_name()).c_str(), e.what());
    return 2;
  } catch (const ldlpgs::InputError& e) {  // an old spelling refused while parsing (apps/options.h)
    std::fprintf(stderr, "ldlpgs %s: %s\n", app.get_subcommands().front()->get_name().c_str(), e.what());
    return 2;
  }
  if (app.get_subcommands().empty()) return usage_error(app, "no subcommand given");
  return std::nullopt;
}

// What the command printed may still sit in a buffer: a full disk (or `> /dev/full`) shows only
// now, and had exited 0 with nothing written. False (and said) if standard output failed.
bool standard_output_written() {
  std::cout.flush();
  errno = 0;
  if (std::cout && std::fflush(stdout) == 0 && !std::ferror(stdout)) return true;
  std::fprintf(stderr, "ldlpgs: cannot write standard output%s\n",
               errno ? (std::string(" (") + std::strerror(errno) + ")").c_str() : "");
  return false;
}

// The parsed subcommand run; its exceptions as one line each: bad input 2, an internal error 3.
int run_command(CLI::App& app, const Commands& commands, int argc, char** argv) {
  std::string input;  // the command's arguments, to name what was too large
  for (int k = 1; k < argc; ++k) (input += k > 1 ? " " : "") += argv[k];
  try {
    const int code = commands.at(app.get_subcommands().front())();
    return standard_output_written() ? code : 2;
  } catch (const ldlpgs::InputError& e) {
    // (the readers quote input through printable() already: its escapes are kept as they are)
    std::fprintf(stderr, "ldlpgs: %s\n", ldlpgs::printable(e.what(), 400, false).c_str());
    return 2;
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "ldlpgs: out of memory on '%s': the input is too large for this machine\n",
                 ldlpgs::printable(input, 200).c_str());
    return 2;
  } catch (const std::length_error& e) {  // a size beyond what a container can hold
    std::fprintf(stderr, "ldlpgs: '%s' asks for more than can be allocated (%s)\n", ldlpgs::printable(input, 200).c_str(),
                 ldlpgs::printable(e.what(), 100).c_str());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ldlpgs: internal error (please report it) on '%s': %s\n", ldlpgs::printable(input, 200).c_str(),
                 ldlpgs::printable(e.what(), 300).c_str());
    return 3;
  }
}

}  // namespace

int main(int argc, char** argv) {
  limit_bench_to_one_thread(argc, argv);
  CLI::App app{"ldlpgs: block-sparse LDL^T with graph-elimination orderings, for mechanisms"};
  app.set_version_flag("--version", std::string("ldlpgs ") + ldlpgs::kVersion);
  app.add_flag_callback("--no-size-limits", [] { ldlpgs::size_limits() = ldlpgs::SizeLimits::none(); },
                        "Lift the caps on declared sizes (sparse/limits.h: 2^24 rows, 2^28 entries, 2^22 constraints)");
  app.require_subcommand(0, 1);
  const Commands commands = add_commands(app);
  if (const std::optional<int> exit = parse_arguments(app, argc, argv)) return *exit;
  return run_command(app, commands, argc, argv);
}
