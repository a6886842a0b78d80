// The options and JSON conventions the subcommands share (apps/options.h).
#include "apps/options.h"

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <limits>
#include <cstdio>
#include <iostream>

#include "ldlpgs/sparse/error.h"
#include "ldlpgs/sparse/text.h"
#include "ldlpgs/version.h"

namespace ldlpgs::cli {

void add_problem_options(CLI::App* cmd, ProblemArgs* a) {
  cmd->add_option("problem", a->spec, "Matrix Market file (symmetric), or FAMILY:CONSTRAINTS for a generated "
                                      "mechanism with H = J W J^T values (e.g. grid:100)")->required();
  cmd->add_option("--blocks", a->blocks, "Input block partition: auto (identical consecutive rows), N (uniform), or "
                                         "a file with one block size per line")->capture_default_str();
  cmd->add_option("--max-block", a->max_block, "Largest block --blocks auto forms")
      ->capture_default_str()
      ->check(integer_in(1, std::numeric_limits<int>::max()));
  cmd->add_flag("--split-blocks", a->split_blocks,
                "Drop the matrix's exact zeros and split each block (of --blocks, or a generated mechanism's "
                "constraints) into runs of rows with identical patterns");
}

void add_ordering_option(CLI::App* cmd, std::string* ordering, const std::string& help, bool list) {
  cmd->add_option("--ordering", *ordering, list ? help + " (comma-separated names, or all)" : help)
      ->capture_default_str();
  if (list) add_alias(cmd, "--orderings", ordering);
}

void add_json_flag(CLI::App* cmd, bool* json) {
  cmd->add_flag("--json", *json, "Print one JSON object on standard output instead of the table");
}

void add_renamed(CLI::App* cmd, const std::string& old_name, const std::string& message) {
  cmd->add_option_function<std::string>(old_name, [message](const std::string&) { throw InputError(message); })
      ->group("");
}

namespace {
std::string bound(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", x);
  return text;
}
}  // namespace

CLI::Validator finite_in(double lo, double hi, bool open) {
  const std::string range = lo == -HUGE_VAL && hi == HUGE_VAL ? ""
                            : hi == HUGE_VAL ? (open ? " > " : " >= ") + bound(lo)
                                             : " in " + std::string(open ? "(" : "[") + bound(lo) + ", " + bound(hi) + "]";
  return CLI::Validator(
      [lo, hi, open, range](std::string& text) -> std::string {
        double x = 0;
        const bool number = CLI::detail::lexical_cast(text, x) && std::isfinite(x);
        if (number && (open ? x > lo : x >= lo) && x <= hi) return {};
        return "'" + printable(text, 40) + "': must be a finite number" + range;
      },
      "");
}

CLI::Validator integer_in(long long lo, long long hi) {
  return CLI::Validator(
      [lo, hi](std::string& text) -> std::string {
        // Decimal, whatever the leading zeros: CLI11's conversion reads "010" as octal 8, so
        // `--shards 010` had meant 8 shards. The text is rewritten to what CLI11 then converts.
        long long x = 0;
        const char* first = text.data() + (text.starts_with('+') ? 1 : 0);
        const auto [end, ec] = std::from_chars(first, text.data() + text.size(), x);
        if (!text.empty() && ec == std::errc() && end == text.data() + text.size() && x >= lo && x <= hi) {
          text = std::to_string(x);
          return {};
        }
        return "'" + printable(text, 40) + "': must be an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
      },
      "");
}

nlohmann::json json_header(const std::string& command, nlohmann::json fields) {
  fields["ldlpgs_version"] = kVersion;
  fields["command"] = command;
  return fields;
}

nlohmann::json number_or_null(double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(nullptr); }

void print_json(const nlohmann::json& j) { std::cout << j.dump(2) << '\n'; }

void finish_writing(std::ofstream& out, const std::string& path, const std::string& what) {
  auto reason = [] { return errno ? std::string(" (") + std::strerror(errno) + ")" : std::string(); };
  if (!out.is_open()) throw InputError(path + ": cannot write " + what + ": cannot open it" + reason());  // errno of the open
  errno = 0;
  out.close();
  if (out.fail()) throw InputError(path + ": cannot write " + what + reason());
}

void progress(const std::string& command, const std::string& what) {
  std::fprintf(stderr, "ldlpgs %s: %s\n", command.c_str(), what.c_str());
}

HybridSchedule schedule_option(const char* flag, const std::string& value) {
  HybridSchedule schedule;
  if (hybrid_schedule_from_string(value, &schedule)) return schedule;
  std::string known;
  for (const char* name : hybrid_schedule_names()) known = known + " " + name;
  throw InputError(flag + (" " + value) + ": unknown schedule (known:" + known + ")");
}

}  // namespace ldlpgs::cli
