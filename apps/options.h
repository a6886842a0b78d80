#pragma once
// The command-line vocabulary (docs/cli.md, "Command-line vocabulary"): every option more than one
// subcommand takes is registered here, so each flag is spelled once, and every --json object
// starts from json_header(). Lists are comma-separated with no spaces; an option that writes a
// file ends in -file, one that writes a directory in -dir; old spellings are hidden aliases, or
// refused with a message naming the new one when their meaning changed.
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <string>
#include <vector>

#include "ldlpgs/solver/solver.h"

namespace ldlpgs::cli {

// The positional PROBLEM of order, verify and bench: a Matrix Market file or FAMILY:CONSTRAINTS
// (a generated mechanism), and the block partition of a file: --blocks, --max-block.
struct ProblemArgs {
  std::string spec, blocks = "auto";
  int max_block = 6;
  bool split_blocks = false;  // --split-blocks: partition_refine, on the matrix without its zeros
};
void add_problem_options(CLI::App* cmd, ProblemArgs* a);

// --ordering NAME; with `list`, comma-separated names or `all` (order, report), where the old
// --orderings stays a hidden alias.
void add_ordering_option(CLI::App* cmd, std::string* ordering, const std::string& help, bool list = false);

// A schedule option's value (--schedule, --contact-schedule), or an InputError listing the names.
HybridSchedule schedule_option(const char* flag, const std::string& value);

// --json: the command's one JSON object on standard output instead of its table.
void add_json_flag(CLI::App* cmd, bool* json);

// Checks for number options, run on what the user typed (a default is never checked), with a
// one-line message: "must be a finite number > 0". CLI11's Range and NonNegativeNumber let nan
// through and spell out DBL_MAX in 310 digits. `open`: the lower bound itself is refused.
CLI::Validator finite_in(double lo, double hi = HUGE_VAL, bool open = false);
CLI::Validator integer_in(long long lo, long long hi);

// A comma-separated list (--sizes 100,1000): a space ends it, so `--cases a b` is refused
// rather than read two ways.
template <class T>
CLI::Option* add_list_option(CLI::App* cmd, const std::string& name, std::vector<T>* values, const std::string& help) {
  return cmd->add_option(name, *values, help + " (comma-separated)")->delimiter(',')->allow_extra_args(false);
}

// An old spelling of an option, hidden from --help, setting what the new one sets.
template <class T>
void add_alias(CLI::App* cmd, const std::string& old_name, T* target) {
  cmd->add_option(old_name, *target)->group("");
}
// An old spelling whose meaning changed: refused, naming the new one.
void add_renamed(CLI::App* cmd, const std::string& old_name, const std::string& message);

// `fields` with "ldlpgs_version" (kVersion) and "command": the fields every --json object carries.
nlohmann::json json_header(const std::string& command, nlohmann::json fields = nlohmann::json::object());
// Non-finite values as null (JSON has no NaN).
nlohmann::json number_or_null(double x);
void print_json(const nlohmann::json& j);

// Closes a file written with `out` and throws InputError "PATH: cannot write WHAT (reason)" if any
// write failed: a stream buffers, so a full disk or /dev/full shows only when it flushes.
void finish_writing(std::ofstream& out, const std::string& path, const std::string& what);

// A progress line on standard error: "ldlpgs COMMAND: WHAT".
void progress(const std::string& command, const std::string& what);
// Dimension from which order and bench print progress: below it they take a second or less.
inline constexpr int kProgressDimension = 5000;

}  // namespace ldlpgs::cli
