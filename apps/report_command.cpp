// ldlpgs report: the main job. On the generated mechanism families, the built-in scenes and the
// test matrices, in seven stages:
//   1. the orderings comparison (papers/orderings.md),
//   2. the block LDL^T of every problem verified against CHOLMOD's (factor/verify.h),
//   3. the talk's table and spy plots (papers/scripts/talk_figures.py, papers/talk-figures.md),
//   4. speed against error of the solvers on the hard cases, and where each breaks
//      (apps/sweep.h, papers/speed-vs-error.md),
//   5. where each solver breaks, with the figures (matplotlib),
//   6. two runs to watch in a browser (view/html.h),
//   7. Gymnasium's MuJoCo models stepped beside MuJoCo (apps/models.h, papers/physics.md), and
//      index.html (python3-markdown).
// It writes a directory (report/ by default) holding index.md (opening with a key finding per
// study), index.html, the figures, and data/: each big table as JSON and CSV records (one flat
// object or line per row, for pandas); the orderings tables go to standard output as well, and a progress
// line per stage and problem to standard error. Exit code 1 if a factorization is not verified
// against CHOLMOD's (it disagrees, either refused the matrix, or no digit can be checked) or a
// stage fails, 2 for bad input.
#include <algorithm>
#include <cmath>
#include <chrono>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <thread>

#include "apps/commands.h"
#include "apps/compare.h"
#include "apps/models.h"
#include "apps/options.h"
#include "apps/sweep.h"
#include "apps/verification.h"
#include "ldlpgs/sparse/error.h"
#include "ldlpgs/physics/io/mjcf.h"
#include "ldlpgs/physics/io/scenes.h"
#include "ldlpgs/sparse/families.h"
#include "ldlpgs/version.h"

namespace ldlpgs::cli {

namespace {

namespace fs = std::filesystem;

constexpr int kStages = 7;
constexpr int kModelSteps = 1000;  // per model, of its own timestep
constexpr double kViewSeconds = 2;  // simulated, per viewer page

void stage_progress(int stage, const std::string& what) { std::fprintf(stderr, "report [%d/%d] %s\n", stage, kStages, what.c_str()); }

std::string shell_quoted(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

// The python that has Debian's matplotlib and markdown (the scripts re-run themselves under
// /usr/bin/python3 too, but asking first lets the report say what is missing).
std::string find_python() {
  for (const char* python : {"/usr/bin/python3", "python3"}) {
    const std::string probe = std::string(python) + " -c 'import matplotlib, markdown' >/dev/null 2>&1";
    if (std::system(probe.c_str()) == 0) return python;
  }
  return "";
}

// Where the report's scripts (papers/scripts/*.py), default matrices and MJCF models are:
// installed beside the program (PREFIX/share/ldlpgs/{scripts,matrices,mjcf/gymnasium} for
// PREFIX/bin/ldlpgs), else in the source tree it was built from (`source`, empty when installed).
struct ReportFiles {
  std::string scripts, matrices, source, models;
};
const ReportFiles& report_files() {
  static const ReportFiles files = [] {
    std::error_code ec;
    const fs::path share = fs::read_symlink("/proc/self/exe", ec).parent_path().parent_path() / "share" / "ldlpgs";
    if (!ec && fs::exists(share / "scripts" / "talk_figures.py", ec))
      return ReportFiles{(share / "scripts").string(), (share / "matrices").string(), "",
                         (share / "mjcf" / "gymnasium").string()};
    return ReportFiles{LDLPGS_SOURCE_DIR "/papers/scripts", LDLPGS_SOURCE_DIR "/tests/data/matrices", LDLPGS_SOURCE_DIR,
                       LDLPGS_SOURCE_DIR "/tests/data/mjcf/gymnasium"};
  }();
  return files;
}

// Runs one of the report's scripts; its standard output to `stdout_file` when given.
bool run_script(const std::string& python, const std::string& script, const std::string& args,
                const std::string& stdout_file = "") {
  std::string cmd = python + " " + shell_quoted(report_files().scripts + "/" + script) + " " + args;
  if (!stdout_file.empty()) cmd += " > " + shell_quoted(stdout_file);
  const int rc = std::system(cmd.c_str());
  if (rc != 0) std::fprintf(stderr, "report: papers/%s failed (exit status %d)\n", script.c_str(), rc);
  return rc == 0;
}

std::string read_file(const std::string& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

std::string machine() {
  std::ifstream cpuinfo("/proc/cpuinfo");
  std::string line, cpu = "unknown CPU";
  while (std::getline(cpuinfo, line))
    if (line.rfind("model name", 0) == 0) {
      cpu = line.substr(line.find(':') + 2);
      break;
    }
  double load[1] = {0};
  std::ifstream("/proc/loadavg") >> load[0];
  char text[256];
  std::snprintf(text, sizeof text, "%s, %u hardware threads, load average %.2f at the start", cpu.c_str(),
                std::thread::hardware_concurrency(), load[0]);
  return text;
}

// One table of the report as data: DIR/NAME.json ({"ldlpgs_version", "command": "report",
// "table", "records"}: one object per row) and DIR/NAME.csv, one line per row, nested objects flattened to a_b columns.
void write_table(const fs::path& dir, const std::string& name, const nlohmann::json& rows) {
  const std::string json_path = (dir / (name + ".json")).string();
  std::ofstream json(json_path);
  json << json_header("report", {{"table", name}, {"records", rows}}).dump(1) << '\n';
  finish_writing(json, json_path, "the table");
  std::vector<nlohmann::json> flat;
  std::vector<std::string> columns;
  for (const nlohmann::json& row : rows) {
    nlohmann::json f = row.flatten();  // keys "/a/b"
    nlohmann::json line = nlohmann::json::object();
    for (auto& [key, value] : f.items()) {
      std::string column = key.substr(1);
      std::replace(column.begin(), column.end(), '/', '_');
      if (std::find(columns.begin(), columns.end(), column) == columns.end()) columns.push_back(column);
      line[column] = value;
    }
    flat.push_back(std::move(line));
  }
  std::ofstream csv(dir / (name + ".csv"));
  for (size_t c = 0; c < columns.size(); ++c) csv << (c ? "," : "") << columns[c];
  csv << '\n';
  for (const nlohmann::json& line : flat) {
    for (size_t c = 0; c < columns.size(); ++c) {
      if (c) csv << ',';
      if (!line.contains(columns[c]) || line[columns[c]].is_null()) continue;  // empty: NaN in pandas
      const nlohmann::json& v = line[columns[c]];
      // strings quoted as CSV does, a quote doubled
      if (v.is_string()) {
        std::string text = v.get<std::string>(), q;
        for (char ch : text) q += ch == '"' ? std::string("\"\"") : std::string(1, ch);
        csv << '"' << q << '"';
      } else {
        csv << v.dump();
      }
    }
    csv << '\n';
  }
  finish_writing(csv, (dir / (name + ".csv")).string(), "the table");
}

// A paper's path as a link from the report directory when the report is inside the project
// (report/ by default); outside it, or from an installed program, the path in the project only:
// a link would carry this machine's layout into the report.
std::string paper(const std::string& out_dir, const std::string& name) {
  if (report_files().source.empty()) return "`papers/" + name + "`";
  const fs::path source = fs::weakly_canonical(report_files().source), dir = fs::weakly_canonical(out_dir);
  const std::string inside = fs::relative(dir, source).string();
  if (inside.empty() || inside.starts_with("..")) return "`papers/" + name + "`";
  return "[papers/" + name + "](" + fs::relative(source / "papers" / name, dir).string() + ")";
}

// The key findings: one sentence per study, with its number, before the big tables.

// Orderings: MECA's scalar nnz(L) against AMD's on the block graph, as a geometric mean of ratios.
std::string orderings_finding(const std::string& out_dir, const std::vector<std::pair<Problem, std::vector<Row>>>& results) {
  double log_sum = 0;
  int compared = 0, no_larger = 0;
  for (const auto& [p, rows] : results) {
    const Row *meca = nullptr, *amd = nullptr;
    for (const Row& r : rows) {
      if (r.summary.name == "meca") meca = &r;
      if (r.summary.name == "amd") amd = &r;
    }
    if (!meca || !amd || amd->summary.nnz_L == 0) continue;
    const double ratio = static_cast<double>(meca->summary.nnz_L) / static_cast<double>(amd->summary.nnz_L);
    log_sum += std::log(ratio);
    ++compared;
    no_larger += ratio <= 1;
  }
  char line[1024];
  if (compared)
    std::snprintf(line, sizeof line, "- **Orderings**: MECA's nnz(L) is %.3f times AMD's (geometric mean over %d "
                  "problems), no larger on %d of them (%s).\n",
                  std::exp(log_sum / compared), compared, no_larger, paper(out_dir, "orderings.md").c_str());
  else
    std::snprintf(line, sizeof line, "- **Orderings**: %zu problems compared; MECA and AMD were not both run (%s).\n",
                  results.size(), paper(out_dir, "orderings.md").c_str());
  return line;
}

std::string verification_finding(const std::string& out_dir, const std::vector<std::pair<std::string, Verification>>& checks) {
  int agree = 0, verified = 0;
  double worst = 0;
  for (const auto& [name, v] : checks) {
    const Verdict said = verdict(v);
    agree += said == Verdict::agree;
    if (said != Verdict::agree && said != Verdict::disagree) continue;  // nothing measured
    ++verified;
    worst = std::max({worst, v.L_rel_diff, v.D_rel_diff, v.x_rel_diff});
  }
  char largest[96] = "nothing was verified";
  if (verified) std::snprintf(largest, sizeof largest, "the largest relative difference of L, D or x is %.1e", worst);
  const std::string others = not_agreeing(checks);
  // the tolerance grows with the condition estimate, so the largest difference alone says little
  char line[1024];
  std::snprintf(line, sizeof line, "- **The block LDL^T against CHOLMOD**: %d of %zu problems agree within "
                "max(1e-10, eps cond_1); %s%s (%s).\n",
                agree, checks.size(), largest, others.empty() ? "" : ("; " + others).c_str(),
                paper(out_dir, "factor.md").c_str());
  return line;
}

std::string talk_finding(const std::string& out_dir, int talk_rows) {
  char line[1024];
  if (talk_rows > 0)
    std::snprintf(line, sizeof line, "- **The talk's figures**: %d mechanisms measured beside the talk's numbers "
                  "(%s).\n", talk_rows, paper(out_dir, "talk-figures.md").c_str());
  else
    std::snprintf(line, sizeof line, "- **The talk's figures**: not made in this run (%s).\n",
                  paper(out_dir, "talk-figures.md").c_str());
  return line;
}

// Speed against error: on how many cases each solver gets within 1 mm at all.
std::string sweep_finding(const std::string& out_dir, const std::vector<SweepPoint>& points) {
  std::string reached;
  std::vector<std::string> cases;
  for (const SweepPoint& p : points)
    if (std::find(cases.begin(), cases.end(), p.scene) == cases.end()) cases.push_back(p.scene);
  for (const char* solver : {"ldl-pgs", "pgs", "block-gs", "direct"}) {
    int within = 0, ran = 0;
    for (const std::string& c : cases) {
      bool tried = false, ok = false;
      for (const SweepPoint& p : points)
        if (p.scene == c && p.solver == solver) {
          tried = true;
          ok = ok || (!p.failed() && p.error_max <= 1e-3);
        }
      ran += tried;
      within += ok;
    }
    if (ran) reached += std::string(reached.empty() ? "" : ", ") + solver + " " + std::to_string(within) + " of " +
                        std::to_string(ran);
  }
  char line[1024];
  std::snprintf(line, sizeof line, "- **Speed against error**: cases held within 1 mm for the whole run at some "
                "iteration count: %s (%s).\n", reached.c_str(), paper(out_dir, "speed-vs-error.md").c_str());
  return line;
}

std::string breaks_finding(const std::string& out_dir, const std::vector<Breakdown>& breaks) {
  std::string held;
  for (const char* solver : {"ldl-pgs", "pgs", "block-gs", "direct"}) {
    int never = 0, ran = 0;
    for (const Breakdown& b : breaks)
      if (b.solver == solver) ++ran, never += b.breaks == 0;
    if (ran) held += std::string(held.empty() ? "" : ", ") + solver + " " + std::to_string(never) + " of " +
                     std::to_string(ran);
  }
  char line[1024];
  std::snprintf(line, sizeof line, "- **Where each solver breaks**: cases that never broke up to 1e9 times the "
                "scene's mass ratio (10 iterations): %s (%s).\n\n", held.c_str(),
                paper(out_dir, "speed-vs-error.md").c_str());
  return line;
}

std::string key_findings(const std::string& out_dir, const std::vector<std::pair<Problem, std::vector<Row>>>& results,
                         const std::vector<std::pair<std::string, Verification>>& checks, int talk_rows,
                         const std::vector<SweepPoint>& points, const std::vector<Breakdown>& breaks) {
  return "## Key findings\n\n" + orderings_finding(out_dir, results) + verification_finding(out_dir, checks) +
         talk_finding(out_dir, talk_rows) + sweep_finding(out_dir, points) + breaks_finding(out_dir, breaks);
}

// The report's options (the `report` flags).
struct ReportOptions {
  std::string matrices = report_files().matrices, orderings = "all", out = "report";
  std::vector<int> sizes = {100, 1000, 5000};
  std::string verify = "best";
  bool markdown = false, cholmod = false, full = false, no_figures = false;
  std::vector<std::string> cases;  // empty: sweep_cases(full)
};

// One run of the report: its inputs checked, then the six stages in order, each appending its
// section to the index (buffered: the key findings that open the file are known only at the end)
// and its tables to data/, then the index written.
class Report {
 public:
  explicit Report(const ReportOptions& o) : o_(o), index_(nullptr, std::fclose) {}

  int run() {
    start_ = std::chrono::steady_clock::now();
    prepare();
    orderings();
    verification();
    talk_figures();
    speed_against_error();
    stability_stage();
    viewer_pages();
    models_stage();
    return finish();
  }

 private:
  // The inputs (orderings, matrices, cases) and the report directory, refused before the long work.
  void prepare() {
    names_ = parse_ordering_list(o_.orderings);
    verify_ordering_ = &find_ordering(o_.verify);
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(o_.matrices, ec)) {
      if (entry.path().extension() == ".mtx") files_.push_back(entry.path().string());
    }
    if (ec) throw InputError(o_.matrices + ": cannot read directory (" + ec.message() + ")");
    std::sort(files_.begin(), files_.end());
    for (const std::string& c : o_.cases) load_mechanism(c);  // refuse a bad name before the long work
    if (o_.out.empty()) throw InputError("--out-dir: an empty path (the report directory to write)");
    fs::create_directories(fs::path(o_.out) / "figures", ec);
    if (!ec) fs::create_directories(fs::path(o_.out) / "data", ec);
    if (ec) throw InputError(o_.out + ": cannot create the report directory (" + ec.message() + ")");
    out_dir_ = fs::absolute(o_.out).string();
    figures_ = out_dir_ + "/figures";
    data_ = out_dir_ + "/data";
    index_path_ = out_dir_ + "/index.md";
    if (!std::ofstream(index_path_)) throw InputError(index_path_ + ": cannot write");
    index_.reset(open_memstream(&body_.data, &body_.size));
    if (!index_) throw InputError(index_path_ + ": cannot buffer the report");
    md_ = index_.get();
    write_head();
  }

  void write_head() {
    const std::time_t now = std::time(nullptr);
    char date[64];
    std::strftime(date, sizeof date, "%Y-%m-%d %H:%M UTC", std::gmtime(&now));
    char head[2048];
    std::snprintf(head, sizeof head, "# ldlpgs report\n\nMade by `./build.sh report` (`build/bin/ldlpgs report%s%s`, "
                  "ldlpgs %s) on %s.\nMachine: %s. The tables as data (JSON and CSV, for pandas): `data/`.\n\n",
                  o_.full ? " --full" : "", o_.out == "report" ? "" : (" --out-dir " + o_.out).c_str(), kVersion,
                  date, machine().c_str());
    head_ = head;
    std::fprintf(md_, "1. [Orderings](#1-orderings): fill and flops of MDA and MECA against AMD and METIS\n"
                 "2. [The block LDL^T against CHOLMOD](#2-the-block-ldlt-against-cholmod)\n"
                 "3. [The talk's figures](#3-the-talks-figures)\n"
                 "4. [Speed against error](#4-speed-against-error)\n"
                 "5. [Where each solver breaks](#5-where-each-solver-breaks)\n"
                 "6. [Watch it move](#6-watch-it-move)\n\n");
  }

  // One problem of stage 1 compared; text: its table on stdout.
  void compare_problem(Problem p) {
    std::vector<Row> rows = compare(p, names_, o_.cholmod);
    if (!o_.markdown) {
      print_table(stdout, p, rows);
      std::fflush(stdout);
    }
    for (Row& r : rows) r.ordering = Ordering();  // keep the summaries, not the permutations
    results_.emplace_back(std::move(p), std::move(rows));
  }

  // 1. Orderings. Text: one table per problem on stdout. Markdown: one table per metric.
  void orderings() {
    stage_progress(1, "orderings on the mechanism families and " + std::to_string(files_.size()) + " matrices");
    std::vector<std::string> skipped;
    for (std::string_view family : family_names()) {
      for (int size : o_.sizes) {
        // The heavy body makes H dense: past a few hundred constraints that is a dense matrix
        // with nothing left to order, and the explicit elimination graph holds all its edges.
        if (family == "heavy" && size > 500) continue;
        std::fprintf(stderr, "report: %s, %d constraints\n", std::string(family).c_str(), size);
        compare_problem(make_mechanism(std::string(family), size));
      }
    }
    for (const std::string& name : builtin_scene_names()) {
      const Mechanism m = load_mechanism(name);
      if (m.constraint_graph(true).num_blocks() == 0) continue;
      std::fprintf(stderr, "report: scene %s\n", name.c_str());
      compare_problem(scene_problem(m));
    }
    for (const std::string& file : files_) {
      std::fprintf(stderr, "report: %s\n", file.c_str());
      try {
        compare_problem(load_matrix(file, "auto", 6));
      } catch (const InputError& e) {
        // An unsymmetric matrix has no LDL^T: the comparison skips it and says why.
        std::printf("%sskipped: %s\n", o_.markdown ? "\n" : "", e.what());
        skipped.push_back(e.what());
      }
    }
    if (o_.markdown) print_markdown_by_metric(stdout, results_);
    std::fprintf(md_, "## 1. Orderings\n\nThe generated mechanism families at %zu sizes, the built-in scenes' H_0 "
                 "(whole, as `ldlpgs export SCENE --no-shatter` writes it) and the matrices of `%s`, "
                 "every ordering; scalar counts as CHOLMOD defines them, block flops the talk's cost model "
                 "(papers/orderings.md explains the columns). One problem in detail: "
                 "`build/bin/ldlpgs order PROBLEM --cholmod`.\n",
                 o_.sizes.size(), o_.matrices.c_str());
    print_markdown_by_metric(md_, results_);
    for (const std::string& s : skipped) std::fprintf(md_, "\nSkipped: %s\n", s.c_str());
    nlohmann::json ordering_rows = nlohmann::json::array();
    for (const auto& [p, rows] : results_) {
      nlohmann::json j = to_json(p, rows);
      for (nlohmann::json& r : j["results"]) {
        for (const char* key : {"matrix", "n", "blocks"}) r[key] = j[key];
        ordering_rows.push_back(std::move(r));
      }
    }
    write_table(data_, "orderings", ordering_rows);
  }

  // 2. The factorization of every problem, in the ordering o_.verify, against CHOLMOD's.
  void verification() {
    stage_progress(2, "the block LDL^T of every problem against CHOLMOD");
    nlohmann::json verification_rows = nlohmann::json::array();
    for (const auto& [p, rows] : results_) {
      std::fprintf(stderr, "report: verifying %s\n", p.name.c_str());
      checks_.emplace_back(p.name, verify_against_cholmod(p.a, p.blocks, compute_ordering(*verify_ordering_, p.blocks, p.a)));
      verification_rows.push_back(to_json(p, checks_.back().second));
    }
    write_table(data_, "verification", verification_rows);
    std::printf(o_.markdown ? "\n### The block LDL^T against CHOLMOD\n\n" : "\nThe block LDL^T against CHOLMOD's simplicial LDL^T, same permutation:\n");
    print_verification_table(stdout, checks_, o_.markdown);
    // A row that is not yes is one of three things (verdict()): counted apart, so that a matrix
    // a solver refused is not reported as a disagreement.
    const std::string not_all = not_agreeing(checks_);
    const bool all_agree = not_all.empty();
    if (!all_agree)
      std::printf("NOT ALL AGREE: %s; tolerances in factor/verify.h\n", not_all.c_str());
    ok_ = ok_ && all_agree;
    const std::string summary = all_agree ? "All agree." : "**Not all agree: " + not_all + ".**";
    std::fprintf(md_, "\n## 2. The block LDL^T against CHOLMOD\n\nOrdering %s; L, D and x against CHOLMOD's simplicial "
                 "LDL^T on the same permutation, tolerance max(1e-10, eps cond_1) (factor/verify.h); one row in "
                 "detail: `build/bin/ldlpgs verify PROBLEM`. %s\n\n",
                 o_.verify.c_str(), summary.c_str());
    print_verification_table(md_, checks_, true);
  }

  // 3. The talk's table (papers/scripts/talk_figures.py runs spy, export, bench and step of this program).
  void talk_figures() {
    python_ = o_.no_figures ? "" : find_python();
    if (python_.empty() && !o_.no_figures)
      std::fprintf(stderr, "report: python3 with matplotlib and markdown not found (Debian's python3-matplotlib and "
                           "python3-markdown; ./build.sh report installs them): the talk's table, the plots and "
                           "index.html are skipped\n");
    std::fprintf(md_, "\n## 3. The talk's figures\n\n");
    stage_progress(3, "the talk's table and spy plots");
    if (python_.empty()) {
      std::fprintf(md_, "Skipped: no python3 with matplotlib.\n");
      return;
    }
    const std::string self = fs::read_symlink("/proc/self/exe").string(), table = out_dir_ + "/talk-table.md";
    if (!run_script(python_, "talk_figures.py", shell_quoted(self) + " --figures " + shell_quoted(figures_), table)) {
      ok_ = false;
      std::fprintf(md_, "Failed: papers/scripts/talk_figures.py (its message is on standard error).\n");
      return;
    }
    const std::string text = read_file(table);
    for (size_t at = text.find("\n|"); at != std::string::npos; at = text.find("\n|", at + 1)) ++talk_rows_;
    talk_rows_ = std::max(0, talk_rows_ - 1);  // the header's rule line
    std::fprintf(md_, "Per mechanism, the talk's figure / ours (papers/talk-figures.md says how each is measured "
                 "and why they differ); made by `python3 papers/scripts/talk_figures.py build/bin/ldlpgs --figures "
                 "%s/figures`.\n\n%s\n",
                 o_.out.c_str(), text.c_str());
    std::fprintf(stdout, "\nThe talk's figures / ours:\n%s", text.c_str());
    for (const char* name : {"mechanism-50", "mechanism-50-shattered", "tracked-vehicle", "multi-wheeled-vehicle",
                             "multi-wheeled-vehicle-10-shards", "multi-wheeled-vehicle-shattered"})
      std::fprintf(md_, "![%s](figures/%s.png)\n\n", name, name);
  }

  // 4. Speed against error of the solvers on the hard cases.
  void speed_against_error() {
    stage_progress(4, std::string("speed against error (") + (o_.full ? "full" : "quick") + ") and stability");
    cases_ = o_.cases.empty() ? sweep_cases(o_.full) : o_.cases;
    seconds_ = o_.full ? 2.0 : 1.0;
    points_ = speed_vs_error(cases_, sweep_iterations(o_.full), seconds_, true);
    const std::string sweep_data = data_ + "/sweep.json";
    write_table(data_, "sweep", to_json(points_));
    std::fprintf(md_, "\n## 4. Speed against error\n\nEach hard case stepped for %g s of simulated time with pgs, "
                 "block-gs and ldl-pgs at several iteration counts, and direct (equality-only scenes); the median "
                 "solve time per step against the largest position error at the end (papers/speed-vs-error.md "
                 "reads the full version). Made by `build/bin/ldlpgs sweep%s --json-file FILE`; the points are in "
                 "`data/sweep.json`.\n\n",
                 seconds_, o_.full ? " --full" : "");
    print_sweep_summary(md_, points_);
    std::printf("\nSpeed against error, %g s simulated (best error reached; fastest run within 1 mm):\n", seconds_);
    print_sweep_summary(stdout, points_);
    if (!python_.empty()) {
      if (run_script(python_, "plot_speed_vs_error.py", shell_quoted(sweep_data) + " " + shell_quoted(figures_))) {
        for (const std::string& c : cases_) std::fprintf(md_, "\n![%s](figures/speed-vs-error-%s.png)\n", c.c_str(), c.c_str());
      } else {
        ok_ = false;
      }
    }
    std::fprintf(md_, "\n### Every run\n\n");
    print_sweep_markdown(md_, points_);
  }

  // 5. The mass ratio at which each solver breaks.
  void stability_stage() {
    stage_progress(5, "where each solver breaks");
    breaks_ = stability(cases_, 10, seconds_, true);
    write_table(data_, "stability", to_json(breaks_));
    std::fprintf(md_, "\n## 5. Where each solver breaks\n\nThe heaviest body of each case made 10, 100, ... times "
                 "heavier (mass and inertia) until the run fails: a non-finite state, a position error above 1 cm, "
                 "or an energy blow-up; 10 iterations, dt <= 2.5 ms, %g s. Made by `build/bin/ldlpgs sweep%s "
                 "--stability`.\n\n",
                 seconds_, o_.full ? " --full" : "");
    print_stability_markdown(md_, breaks_);
  }

  // 6. Two runs as pages that play them (`ldlpgs view`), embedded in index.html: the tracked
  // vehicle driving its tracks, and a vehicle driving on the ground (contacts).
  void viewer_pages() {
    stage_progress(6, "two runs to watch");
    std::fprintf(md_, "\n## 6. Watch it move\n\nTwo runs as pages that play them in a browser (three.js inlined: "
                 "they open offline); drag to orbit, the slider picks a time, the plot beside it is the joints' "
                 "separation and the contacts' penetration against time.\n");
    for (const char* scene : {"tracked-vehicle", "multi-wheeled-vehicle-on-ground"}) {
      const int steps = static_cast<int>(std::lround(kViewSeconds / load_mechanism(scene).timestep));
      const std::string page = std::string("view-") + scene + ".html";
      std::fprintf(stderr, "report: %s\n", page.c_str());
      const ViewPage v = write_view_page(scene, steps, out_dir_ + "/" + page);
      std::fprintf(md_, "\n### %s\n\n`build/bin/ldlpgs view %s --steps %d --html-file %s`: %g s simulated, %d "
                   "frames, %.1f MB; joints within %.2g m, deepest penetration %.2g m%s%s.\n\n"
                   "<iframe src=\"%s\" title=\"%s\" width=\"100%%\" height=\"520\"></iframe>\n\n[%s](%s)\n",
                   scene, scene, steps, page.c_str(), v.simulated_s, v.frames, static_cast<double>(v.bytes) / 1e6,
                   v.position_error_max_m, v.penetration_max_m, v.failure.empty() ? "" : "; it came apart at ",
                   v.failure.c_str(), page.c_str(), scene, page.c_str(), page.c_str());
    }
  }

  // 7. Gymnasium's MuJoCo models, each stepped by us and by MuJoCo (`ldlpgs models`), and index.html.
  void models_stage() {
    stage_progress(7, "Gymnasium's MuJoCo models beside MuJoCo, and index.html");
    std::fprintf(md_, "\n## 7. The field's own models\n\n");
    std::error_code ec;
    if (!mjcf_supported() || !fs::is_directory(report_files().models, ec)) {
      std::fprintf(md_, "Skipped: %s.\n", mjcf_supported() ? "the models are not installed" : "built without MuJoCo");
      return;
    }
    std::vector<std::string> paths;
    for (const auto& entry : fs::directory_iterator(report_files().models, ec))
      if (is_mjcf_path(entry.path().string())) paths.push_back(entry.path().string());
    std::sort(paths.begin(), paths.end());
    nlohmann::json rows = nlohmann::json::array();
    std::fprintf(md_, "The MuJoCo models of Gymnasium's environments (MIT), %d steps of each one's own timestep at "
                 "zero controls, by our ldl-pgs (talk schedule) and by MuJoCo stepping the same file. Made by "
                 "`build/bin/ldlpgs models tests/data/mjcf/gymnasium --steps %d`; motion against MuJoCo's RK4 in "
                 "%s.\n\n| model | ours (us/step) | MuJoCo (us/step) | joints (m) | joints (rad) | deepest "
                 "contact (m) | dropped, refused or failed |\n|---|---|---|---|---|---|---|\n",
                 kModelSteps, kModelSteps, paper(out_dir_, "physics.md").c_str());
    for (const std::string& path : paths) {
      std::fprintf(stderr, "report: %s\n", fs::path(path).filename().c_str());
      const ModelRow r = check_model(path, kModelSteps, HybridSchedule::talk, /*allow_dropped=*/false);
      rows.push_back(row_json(r));
      const std::string note = !r.refused.empty() ? "refused: " + r.refused : !r.failure.empty() ? "failed: " + r.failure : r.dropped;
      if (!r.failure.empty()) ok_ = false;
      std::fprintf(md_, "| %s | %.1f | %.1f | %.2g | %.2g | %.2g | %s |\n", fs::path(path).stem().c_str(), r.step_us,
                   r.mujoco_step_us, r.error.position_max, r.error.angular_max, r.penetration_max_m, note.c_str());
    }
    write_table(data_, "models", rows);
  }

  // index.md (head, key findings, the stages' sections), index.html; the exit code.
  int finish() {
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    std::fprintf(md_, "\nThe report took %.0f s.\n", elapsed);
    index_.reset();  // body_.data and body_.size now final
    {
      std::ofstream file(index_path_);
      file << head_ << key_findings(out_dir_, results_, checks_, talk_rows_, points_, breaks_)
           << std::string_view(body_.data, body_.size);
      finish_writing(file, index_path_, "the report");
    }
    if (!python_.empty())
      ok_ = run_script(python_, "render_html.py", shell_quoted(index_path_) + " " + shell_quoted(out_dir_ + "/index.html")) && ok_;
    // The paths as the user named the directory (relative stays relative): nothing of this
    // machine's layout in what is printed, or pasted into the README.
    const fs::path shown(o_.out);
    std::printf("\nReport: %s%s (%.0f s)\n", (shown / "index.md").string().c_str(),
                python_.empty() ? "" : (", " + (shown / "index.html").string()).c_str(), elapsed);
    return ok_ ? 0 : 1;
  }

  const ReportOptions& o_;
  std::chrono::steady_clock::time_point start_;
  std::vector<std::string> names_, files_;
  const OrderingInfo* verify_ordering_ = nullptr;
  std::string out_dir_, figures_, data_, index_path_, head_, python_;
  struct Buffer {  // declared before the stream: freed after the stream's close sets it
    char* data = nullptr;
    size_t size = 0;
    ~Buffer() { std::free(data); }
  } body_;
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> index_;
  std::FILE* md_ = nullptr;
  bool ok_ = true;
  std::vector<std::pair<Problem, std::vector<Row>>> results_;
  std::vector<std::pair<std::string, Verification>> checks_;
  int talk_rows_ = 0;
  std::vector<std::string> cases_;
  double seconds_ = 1;
  std::vector<SweepPoint> points_;
  std::vector<Breakdown> breaks_;
};

}  // namespace

Command add_report_command(CLI::App& app) {
  auto o = std::make_shared<ReportOptions>();
  CLI::App* cmd = app.add_subcommand("report", "The main job: orderings, CHOLMOD verification, the talk's table, "
                                                "speed against error; writes a report directory");
  cmd->add_option("--matrices", o->matrices, "Directory of Matrix Market files")->capture_default_str();
  add_list_option(cmd, "--sizes", &o->sizes, "Constraint counts of the generated mechanisms")
      ->capture_default_str()
      ->check(integer_in(1, std::numeric_limits<int>::max()));
  add_ordering_option(cmd, &o->orderings, "Orderings compared", true);
  cmd->add_flag("--markdown", o->markdown, "Markdown tables on standard output (papers/orderings.md)");
  cmd->add_flag("--cholmod", o->cholmod, "Add CHOLMOD's counts for each permutation");
  cmd->add_option("--verify", o->verify, "Ordering of the factorizations verified against CHOLMOD")->capture_default_str();
  cmd->add_option("--out-dir", o->out, "Report directory to write")->capture_default_str();
  add_alias(cmd, "--out", &o->out);
  cmd->add_flag("--full", o->full, "The paper's speed-against-error sweep (papers/speed-vs-error.md) instead of the quick one");
  add_list_option(cmd, "--cases", &o->cases, "Scenes of the speed-against-error and stability stages (default: the "
                                             "hard cases)");
  cmd->add_flag("--no-figures", o->no_figures, "Skip the stages that need python3 (talk's table, plots, index.html)");
  return [o] { return Report(*o).run(); };
}

}  // namespace ldlpgs::cli
