// Bad input to the program, one named test per kind, grouped by kind: one line on stderr naming
// the file, line and problem, exit code 2, no crash.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "tests/support/program.h"

// In the helpers' namespace (tests/support/program.h, temp_files.h): run, json_of, temp_path...
namespace ldlpgs::testing {
namespace {

// ---- unknown names: scenes, cases, families, solvers, orderings, kernels, options ----

TEST(LdlpgsBadInput, UnknownScene) { expect_input_error("step no-such-scene", {"no-such-scene", "built-in"}); }

TEST(LdlpgsBadInput, SweepUnknownScene) { expect_input_error("sweep --cases no-such-scene", {"no-such-scene"}); }

TEST(LdlpgsBadInput, SpyUnknownScene) { expect_input_error("spy no-such-scene --json-file x.json", {"no-such-scene"}); }

TEST(LdlpgsBadInput, ReportUnknownCase) {
  expect_input_error("report --sizes 12 --cases no-such-scene --no-figures --out-dir " + temp_path("r"), {"no-such-scene"});
}

TEST(LdlpgsBadInput, UnknownFamily) {
  expect_input_error("verify wheel:10", {"wheel", "chain"});
}

TEST(LdlpgsBadInput, UnknownSolver) { expect_input_error("step pendulum --solver magic", {"--solver", "magic", "ldl-pgs"}); }

TEST(LdlpgsBadInput, UnknownFrictionCone) {
  expect_input_error("step box-stack-1000 --friction-cone cone", {"--friction-cone", "cone", "disk pyramid"});
}

TEST(LdlpgsBadInput, UnknownContactSchedule) {
  expect_input_error("step box-stack-1000 --contact-schedule fast", {"--contact-schedule", "fast", "block-gs"});
}

TEST(LdlpgsBadInput, UnknownOrdering) {
  expect_input_error("order " + kMatrices + "/bcsstk01.mtx --ordering mda,colamd", {"colamd", "meca"});
}

TEST(LdlpgsBadInput, UnknownKernels) { expect_input_error("bench chain:10 --kernels avx1024", {"--kernels", "avx1024"}); }

TEST(LdlpgsBadInput, UnknownOption) {
  expect_input_error("order " + kMatrices + "/bcsstk01.mtx --frobnicate", {"frobnicate"});
}

// ---- numbers out of range ----

TEST(LdlpgsBadInput, BadConstraintCount) {
  expect_input_error("bench chain:-3", {"chain:-3", "positive"});
}

TEST(LdlpgsBadInput, ZeroBlockSize) {
  expect_input_error("order " + kMatrices + "/bcsstk01.mtx --blocks 0", {"0"});
}

TEST(LdlpgsBadInput, SmallSupernodeRowsBelowOne) {
  expect_input_error("bench chain:10 --small-supernode-max-rows 0", {"--small-supernode-max-rows", "must be an integer in [1, 1048576]"});
}

TEST(LdlpgsBadInput, RelaxMaxZerosOutsideZeroToOne) {
  expect_input_error("bench chain:10 --relax-max-zeros 1.5", {"--relax-max-zeros", "must be a finite number in [0, 1]"});
}

// Number options: NaN, infinities and values out of range are refused in one short line naming
// the option (CLI11's own checks let nan through and spelt out DBL_MAX in 310 digits).
TEST(LdlpgsBadInput, BenchNumberOptionsOutOfRange) {
  expect_input_error("bench chain:10 --relax-max-zeros nan", {"--relax-max-zeros", "finite number in [0, 1]"});
  expect_input_error("bench chain:10 --rsi-max-per-entry inf", {"--rsi-max-per-entry", "finite number"});
  const Result r = run("bench chain:10 --supernode-min-rows -1");
  EXPECT_EQ(r.code, 2);
  EXPECT_LT(r.err.size(), 120u) << r.err;
  EXPECT_NE(r.err.find("--supernode-min-rows: '-1': must be an integer in [0, "), std::string::npos) << r.err;
}

TEST(LdlpgsBadInput, VerifyToleranceNotFinite) {
  expect_input_error("verify chain:10 --backward-tolerance inf", {"--backward-tolerance", ">= 0"});
  expect_input_error("verify chain:10 --tolerance nan", {"--tolerance"});
  expect_input_error("verify chain:10 --per-condition -1", {"--per-condition"});
}

TEST(LdlpgsBadInput, NegativeCertifyTimeLimit) {
  expect_input_error("order chain:5 --certify --certify-time-limit-s -1", {"--certify-time-limit-s"});
}

TEST(LdlpgsBadInput, NonPositiveTimestep) { expect_input_error("step pendulum --timestep -1", {"--timestep"}); }

// 0 and -1 had been read as "the default" (the scene's timestep, 8 iterations, shards by flops).
TEST(LdlpgsBadInput, StepZeroTimestep) { expect_input_error("step pendulum --timestep 0", {"--timestep", "> 0"}); }

TEST(LdlpgsBadInput, StepNegativePostStabilize) {
  expect_input_error("step pendulum --post-stabilize -1", {"--post-stabilize"});
}

TEST(LdlpgsBadInput, StepOwnFactorWithRefactor) {
  expect_input_error("step pendulum --post-stabilize-own-factor --post-stabilize-refactor",
                     {"--post-stabilize-own-factor", "--post-stabilize-refactor", "exclude"});
}

TEST(LdlpgsBadInput, FactorContactsAfterNegative) {
  expect_input_error("step box-stack-1000 --factor-contacts-after -1", {"--factor-contacts-after"});
  expect_input_error("step box-stack-1000 --position-schur-after -1", {"--position-schur-after"});
}

TEST(LdlpgsBadInput, ContactMarginOutOfRange) {
  for (const char* m : {"-0.01", "nan", "2"}) expect_input_error(std::string("step pyramid-10 --contact-margin-m ") + m, {"--contact-margin-m"});
}

// nan, inf and 1e308 had run one step each and said "failed: energy" with exit 0.
TEST(LdlpgsBadInput, SweepSecondsOutOfRange) {
  for (const char* s : {"nan", "0", "1e308"}) expect_input_error(std::string("sweep --cases chain-10 --seconds ") + s, {"--seconds"});
}

TEST(LdlpgsBadInput, SweepZeroIterations) { expect_input_error("sweep --cases chain-10 --iterations 0", {"--iterations"}); }

// 1e308 s overflowed the step count (0 steps, NaN printed); 1e-300 s is less than one step.
TEST(LdlpgsBadInput, PeersSecondsOutsideTheSteps) {
  expect_input_error("peers pendulum --seconds 1e308", {"--seconds", "at most 10^6"});
  expect_input_error("peers pendulum --seconds 1e-300", {"--seconds", "at least 1"});
}

TEST(LdlpgsBadInput, ZeroShards) {
  expect_input_error("spy chain-10 --shards 0 --json-file " + temp_path("x.json"), {"--shards", "[2, 64]"});
}

TEST(LdlpgsBadInput, StepShardsOutOfRange) {
  expect_input_error("step multi-wheeled-vehicle --shards 65", {"--shards", "must be an integer in [2, 64]"});
}

TEST(LdlpgsBadInput, SpyShardsOutOfRange) {
  expect_input_error("spy multi-wheeled-vehicle --shards 1 --json-file " + temp_path("x.json"), {"--shards", "must be an integer in [2, 64]"});
}

TEST(LdlpgsBadInput, ExportShatterThresholdBelowOne) {
  expect_input_error("export mechanism-50 --shatter 0 --matrix-file x.mtx --blocks-file x.blocks", {"--shatter"});
}

TEST(LdlpgsBadInput, SpyShatterThresholdBelowOne) {
  expect_input_error("spy mechanism-50 --shatter 0 --json-file " + temp_path("x.json"), {"--shatter"});
}

// ---- options that do not fit the problem or each other ----

TEST(LdlpgsBadInput, DirectSolverOnAContactScene) {
  expect_input_error("step pyramid-2 --solver direct", {"direct", "body \"ground\"", "shapes"});
}

TEST(LdlpgsBadInput, DirectOnInequalities) {
  expect_input_error("step ragdoll --solver direct", {"direct", "ragdoll", "angular_limit"});
}

// A generated mechanism has one block per constraint: a partition given for it had been ignored.
TEST(LdlpgsBadInput, PartitionOptionsOnAGeneratedMechanism) {
  expect_input_error("order grid:10 --blocks 0", {"grid:10", "--blocks 0"});
  expect_input_error("verify grid:10 --max-block 3", {"grid:10", "--max-block"});
}

TEST(LdlpgsBadInput, SpyShatterAndNoShatter) {
  expect_input_error("spy mechanism-50 --shatter 5 --no-shatter --json-file " + temp_path("x.json"),
                     {"--shatter", "--no-shatter"});
}

// ---- input files and directories that are missing ----

TEST(LdlpgsBadInput, MissingFile) {
  expect_input_error("order /nonexistent/m.mtx", {"/nonexistent/m.mtx", "cannot open"});
}

TEST(LdlpgsBadInput, ReportMatricesDirectoryMissing) {
  expect_input_error("report --matrices /nonexistent/dir --sizes 10", {"/nonexistent/dir"});
}

// ---- Matrix Market files ----

TEST(LdlpgsBadInput, MalformedMatrixMarket) {
  const std::string f = temp_file("bad.mtx", "%%MatrixMarket matrix coordinate real symmetric\n3 3 2\n1 1 x\n2 2 1\n");
  expect_input_error("order " + f, {f + ":3:"});
}

TEST(LdlpgsBadInput, TruncatedMatrixMarket) {
  const std::string f = temp_file("short.mtx", "%%MatrixMarket matrix coordinate real symmetric\n3 3 3\n1 1 1\n2 2 1\n");
  expect_input_error("order " + f, {f, "3"});
}

TEST(LdlpgsBadInput, NanValue) {
  const std::string f = temp_file("nan.mtx", "%%MatrixMarket matrix coordinate real symmetric\n2 2 2\n1 1 nan\n2 2 1\n");
  expect_input_error("order " + f, {f + ":3:"});
}

TEST(LdlpgsBadInput, UnsymmetricMatrix) {
  expect_input_error("order " + kMatrices + "/Pd.mtx", {"Pd.mtx:", "not symmetric"});
}

TEST(LdlpgsBadInput, VerifyUnsymmetricMatrix) {
  expect_input_error("verify " + kMatrices + "/Pd.mtx", {"Pd.mtx:", "not symmetric"});
}

// ---- blocks files ----

TEST(LdlpgsBadInput, BlockFileDoesNotSumToN) {
  const std::string blocks = temp_file("blocks.txt", "6\n6\n6\n");
  expect_input_error("order " + kMatrices + "/bcsstk01.mtx --blocks " + blocks, {blocks, "18", "48"});
}

TEST(LdlpgsBadInput, BlockFileBadLine) {
  const std::string blocks = temp_file("blocks.txt", "6\nsix\n");
  expect_input_error("order " + kMatrices + "/bcsstk01.mtx --blocks " + blocks, {blocks + ":2:"});
}

// ---- scene files ----

TEST(LdlpgsBadInput, SceneWithUnknownBody) {
  const std::string path = temp_file("bad.json", R"({"name": "bad", "bodies": [{"name": "a", "mass": 1,
    "inertia": [1, 1, 1], "position": [0, 0, 0]}], "constraints": [{"type": "ball", "bodies": ["a", "ghost"],
    "anchor": [0, 0, 0]}]})");
  expect_input_error("step " + path, {"bad.json", "constraints[0]", "ghost"});
}

TEST(LdlpgsBadInput, SceneWithZeroMass) {
  const std::string path = temp_file("zero.json", R"({"name": "z", "bodies": [{"name": "a", "mass": 0,
    "inertia": [1, 1, 1], "position": [0, 0, 0]}], "constraints": []})");
  expect_input_error("export " + path + " --matrix-file x.mtx --blocks-file x.blocks", {"zero.json", "bodies[0]", "mass"});
}

// export had written a 0 x 0 matrix that order then refused.
TEST(LdlpgsBadInput, ExportWithoutEqualityConstraints) {
  const std::string scene = temp_file("no-constraints.json", R"({"name": "empty", "bodies": [], "constraints": []})");
  expect_input_error("export " + scene + " --matrix-file " + temp_path("e.mtx") + " --blocks-file " + temp_path("e.blocks"),
                     {"no equality constraints"});
}

TEST(LdlpgsBadInput, SpySceneWithoutEqualityConstraints) {
  const std::string path = temp_file("ropes.json", R"({"name": "ropes", "bodies": [{"name": "post", "static": true,
    "position": [0, 0, 0]}, {"name": "bob", "mass": 1, "inertia": [1, 1, 1], "position": [0, -1, 0]}],
    "constraints": [{"type": "rope", "bodies": ["post", "bob"], "anchors": [[0, 0, 0], [0, -1, 0]]}]})");
  expect_input_error("spy " + path + " --out " + temp_path("x.json"), {"ropes.json", "no equality constraints"});
}

// ---- MJCF models: built with MuJoCo, or refusing every MJCF file without it ----

#ifdef LDLPGS_HAVE_MUJOCO

TEST(LdlpgsBadInput, StepMjcfWithAConstructWeCannotRepresent) {
  const std::string path = temp_file("coupled.xml", R"(<mujoco><worldbody><body name="arm"><joint name="a"/>
    <geom size=".1"/><body name="hand"><joint name="b"/><geom size=".1"/></body></body></worldbody>
    <equality><joint name="gear" joint1="a" joint2="b"/></equality></mujoco>)");
  expect_input_error("step " + path, {"coupled.xml", "equality \"gear\" (joint)", "couples joint values"});
}

TEST(LdlpgsBadInput, ModelsOfAPathThatIsNotThere) {
  expect_input_error("models /nonexistent/model.xml", {"/nonexistent/model.xml", "no such file or folder"});
}

TEST(LdlpgsBadInput, ModelsOfAFolderWithoutModels) {
  const std::string dir = temp_path("no-models");
  std::filesystem::create_directories(dir);
  expect_input_error("models " + dir, {"no-models", "no MJCF (*.xml) files"});
}

TEST(LdlpgsBadInput, ModelsWithAnUnknownSchedule) {
  expect_input_error("models " + kGymnasium + "/point.xml --schedule fast", {"--schedule fast", "unknown schedule"});
}

TEST(LdlpgsBadInput, ExportUnparsableMjcf) {
  const std::string path = temp_file("broken.xml", "<mujoco><worldbody>");
  expect_input_error("export " + path + " --matrix-file x.mtx --blocks-file x.blocks", {"broken.xml", "MuJoCo cannot load it"});
}

#else

TEST(LdlpgsBadInput, MjcfWithoutMuJoCo) {
  const std::string path = temp_file("model.xml", "<mujoco/>");
  expect_input_error("step " + path, {"model.xml", "need MuJoCo"});
}

#endif

// ---- outputs that cannot be written ----

// A full disk shows only when the stream flushes: these had exited 0 with an empty file.
TEST(LdlpgsBadInput, WriteToAFullDevice) {
  expect_input_error("spy chain-10 --json-file /dev/full", {"/dev/full", "cannot write"});
  expect_input_error("step pendulum --steps 3 --trace-file /dev/full", {"/dev/full", "cannot write"});
  expect_input_error("export chain-10 --matrix-file " + temp_path("full.mtx") + " --blocks-file /dev/full",
                     {"/dev/full", "cannot write"});
}

// Standard output on a full disk: found only when flushed at the end, and had been exit 0.
TEST(LdlpgsBadInput, StandardOutputOnAFullDevice) {
  expect_input_error("order chain:10 --json >/dev/full", {"cannot write standard output"});
}

TEST(LdlpgsBadInput, SpyUnwritableOutput) {
  expect_input_error("spy pendulum --out /nonexistent/dir/spy.json", {"/nonexistent/dir/spy.json", "cannot write"});
}

TEST(LdlpgsBadInput, ReportEmptyOutDir) {
  expect_input_error("report --sizes 10 --cases pendulum --no-figures --out-dir ''", {"--out-dir"});
}

TEST(LdlpgsBadInput, ReportUnwritableDirectory) {
  expect_input_error("report --sizes 12 --out-dir /proc/no-such-report --no-figures", {"/proc/no-such-report"});
}

}  // namespace
}  // namespace ldlpgs::testing
