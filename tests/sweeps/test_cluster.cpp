// Cluster plans without Slurm: --array syntax, plan structure, the sbatch scripts' commands, run-local against an
// unsharded sweep, and status/resubmission decisions from the outputs on disk.
#include <catch2/catch.hpp>

#include <fstream>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "occsweep/core/splitmix64.hpp"
#include "occsweep/sweeps/cluster_estimate.hpp"
#include "occsweep/sweeps/cluster_slurm.hpp"
#include "occsweep/sweeps/grid.hpp"

#include "test_helpers.hpp"

using namespace occsweep;
namespace fs = std::filesystem;
using Catch::Matchers::Contains;

namespace {

/// Slurm's --array syntax read back: "0-3,7" -> {0,1,2,3,7}.
std::vector<std::uint64_t> expandRanges(const std::string& text) {
  std::vector<std::uint64_t> out;
  std::istringstream in(text);
  for (std::string part; std::getline(in, part, ',');) {
    const auto dash = part.find('-');
    const auto a = std::stoull(part.substr(0, dash)), b = dash == std::string::npos ? a : std::stoull(part.substr(dash + 1));
    for (auto i = a; i <= b; ++i) out.push_back(i);
  }
  return out;
}

PlanConfig sceneConfig(std::vector<std::string> datasets, std::vector<PlanGrid> grids) {
  PlanConfig c;
  c.occsweep = occsweep::test::builtCli();
  c.datasets = std::move(datasets);
  c.generate = "scene --out {out} --seed {seed}";
  c.generate_kind = OutputKind::Dataset;
  c.generate_out = "data/{dataset}";
  c.blocks = 1;
  c.ranked = false;
  c.sets = {"."};
  c.group_set.clear();
  c.grids = std::move(grids);
  return c;
}

}  // namespace

TEST_CASE("arrayRanges gives Slurm's --array syntax that reads back to the same ids over many random sets") {
  SplitMix64 rng(7);
  for (int round = 0; round < 500; ++round) {
    std::set<std::uint64_t> ids;
    const auto n = rng.below(40);
    for (std::uint64_t i = 0; i < n; ++i) ids.insert(rng.below(60));
    const std::vector<std::uint64_t> sorted(ids.begin(), ids.end());
    const std::string text = arrayRanges(sorted);
    CHECK(expandRanges(text.empty() ? std::string() : text) == sorted);
    CHECK(text.find("--") == std::string::npos);
  }
  CHECK(arrayRanges({0, 1, 2, 3, 7, 9, 10}) == "0-3,7,9-10");
}

TEST_CASE("plan option parsers refuse what they cannot read and name it") {
  CHECK(parsePlanGrid("knn-opt").shards == 1);
  const PlanGrid g = parsePlanGrid("reduction:8:grouped");
  CHECK((g.name == "reduction" && g.shards == 8 && g.grouped));
  CHECK(parsePlanGrid("/a/b.json:3").name == "/a/b.json");
  CHECK_THROWS_WITH(parsePlanGrid("knn-opt:0"), Contains("knn-opt:0"));
  CHECK_THROWS_WITH(parsePlanGrid("knn-opt:x"), Contains("number"));
  CHECK_THROWS_WITH(parsePlanGrid("knn-opt:2:split"), Contains("grouped"));
  CHECK(expandTemplate("a {x}-{y}", {{"x", "1"}, {"y", "2"}}) == "a 1-2");
  CHECK_THROWS_WITH(expandTemplate("{nope}", {{"x", "1"}}), Contains("{nope}") && Contains("{x}"));
  CHECK_THROWS_WITH(expandTemplate("{x", {{"x", "1"}}), Contains("without"));
  PlanConfig c = sceneConfig({"a"}, {{"octomap-opt", 21, false}});
  CHECK_THROWS_WITH(buildPlan(c), Contains("21 shards but only 20 maps"));
  c.grids = {{"no-such-grid", 1, false}};
  CHECK_THROWS(buildPlan(c));
  c.grids = {{"knn-opt", 2, false}, {"knn-opt", 3, false}};
  CHECK_THROWS_WITH(buildPlan(c), Contains("twice"));
  // Two ungrouped grids of one method: the report (compare) takes one result per method and set.
  const fs::path mine = test::scratch("cluster-plan-methods") / "knn-mine.json";
  {
    std::ifstream in(occsweep::test::sourceTree().string() + "/sweeps/grids/knn-opt.json");
    nlohmann::json g = nlohmann::json::parse(in);
    g["name"] = "knn-mine";
    std::ofstream(mine) << g.dump();
  }
  c.grids = {{"knn-opt", 1, false}, {mine.string(), 1, false}};
  CHECK_THROWS_WITH(buildPlan(c), Contains("knn-opt and knn-mine are both of method knn"));
  c.grids = {{"knn-opt", 1, false}, {mine.string(), 1, true}};  // grouped: not in the report
  CHECK_NOTHROW(buildPlan(c));
}

TEST_CASE("a plan has every shard once and merges take exactly their shards and plan.json reads back the same") {
  SplitMix64 rng(11);
  for (int round = 0; round < 20; ++round) {
    const auto nd = 1 + rng.below(4), so = 1 + rng.below(20), sk = 1 + rng.below(30), sr = 1 + rng.below(5);
    std::vector<std::string> names;
    // Appended piece by piece: "d" + std::to_string trips GCC 12's -Wrestrict false positive here.
    for (std::uint64_t i = 0; i < nd; ++i) names.push_back(std::string("d").append(std::to_string(i)));
    const ClusterPlan p = buildPlan(sceneConfig(names, {{"octomap-opt", so, false}, {"knn-opt", sk, false},
                                                        {"reduction", sr, true}}));
    REQUIRE(p.stages.size() == 4);
    CHECK(stageNamed(p, "generate").tasks.size() == nd);
    const auto& sweep = stageNamed(p, "sweep").tasks;
    CHECK(sweep.size() == nd * (so + sk + sr));
    std::set<std::string> outputs;
    for (const auto& t : sweep) outputs.insert(t.output);
    CHECK(outputs.size() == sweep.size());
    std::set<std::string> merged_inputs;
    for (const auto& m : stageNamed(p, "merge").tasks) {
      const auto shards = m.expect_grid == "octomap-opt" ? so : m.expect_grid == "knn-opt" ? sk : sr;
      CHECK(m.inputs.size() == shards);
      for (std::size_t k = 0; k < m.inputs.size(); ++k) {
        CHECK(m.inputs[k].find("shard-" + std::to_string(k) + "-of-" + std::to_string(shards)) != std::string::npos);
        merged_inputs.insert(m.inputs[k]);
      }
    }
    CHECK(merged_inputs == outputs);  // no shard left out, none merged twice
    // The report compares the optimisation grids only (grouped reduction results answer another question).
    CHECK(stageNamed(p, "report").tasks.at(0).inputs.size() == 2 * nd);
    const auto dir = test::scratch("cluster-plan-io");
    writePlan(p, dir, false);
    const ClusterPlan back = readPlan(dir);
    for (const auto& s : p.stages) CHECK(sbatchScript(back, stageNamed(back, s.name)) == sbatchScript(p, s));
    for (const char* stage : {"sweep", "merge"})
      for (std::size_t i = 0; i < stageNamed(p, stage).tasks.size(); ++i) {
        const auto& work = stageNamed(p, stage).tasks[i].expect_work;
        REQUIRE(work.has_value());
        CHECK(work->group.has_value() == (stageNamed(p, stage).tasks[i].expect_grid == "reduction"));
        CHECK(stageNamed(back, stage).tasks[i].expect_work == work);
      }
    // A plan whose expected work was edited to a setting no sweep can have is refused as it is read, naming the field
    // (previous code: a resolution of -1 was read, its tasks run, and each failed as "other work").
    for (const char* key : {"resolution", "s_c"}) {
      const auto edited_dir = test::scratch(std::string("cluster-plan-bad-") + key);
      writePlan(p, edited_dir, false);
      nlohmann::json j = nlohmann::json::parse(test::bytesOf(edited_dir / "plan.json"));
      for (auto& stage : j.at("stages"))
        for (auto& task : stage.at("tasks"))
          if (task.contains("expect") && task.at("expect").contains("work")) task["expect"]["work"][key] = -1;
      std::ofstream(edited_dir / "plan.json", std::ios::trunc) << j.dump(1) << '\n';
      CHECK_THROWS_WITH(readPlan(edited_dir), Contains(std::string("expect.work.") + key + ": must be a finite number > 0"));
    }
    writePlan(p, dir, false);  // the same plan again is fine
    ClusterPlan other = p;
    other.slurm.mem = "9G";
    CHECK_THROWS_WITH(writePlan(other, dir, false), Contains("different plan"));
  }
}

TEST_CASE("each sbatch array task runs exactly its task's command with its arguments intact") {
  const auto dir = test::scratch("cluster-sbatch");
  const fs::path echo = dir / "print-args.sh";
  std::ofstream(echo) << "#!/bin/sh\nfor a in \"$@\"; do printf '%s\\n' \"$a\"; done\n";
  fs::permissions(echo, fs::perms::owner_all);
  PlanConfig c = sceneConfig({"x"}, {{"octomap-opt", 3, false}, {"knn-opt", 2, false}});
  c.experiment = "sweep";
  c.datasets = {(dir / "it's a data set").string()};
  c.occsweep = echo.string();
  const ClusterPlan p = buildPlan(c);
  writePlan(p, dir / "plan", false);
  for (const auto& stage : p.stages)
    for (const auto& t : stage.tasks) {
      const auto r = [&] {
        const std::string cmd = "SLURM_ARRAY_TASK_ID=" + std::to_string(t.index) + " bash '" +
                                (dir / "plan" / "slurm" / (stage.name + ".sbatch")).string() + "'";
        FILE* pipe = ::popen(cmd.c_str(), "r");
        std::string out;
        char buf[4096];
        while (std::size_t n = std::fread(buf, 1, sizeof buf, pipe)) out.append(buf, n);
        ::pclose(pipe);
        return out;
      }();
      std::string expected;
      for (std::size_t i = 1; i < t.argv.size(); ++i) expected += t.argv[i] + "\n";
      CHECK(r == expected);
    }
  CHECK(stageNamed(p, "sweep").tasks[0].argv.at(3) == (dir / "it's a data set").string());
}

TEST_CASE("run-local gives the unsharded sweep's numbers and status and resubmission follow the outputs on disk") {
  const auto dir = test::scratch("cluster-local");
  const fs::path plan_dir = dir / "plan";
  const ClusterPlan p = buildPlan(sceneConfig({"a", "b"}, {{"octomap-opt", 3, false}, {"knn-opt", 4, false}}));
  writePlan(p, plan_dir, false);
  REQUIRE(runLocal(p, plan_dir, 2) == 0);
  // Oracle: one unsharded sweep per data set, run directly.
  for (const char* d : {"a", "b"})
    for (const char* g : {"octomap-opt", "knn-opt"}) {
      const fs::path whole = dir / (std::string(d) + "-" + g + ".json");
      const auto r = test::runCli("sweep --quiet --dataset " + (plan_dir / "data" / d).string() + " --grid " + g +
                                  " --out " + whole.string());
      REQUIRE(r.exit_code == 0);
      const auto diff = resultDifferences(readResults(whole), readResults(plan_dir / "merged" / d / (std::string(g) + ".json")));
      CHECK(diff.empty());
    }
  auto status = planStatus(p, plan_dir, {}, {});
  for (const auto& row : status)
    for (const auto& t : row) CHECK(t.state == TaskState::Done);
  for (const auto& ids : tasksToRun(p, status)) CHECK(ids.empty());

  // A missing shard, a truncated shard (a half file) and a shard of another grid: exactly those and what is
  // downstream of them run again.
  const auto& sweep = stageNamed(p, "sweep").tasks;
  fs::remove(plan_dir / sweep[1].output);
  { std::ofstream(plan_dir / sweep[5].output, std::ios::trunc) << "{\"format\": \"occsweep-res"; }
  fs::copy_file(plan_dir / sweep[2].output, plan_dir / sweep[8].output, fs::copy_options::overwrite_existing);
  status = planStatus(p, plan_dir, {}, {});
  CHECK(status[1][1].state == TaskState::Missing);
  CHECK(status[1][5].state == TaskState::Invalid);
  CHECK(status[1][8].state == TaskState::Invalid);
  CHECK_THAT(status[1][8].detail, Contains("expected"));
  auto torun = tasksToRun(p, status);
  CHECK(torun[0].empty());
  CHECK(torun[1] == std::vector<std::uint64_t>{1, 5, 8});
  // Sweep tasks: a octomap 0-2, a knn 3-6, b octomap 7-9, b knn 10-13; merges: a octomap, a knn, b octomap, b knn.
  CHECK(torun[2] == std::vector<std::uint64_t>{0, 1, 2});
  CHECK(torun[3] == std::vector<std::uint64_t>{0});
  // Slurm's word: a live task is not run twice; a failed one is failed.
  const std::vector<Submission> subs = {{"sweep", "41", {1, 5, 8}}};
  status = planStatus(p, plan_dir, {{"41_1", {"RUNNING", ""}}, {"41_5", {"FAILED", "NonZeroExitCode"}}}, subs);
  CHECK(status[1][1].state == TaskState::Running);
  CHECK(status[1][5].state == TaskState::Failed);
  CHECK(status[1][8].state == TaskState::Invalid);
  CHECK(tasksToRun(p, status)[1] == std::vector<std::uint64_t>{5, 8});
  // run-local removes only outputs that pass their own check (docs/cluster.md, "Outputs stay in the plan folder"):
  // the half file and the other grid's shard are not this task's, so their tasks fail and the files stay as they
  // are; once the user removes them, run-local repairs exactly that, and the numbers are the same again.
  const std::string half = test::bytesOf(plan_dir / sweep[5].output), other = test::bytesOf(plan_dir / sweep[8].output);
  CHECK(runLocal(p, plan_dir, 2) == 2);
  CHECK(test::bytesOf(plan_dir / sweep[5].output) == half);
  CHECK(test::bytesOf(plan_dir / sweep[8].output) == other);
  CHECK(planStatus(p, plan_dir, {}, {})[1][1].state == TaskState::Done);
  fs::remove(plan_dir / sweep[5].output);
  fs::remove(plan_dir / sweep[8].output);
  REQUIRE(runLocal(p, plan_dir, 2) == 0);
  for (const auto& row : planStatus(p, plan_dir, {}, {}))
    for (const auto& t : row) CHECK(t.state == TaskState::Done);
  CHECK(resultDifferences(readResults(dir / "a-knn-opt.json"), readResults(plan_dir / "merged/a/knn-opt.json")).empty());
  // A shard redone after its merge makes the merge stale.
  fs::last_write_time(plan_dir / sweep[0].output, fs::file_time_type::clock::now() + std::chrono::seconds(5));
  status = planStatus(p, plan_dir, {}, {});
  CHECK(status[2][0].state == TaskState::Stale);
  CHECK(tasksToRun(p, status)[2] == std::vector<std::uint64_t>{0});
}

TEST_CASE("cluster commands refuse a folder without a plan and a failing task makes run-local exit non-zero") {
  const auto dir = test::scratch("cluster-errors");
  auto r = test::runCli("cluster status " + dir.string());
  CHECK(r.exit_code != 0);
  CHECK_THAT(r.output, Contains("plan.json"));
  r = test::runCli("cluster plan --out " + (dir / "p").string() + " --experiment sweep --dataset " +
                   (dir / "none").string() + " --grid octomap-opt:2");
  REQUIRE(r.exit_code == 0);
  r = test::runCli("cluster run-local " + (dir / "p").string() + " --threads 2");
  CHECK(r.exit_code != 0);
  CHECK_THAT(r.output, Contains("failed"));
  CHECK_FALSE(fs::exists(dir / "p" / "merged"));
}

TEST_CASE("occsweep's results of the task's grid and shard under other sweep settings are not taken as done") {
  // Old code: the check compared grid and shard only, so a shard swept at resolution 0.1 counted as done in a plan
  // that sweeps at 0.2, and its numbers went into the merge.
  const auto dir = test::scratch("cluster-other-work");
  REQUIRE(test::runCli("scene --out " + (dir / "ds").string() + " --scans 4 --width 16 --height 12").exit_code == 0);
  auto r = test::runCli("cluster plan --out " + (dir / "p").string() + " --experiment sweep --dataset " +
                        (dir / "ds").string() + " --grid octomap-opt:1 --sweep-args=--resolution,0.2");
  REQUIRE(r.exit_code == 0);
  const ClusterPlan plan = readPlan(dir / "p");
  const fs::path shard = dir / "p" / stageNamed(plan, "sweep").tasks.at(0).output;
  fs::create_directories(shard.parent_path());
  REQUIRE(test::runCli("sweep --quiet --dataset " + (dir / "ds").string() + " --grid octomap-opt --out " +
                       shard.string()).exit_code == 0);
  const std::string before = test::bytesOf(shard);
  r = test::runCli("cluster status " + (dir / "p").string());
  CHECK_THAT(r.output, Contains("invalid sweep[0]") && Contains("map.resolution 0.1, expected 0.2"));
  // run-local does not take it as done, and does not remove it either: the sweep task refuses another work's
  // results at its output without --force, and the file stays as it was.
  r = test::runCli("cluster run-local " + (dir / "p").string() + " --threads 1");
  CHECK(r.exit_code != 0);
  CHECK(test::bytesOf(shard) == before);
  CHECK_FALSE(fs::exists(dir / "p" / stageNamed(plan, "merge").tasks.at(0).output));
}

TEST_CASE("a task's output is removed before it runs again only when its kind's check proves it occsweep's") {
  // Old code: an output of kind `exists` (a generation task's ranking.json) was removed by its name alone.
  const auto dir = test::scratch("cluster-remove-own");
  std::ofstream(dir / "mine.json") << "{\"my\": \"file\"}\n";
  ClusterTask exists;
  exists.output = "mine.json";  // OutputKind::Exists, the default
  removeOwnOutput(exists, dir);
  CHECK(test::bytesOf(dir / "mine.json") == "{\"my\": \"file\"}\n");
  // A comparison task's output that is occsweep's comparison goes; a user's file under that name stays.
  ClusterTask report;
  report.output = "comparison.json";
  report.kind = OutputKind::Comparison;
  std::ofstream(dir / "comparison.json") << "{\"format\": \"occsweep-comparison\", \"rows\": []}\n";
  removeOwnOutput(report, dir);
  CHECK_FALSE(fs::exists(dir / "comparison.json"));
  std::ofstream(dir / "comparison.json") << "{\"my\": \"comparison\"}\n";
  removeOwnOutput(report, dir);
  CHECK(fs::exists(dir / "comparison.json"));
  // A user's symbolic link at the output's name stays, even to occsweep's own comparison.
  fs::remove(dir / "comparison.json");
  std::ofstream(dir / "own.json") << "{\"format\": \"occsweep-comparison\", \"rows\": []}\n";
  fs::create_symlink("own.json", dir / "comparison.json");
  removeOwnOutput(report, dir);
  CHECK(fs::is_symlink(fs::symlink_status(dir / "comparison.json")));
}

TEST_CASE("a task whose output leads out of the plan folder through a symbolic link is refused before it runs") {
  // Old code: run-local ran the merge, whose --force then replaced a user's results in the linked folder.
  const auto dir = test::scratch("cluster-output-inside");
  fs::create_directories(dir / "plan" / "sweeps");
  fs::create_directories(dir / "theirs");
  fs::create_directory_symlink("../theirs", dir / "plan" / "merged");
  ClusterTask inside, outside;
  inside.output = "sweeps/a.json";
  outside.output = "merged/a.json";
  CHECK_NOTHROW(requireOutputInside(inside, dir / "plan"));
  CHECK_THROWS_WITH(requireOutputInside(outside, dir / "plan"),
                    Contains("merged/a.json") && Contains("leads out of the plan folder"));
}

// docs/cluster.md, "A plan a real cluster runs": set-up lines, each stage's --mem and --time, arrays within Slurm's
// MaxArraySize (a task at array index task - OCCSWEEP_TASK_OFFSET). tests/cluster/slurm_e2e.sh submits such a plan to
// a real Slurm of MaxArraySize 4.
TEST_CASE("a stage's script names its task, runs the set-up lines, then the task its array index and offset name") {
  const auto dir = test::scratch("cluster-setup-lines");
  const fs::path echo = dir / "print-args.sh";
  std::ofstream(echo) << "#!/bin/sh\nfor a in \"$@\"; do printf '%s\\n' \"$a\"; done\n";
  fs::permissions(echo, fs::perms::owner_all);
  PlanConfig c = sceneConfig({"x"}, {{"octomap-opt", 5, false}});
  c.experiment = "sweep";
  c.datasets = {(dir / "ds").string()};
  c.occsweep = echo.string();
  c.slurm.setup = {"echo set-up one", "X=$UNSET_BY_SLURM; echo \"set-up two $X\""};  // before set -u
  c.slurm.mem = "1G";
  c.slurm.stage_mem = {{"sweep", "3G"}};
  c.slurm.stage_time = {{"merge", "00:05:00"}};
  c.slurm.array_throttle = 2;
  c.slurm.max_array_size = 3;
  const ClusterPlan p = buildPlan(c);
  writePlan(p, dir / "plan", false);
  const ClusterPlan back = readPlan(dir / "plan");
  CHECK(back.slurm.setup == c.slurm.setup);
  CHECK(back.slurm.stage_mem == c.slurm.stage_mem);
  CHECK(back.slurm.stage_time == c.slurm.stage_time);
  CHECK(back.slurm.array_throttle == 2);
  CHECK(back.slurm.max_array_size == 3);

  const std::string sweep_script = test::bytesOf(dir / "plan" / "slurm" / "sweep.sbatch");
  const std::string merge_script = test::bytesOf(dir / "plan" / "slurm" / "merge.sbatch");
  CHECK_THAT(sweep_script, Catch::Contains("#SBATCH --mem=3G\n#SBATCH --time=01:00:00\n"));
  CHECK_THAT(merge_script, Catch::Contains("#SBATCH --mem=1G\n#SBATCH --time=00:05:00\n"));
  // After set -e (a failing line stops the task), before set -u (module scripts read unset variables).
  CHECK(sweep_script.find("set -eo pipefail\n") < sweep_script.find("echo set-up one\n"));
  CHECK(sweep_script.find("echo set-up one\n") < sweep_script.find("set -u\n"));

  const ClusterStage& sweep = stageNamed(p, "sweep");
  REQUIRE(sweep.tasks.size() == 5);
  for (const auto& t : sweep.tasks) {
    const std::uint64_t offset = t.index - t.index % 3;  // MaxArraySize 3
    const std::string cmd = "SLURM_ARRAY_TASK_ID=" + std::to_string(t.index - offset) +
                            " OCCSWEEP_TASK_OFFSET=" + std::to_string(offset) + " bash '" +
                            (dir / "plan" / "slurm" / "sweep.sbatch").string() + "' 2>&1";
    std::string expected = "occsweep cluster plan: stage sweep, task " + std::to_string(t.index) +
                           "\nset-up one\nset-up two \n";
    for (std::size_t i = 1; i < t.argv.size(); ++i) expected += t.argv[i] + "\n";
    CHECK(test::runShell(cmd).output == expected);
  }
}

TEST_CASE("each stage's --mem and --time are parsed, and a stage the plan lacks or a value Slurm cannot read is refused") {
  std::string every = "1G";
  std::map<std::string, std::string> per_stage;
  parseStageValues({"2G", "sweep=3G", "merge=500M"}, "--mem", every, per_stage);
  CHECK(every == "2G");
  CHECK(per_stage == std::map<std::string, std::string>{{"sweep", "3G"}, {"merge", "500M"}});
  for (const std::vector<std::string>& bad : std::vector<std::vector<std::string>>{
           {"2G", "4G"}, {"sweep=1G", "sweep=2G"}, {"=3G"}, {"sweep="}, {""}}) {
    std::string e = "1G";
    std::map<std::string, std::string> s;
    CHECK_THROWS_WITH(parseStageValues(bad, "--mem", e, s), Catch::StartsWith("--mem '"));
  }

  PlanConfig c = sceneConfig({"x"}, {{"octomap-opt", 2, false}});
  c.experiment = "sweep";
  c.datasets = {"ds"};
  c.slurm.stage_time = {{"sweeep", "00:10:00"}};
  CHECK_THROWS_WITH(buildPlan(c), "--time sweeep=00:10:00: the plan has no stage 'sweeep' (its stages: sweep, merge, "
                                  "report)");
  c.slurm.stage_time.clear();
  c.slurm.mem = "2 G";
  CHECK_THROWS_WITH(buildPlan(c), Catch::Contains("--mem '2 G': a value may not hold spaces"));
  c.slurm.mem = "2G";
  c.slurm.setup = {"module load a\nmodule load b"};
  CHECK_THROWS_WITH(buildPlan(c), Catch::Contains("one line each"));
}

TEST_CASE("a path on a machine's own file system is named as local, as stat -f names it") {
  // Oracle: GNU stat's file system type names.
  const std::map<std::string, std::string> stat_name = {{"ext2/ext3", "ext2/3/4"}, {"xfs", "xfs"}, {"btrfs", "btrfs"},
                                                        {"tmpfs", "tmpfs"}, {"overlayfs", "overlay"}, {"zfs", "zfs"}};
  const auto dir = test::scratch("cluster-local-fs");
  for (const fs::path& p : {fs::path("/dev/shm"), fs::path("/proc"), fs::path("/"), dir}) {
    if (!fs::exists(p)) continue;
    const std::string type = test::runShell("stat -f -c %T " + test::shellQuoted(p)).output;
    const auto name = stat_name.find(type.substr(0, type.find('\n')));
    INFO(p << ": stat -f says " << type);
    if (name == stat_name.end()) CHECK_FALSE(localFileSystemOf(p).has_value());
    else CHECK(localFileSystemOf(p) == name->second);
  }
  CHECK_FALSE(localFileSystemOf("/proc").has_value());
}

// docs/cluster.md, "Measured tasks": run-local records each task's wall time, CPU time and peak memory, as the kernel
// counts them for the finished process (wait4). Oracle: generation tasks that hold `mb` MB and spin for `seconds` of
// their own CPU time (not wall time, which a loaded machine stretches while CPU time falls short) before they write their output (an `exists` output, so their check passes; the sweeps after them fail theirs).
namespace {

/// A plan whose tasks run the shell script `body` as their occsweep binary; a generation task gets `busy --out OUT`
/// ($3 is its output, of kind `exists`).
PlanConfig scriptedGeneration(const fs::path& dir, std::vector<std::string> datasets, const std::string& body) {
  const fs::path task = dir / "task.sh";
  std::ofstream(task) << "#!/bin/sh\n# busy --out OUT\n" << body;
  fs::permissions(task, fs::perms::owner_all);
  PlanConfig c = sceneConfig(std::move(datasets), {{"octomap-opt", 2, false}});
  c.occsweep = task.string();
  c.generate = "busy --out {out}";
  c.generate_kind = OutputKind::Exists;
  return c;
}

PlanConfig busyGeneration(const fs::path& dir, std::vector<std::string> datasets, int mb, double seconds) {
  // exec: the task's process is the one that holds the memory.
  std::ostringstream body;
  body << "exec python3 -c \"import os, sys, time\nb = bytearray(" << mb
       << " * 1024 * 1024)\nt = time.process_time()\nwhile time.process_time() - t < " << seconds
       << ": pass\nos.makedirs(os.path.dirname(sys.argv[3]) or '.', exist_ok=True)\n"
          "open(sys.argv[3], 'a').close()\" \"$@\"\n";
  return scriptedGeneration(dir, std::move(datasets), body.str());
}

}  // namespace

TEST_CASE("run-local records each task's wall time, CPU time and peak memory, and status sums them per stage") {
  const auto dir = test::scratch("cluster-measured");
  const ClusterPlan p = buildPlan(busyGeneration(dir, {"x", "y", "z"}, 150, 0.4));
  writePlan(p, dir / "plan", false);
  CHECK(runLocal(p, dir / "plan", 2) > 0);  // the generated "data sets" are empty files: the sweeps fail
  const std::vector<TaskMeasurement> measured = readMeasurements(dir / "plan");
  const auto& generate = stageNamed(p, "generate");
  std::size_t generated = 0;
  for (const TaskMeasurement& m : measured) {
    INFO(m.stage << "[" << m.task << "]");
    CHECK(m.exit_code == 0);
    CHECK(m.label == stageNamed(p, m.stage).tasks[m.task].label);
    if (m.stage != "generate") {
      CHECK_FALSE(m.succeeded);  // exit 0 but no results file: not a success
      continue;
    }
    ++generated;
    CHECK(m.succeeded);
    CHECK(m.wall_seconds >= 0.4);
    CHECK(m.cpu_seconds >= 0.3);
    CHECK(m.cpu_seconds <= m.wall_seconds + 0.1);
    CHECK(m.peak_bytes >= 150u * 1024 * 1024);
    CHECK(m.peak_bytes < 400u * 1024 * 1024);
  }
  CHECK(generated == generate.tasks.size());
  const std::vector<MeasuredStage> stages = measuredStages(p, measured);
  REQUIRE(stages.size() == p.stages.size());
  for (const MeasuredStage& st : stages) {
    CHECK(st.measured == (st.stage == "generate" ? 3u : 0u));  // failed sweeps are not measured successes
    double cpu = 0;
    for (const TaskMeasurement& m : measured)
      if (m.stage == st.stage && m.succeeded) cpu += m.cpu_seconds;
    CHECK(st.cpu_seconds == Approx(cpu));
    CHECK(st.longest_seconds <= st.wall_seconds);
  }
  const auto r = test::runCli("cluster status " + (dir / "plan").string());
  INFO(r.output);
  CHECK_THAT(r.output, Catch::Contains("measured by run-local"));
  CHECK_THAT(r.output, Catch::Contains("  stage generate: 3 of 3 tasks, wall "));
  CHECK_THAT(r.output, !Catch::Contains("  stage sweep: "));
}

// Old binary: the peak of a task that ended before run-local's second look (50 ms) was its first sample, taken as the
// task started (4 KB for a 16.6 MB task), and `status` and `--estimate-from` carried it on. Oracle: dd's 32 MiB
// buffer, filled from /dev/zero, in a task that ends within milliseconds.
TEST_CASE("run-local records a short task's peak memory as at least what the task touched") {
  const auto dir = test::scratch("cluster-measured-short");
  const std::uint64_t buffer = 32u << 20;
  const ClusterPlan p = buildPlan(scriptedGeneration(dir, {"x", "y", "z"}, "echo >> \"$3\" && exec dd if=/dev/zero "
                                                     "of=/dev/null bs=32M count=1 status=none\n"));
  writePlan(p, dir / "plan", false);
  fs::create_directories(dir / "plan" / "data");  // no mkdir in the task: it ends sooner
  const auto ran = test::runCli("cluster run-local " + (dir / "plan").string() + " --quiet");
  INFO(ran.output);
  std::size_t generated = 0;
  for (const TaskMeasurement& m : readMeasurements(dir / "plan")) {
    if (m.stage != "generate") continue;
    INFO(m.label << ": " << m.wall_seconds << " s");
    ++generated;
    CHECK(m.peak_bytes >= buffer);
    CHECK(m.peak_bytes < buffer + (256u << 20));  // KiB read as KiB: not 1024 times more
  }
  CHECK(generated == 3);
  const auto r = test::runCli("cluster status " + (dir / "plan").string());
  INFO(r.output);
  const auto at = r.output.find("peak memory ", r.output.find("  stage generate: 3 of 3 tasks"));
  REQUIRE(at != std::string::npos);
  CHECK(std::stod(r.output.substr(at + 12)) >= double(buffer) / 1e6);
}

TEST_CASE("cluster plan warns when the binary or the plan folder is on a file system compute nodes do not share") {
  const auto dir = test::scratch("cluster-local-warning");
  fs::create_directories(dir / "ds");
  const auto r = test::runCli("cluster plan --out " + (dir / "plan").string() + " --experiment sweep --dataset " +
                              (dir / "ds").string() + " --grid octomap-opt:1");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  const bool binary_local = localFileSystemOf(test::cliUnderTest()).has_value();
  const bool plan_local = localFileSystemOf(dir).has_value();
  CHECK((r.output.find("warning: the occsweep binary the tasks run, " + test::cliUnderTest()) != std::string::npos) ==
        binary_local);
  CHECK((r.output.find("warning: the plan folder, ") != std::string::npos) == plan_local);
  if (binary_local || plan_local) CHECK_THAT(r.output, Catch::Contains("run-local works as it is."));
  // /dev/shm is tmpfs wherever it exists: always local.
  if (fs::is_directory("/dev/shm") && localFileSystemOf("/dev/shm")) {
    const fs::path shm = fs::path("/dev/shm") / ("occsweep-plan-" + std::to_string(::getpid()));
    const auto s = test::runCli("cluster plan --out " + shm.string() + " --experiment sweep --dataset " +
                                (dir / "ds").string() + " --grid octomap-opt:1");
    fs::remove_all(shm);
    INFO(s.output);
    CHECK_THAT(s.output, Catch::Contains("warning: the plan folder, " + shm.string() +
                                         ", is on a file system local to this machine (tmpfs)"));
  }
}

// docs/cluster.md, "Cost estimate": each task of a new plan costs the mean of the measured tasks of its kind.
TEST_CASE("cluster plan --estimate-from carries measured tasks to a new plan and sets its --time and --mem") {
  const auto dir = test::scratch("cluster-estimate");
  const PlanConfig measured_config = busyGeneration(dir, {"x", "y"}, 100, 0.3);
  const ClusterPlan measured_plan = buildPlan(measured_config);
  writePlan(measured_plan, dir / "measured", false);
  CHECK(runLocal(measured_plan, dir / "measured", 2) > 0);  // generation succeeds, the sweeps fail
  const std::vector<TaskMeasurement> measured = readMeasurements(dir / "measured");
  double cpu = 0, wall = 0;
  std::uint64_t peak = 0;
  std::size_t generated = 0;
  for (const TaskMeasurement& m : measured)
    if (m.stage == "generate")
      cpu += m.cpu_seconds, wall += m.wall_seconds, peak = std::max(peak, m.peak_bytes), ++generated;
  REQUIRE(generated == 2);

  // Five data sets: five generation tasks of the measured kind; sweeps of a kind never run to success.
  PlanConfig c = measured_config;
  c.datasets = {"a", "b", "c", "d", "e"};
  const ClusterPlan plan = buildPlan(c);
  const std::vector<StageEstimate> e = estimatePlan(plan, measured_plan, measured);
  REQUIRE(e.size() == plan.stages.size());
  CHECK(e[0].stage == "generate");
  CHECK(e[0].tasks == 5);
  CHECK(e[0].modelled == 5);
  CHECK(e[0].cpu_seconds == Approx(5 * cpu / 2));
  CHECK(e[0].longest_seconds == Approx(wall / 2));
  CHECK(e[0].peak_bytes == peak);
  for (std::size_t s = 1; s < e.size(); ++s) CHECK(e[s].modelled == 0);
  // Another shard count is another kind: never scaled from the measured one.
  c.grids = {{"octomap-opt", 4, false}};
  for (const StageEstimate& s : estimatePlan(buildPlan(c), measured_plan, measured))
    if (s.stage == "sweep") CHECK(s.modelled == 0);

  // The margins, by hand; the wall time of stages in turn, each no shorter than its longest task.
  CHECK(timeWithMargin(30) == "00:10:00");
  CHECK(timeWithMargin(400) == "00:14:00");
  CHECK(timeWithMargin(7200) == "04:00:00");
  CHECK(memWithMargin(100u << 20) == "256M");
  CHECK(memWithMargin(1u << 30) == "1536M");
  const std::vector<StageEstimate> two = {{"a", 10, 10, 3600, 100, 0, {}}, {"b", 1, 1, 50, 50, 0, {}}};
  CHECK(estimatedWallSeconds(two, 64, 2) == Approx(100 + 50));
  CHECK(estimatedWallSeconds(two, 8, 2) == Approx(3600.0 / 8 + 50));
  // Three tasks of a minute on two slots take two minutes, not 90 s; on four, one minute.
  const std::vector<StageEstimate> three = {{"g", 3, 3, 180, 60, 0, {60, 60, 60}}};
  CHECK(estimatedWallSeconds(three, 2, 1) == Approx(120));
  CHECK(estimatedWallSeconds(three, 4, 1) == Approx(60));
  CHECK(estimatedWallSeconds(three, 4, 2) == Approx(120));
  CHECK(estimatedWallSeconds({{"g", 3, 3, 150, 70, 0, {70, 50, 30}}}, 2, 1) == Approx(80));  // 70 | 50 then 30

  // Through the command: the estimate printed, the modelled stage's limits set, a given one kept.
  std::string names;
  for (const std::string& n : c.datasets) names += " --name " + n;
  const std::string plan_args = "cluster plan --unranked --blocks 1 --generate 'busy --out {out}' --generate-out "
                                "'data/{dataset}' --grid octomap-opt:2 --occsweep " + c.occsweep + names;
  const auto r = test::runCli(plan_args + " --out " + (dir / "new").string() + " --estimate-from " +
                              (dir / "measured").string() + " --mem merge=2G");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  CHECK_THAT(r.output, Catch::Contains("estimate from the tasks run-local measured in " + (dir / "measured").string()));
  CHECK_THAT(r.output, Catch::Contains("  stage generate: 5 tasks, "));
  CHECK_THAT(r.output, Catch::Contains("  stage merge: 5 tasks, none of a kind measured there"));
  CHECK_THAT(test::bytesOf(dir / "new" / "slurm" / "generate.sbatch"),
             Catch::Contains("#SBATCH --mem=256M\n#SBATCH --time=00:10:00\n"));
  CHECK_THAT(test::bytesOf(dir / "new" / "slurm" / "merge.sbatch"), Catch::Contains("#SBATCH --mem=2G\n"));
  // A folder where nothing ran: refused, saying what to do.
  fs::create_directories(dir / "unrun");
  writePlan(measured_plan, dir / "unrun", false);
  const auto none = test::runCli(plan_args + " --out " + (dir / "new2").string() + " --estimate-from " +
                                 (dir / "unrun").string());
  CHECK(none.exit_code == 2);
  CHECK_THAT(none.output, Catch::Contains("run `occsweep cluster run-local " + (dir / "unrun").string() + "` first"));
  // No measured run: the plan says it has no estimate, and which limits each stage got.
  const auto plain = test::runCli(plan_args + " --out " + (dir / "new3").string() + " --time merge=02:00:00");
  INFO(plain.output);
  REQUIRE(plain.exit_code == 0);
  CHECK_THAT(plain.output, Catch::Contains("cost: not estimated (no --estimate-from)"));
  CHECK_THAT(plain.output, Catch::Contains("  stage generate: --time 01:00:00 --mem 1G\n"));
  CHECK_THAT(plain.output, Catch::Contains("  stage merge: --time 02:00:00 --mem 1G\n"));
}

// docs/cluster.md, "Cost estimate": the report names one merged file per set and grid, so it costs per input.
TEST_CASE("the estimate carries a measured report to a plan of more data sets in proportion to its inputs") {
  const PlanConfig one = sceneConfig({"x"}, {{"octomap-opt", 1, false}, {"knn-opt", 2, false}});
  PlanConfig three = one;
  three.datasets = {"x", "y", "z"};
  const ClusterPlan measured_plan = buildPlan(one), plan = buildPlan(three);
  const ClusterTask& report = measured_plan.stages.back().tasks.at(0);
  REQUIRE(measured_plan.stages.back().name == "report");
  REQUIRE(report.inputs.size() == 2);
  const TaskMeasurement m{"report", report.index, report.label, report.argv, 3.0, 2.0, 50u << 20, 0, true};
  const std::vector<StageEstimate> e = estimatePlan(plan, measured_plan, {m});
  REQUIRE(e.back().stage == "report");
  CHECK(e.back().modelled == 1);
  CHECK(e.back().cpu_seconds == Approx(3 * 2.0));  // 6 inputs against 2
  CHECK(e.back().longest_seconds == Approx(3 * 3.0));
  CHECK(e.back().peak_bytes == (50u << 20));
  // A report of other settings (another grid) is another kind.
  PlanConfig other = three;
  other.grids = {{"octomap-opt", 1, false}};
  CHECK(estimatePlan(buildPlan(other), measured_plan, {m}).back().modelled == 0);

  // select reads one ranking per block but ranks the same sets: it is not scaled by them, and another block count
  // is another kind.
  PlanConfig ranked = sceneConfig({"x"}, {{"octomap-opt", 1, false}});
  ranked.ranked = true, ranked.sets = {"rank-1"}, ranked.pcs_count = 8;
  const ClusterPlan ranked_one = buildPlan(ranked);
  const ClusterStage& select = ranked_one.stages.at(1);
  REQUIRE(select.name == "select");
  const ClusterTask& s = select.tasks.at(0);
  const TaskMeasurement sm{"select", s.index, s.label, s.argv, 3.0, 2.0, 50u << 20, 0, true};
  ranked.datasets = {"x", "y"};
  const std::vector<StageEstimate> same_blocks = estimatePlan(buildPlan(ranked), ranked_one, {sm});
  CHECK(same_blocks.at(1).modelled == 2);
  CHECK(same_blocks.at(1).cpu_seconds == Approx(2 * 2.0));
  ranked.blocks = 4;
  CHECK(estimatePlan(buildPlan(ranked), ranked_one, {sm}).at(1).modelled == 0);
}

TEST_CASE("status finds the tasks of an array submitted at an offset by their array index") {
  const auto dir = test::scratch("cluster-status-offset");
  PlanConfig c = sceneConfig({"x"}, {{"octomap-opt", 6, false}});
  c.experiment = "sweep";
  c.datasets = {(dir / "ds").string()};
  const ClusterPlan p = buildPlan(c);
  // Tasks 4 and 5 of the sweep stage went as indices 0 and 1 of job 77 (MaxArraySize 4), and a record without an
  // offset (an earlier occsweep's) for task 2 of job 70.
  const std::vector<Submission> subs = {{"sweep", "70", {2}, 0}, {"sweep", "77", {4, 5}, 4}};
  const std::map<std::string, SlurmRecord> records = {
      {"70_2", {"RUNNING", ""}}, {"77_0", {"RUNNING", ""}}, {"77_1", {"PENDING", "Priority"}}};
  const auto status = planStatus(p, dir, records, subs);
  const auto& sweep = status[0];
  REQUIRE(sweep.size() == 6);
  CHECK(sweep[2].state == TaskState::Running);
  CHECK(sweep[4].state == TaskState::Running);
  CHECK(sweep[4].slurm_id == "77_0");
  CHECK(sweep[5].state == TaskState::Pending);
  CHECK(sweep[5].slurm_id == "77_1");
  for (const std::size_t t : {0, 1, 3}) CHECK(sweep[t].state == TaskState::Missing);
}
