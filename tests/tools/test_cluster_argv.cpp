// A cluster task's argv is rendered from its typed description (taskArgv, occsweep/sweeps/cluster_tasks.hpp) and
// parsed back by the commands' own option registrations (tools/occsweep/task_options.cpp): parse(render(task)) must
// be the task, for many random tasks, and every task of a built plan must parse back to what the plan says it is.
#include <catch2/catch.hpp>

#include <bit>
#include <cmath>
#include <string_view>

#include "occsweep/core/splitmix64.hpp"
#include "occsweep/sweeps/cluster_plan.hpp"
#include "task_options.hpp"

using namespace occsweep;
using namespace occsweep::cli;

namespace {

/// argv as the occsweep binary sees it after its own name, through a command tree like main.cpp's.
template <class Options, class Register>
void parseAs(const std::vector<std::string>& argv, Options& options, Register add) {
  CLI::App root{"occsweep"};
  root.require_subcommand(1);
  CLI::App* sub = root.add_subcommand(argv.at(0));
  CLI::App* target = sub;
  if (argv.at(0) == "cluster") target = sub->add_subcommand(argv.at(1));
  add(*target, options);
  root.parse(std::vector<std::string>(argv.rbegin(), argv.rend()));  // CLI11 takes them last first
}

SweepConfig parseSweep(const std::vector<std::string>& argv) {
  SweepOptions o;
  parseAs(argv, o, addSweepOptions);
  return sweepConfigOf(o);
}

template <class Task, class Register>
Task parseTask(const std::vector<std::string>& argv, Register add) {
  Task t;
  parseAs(argv, t, add);
  return t;
}

/// A file or folder name as users write them: spaces, quotes, commas, '=', dots, non-ASCII; never empty and never
/// starting with '-' (taskArgv refuses those, see below).
std::string randomName(SplitMix64& rng) {
  static const std::vector<std::string> pieces = {"a", "data", " ", "'", "\"", ",", "=", ".", "..", "/", "set 1",
                                                  "rank-800", "π", "$HOME", "{dataset}", "x:y", "-", "--out"};
  std::string s = rng.below(2) ? "/" : "d";
  for (auto n = 1 + rng.below(6); n > 0; --n) s += pieces[rng.below(pieces.size())];
  return s;
}

/// A positive finite double: a plain metre value, or any bit pattern of one.
double randomPositive(SplitMix64& rng) {
  if (rng.below(2)) return 0.001 + 10 * rng.uniform();
  for (;;) {
    const double x = std::bit_cast<double>(rng.next() & ~(std::uint64_t(1) << 63));
    if (std::isfinite(x) && x > 0) return x;
  }
}

SweepConfig randomSweep(SplitMix64& rng) {
  SweepConfig s;
  s.dataset = randomName(rng);
  s.grid = rng.below(3) ? std::string(rng.below(2) ? "knn-opt" : "octomap-opt") : randomName(rng);
  s.out = randomName(rng);
  s.selection.shard_count = 1 + rng.below(rng.below(2) ? 5 : 100000);
  s.selection.shard_index = rng.below(s.selection.shard_count);
  if (rng.below(2)) {
    const auto n = 1 + rng.below(30);
    s.selection.group = SweepSelection::Group{rng.below(n), n, rng.below(3) ? rng.below(100) : rng.next()};
  }
  if (rng.below(2)) s.map.resolution = randomPositive(rng);
  if (rng.below(2)) s.map.s_c = randomPositive(rng);
  s.map.variant = rng.below(2) ? UpdateVariant::Literal : UpdateVariant::Default;
  s.map.stats = rng.below(2) ? StatsMode::Online : StatsMode::Batch;
  s.engine = rng.below(2) ? "direct" : "replay";
  s.truth = rng.below(2) ? TruthMode::Observable : TruthMode::Full;
  s.threads = int(rng.below(rng.below(2) ? 8 : 1025));
  s.quiet = rng.below(2);
  s.force = rng.below(2);
  return s;
}

std::vector<std::string> randomFiles(SplitMix64& rng) {
  std::vector<std::string> files;
  for (auto n = 1 + rng.below(5); n > 0; --n) files.push_back(randomName(rng));
  return files;
}

}  // namespace

TEST_CASE("a sweep task parses back to itself over many random tasks") {
  for (std::uint64_t seed = 1; seed <= 2000; ++seed) {
    SplitMix64 rng(seed);
    const SweepConfig task = randomSweep(rng);
    const auto argv = taskArgv(task);
    INFO("seed " << seed << ": " << [&] {
      std::string all;
      for (const auto& a : argv) all += "[" + a + "] ";
      return all;
    }());
    REQUIRE(parseSweep(argv) == task);
  }
}

TEST_CASE("merge, compare and select tasks parse back to themselves over many random tasks") {
  for (std::uint64_t seed = 1; seed <= 1000; ++seed) {
    SplitMix64 rng(seed);
    INFO("seed " << seed);
    const MergeTask merge{randomFiles(rng), randomName(rng), bool(rng.below(2))};
    CHECK(parseTask<MergeTask>(taskArgv(merge), addMergeOptions) == merge);
    CompareTask compare{randomFiles(rng), rng.below(2) ? randomName(rng) : "", bool(rng.below(2)),
                        bool(rng.below(2)), rng.below(2) ? randomName(rng) : "octomap",
                        rng.below(2) ? randomName(rng) : "", rng.below(2) ? randomName(rng) : "",
                        rng.below(2) ? randomName(rng) : ""};
    if (rng.below(2)) compare.alpha = 1e-6 + (0.25 - 1e-6) * rng.uniform();  // the verdicts' rules travel too
    if (rng.below(2)) compare.smallest_effect = 100.0 * rng.uniform();
    if (rng.below(2)) compare.units = "names";  // and the declared units
    CHECK(parseTask<CompareTask>(taskArgv(compare), addCompareOptions) == compare);
    const SelectTask select{randomFiles(rng), randomName(rng)};
    CHECK(parseTask<SelectTask>(taskArgv(select), addSelectOptions) == select);
  }
}

TEST_CASE("a sweep task's argv is the sweep command line, defaults left out") {
  SweepConfig s;
  s.dataset = "data/x";
  s.grid = "knn-opt";
  s.out = "sweeps/x.json";
  s.selection.shard_index = 2, s.selection.shard_count = 4;
  s.threads = 3;
  CHECK(taskArgv(s) == std::vector<std::string>{"sweep", "--dataset", "data/x", "--grid", "knn-opt", "--out",
                                                "sweeps/x.json", "--shard", "2/4", "--threads", "3"});
  s.selection.group = SweepSelection::Group{1, 20, 7};
  s.map.s_c = 0.1 + 0.2;  // 0.30000000000000004: the shortest text that reads back exactly
  s.engine = "direct";
  CHECK(taskArgv(s) == std::vector<std::string>{"sweep", "--dataset", "data/x", "--grid", "knn-opt", "--out",
                                                "sweeps/x.json", "--shard", "2/4", "--threads", "3", "--group", "1/20",
                                                "--seed", "7", "--s-c", "0.30000000000000004", "--engine", "direct"});
}

TEST_CASE("taskArgv refuses what the command line would read otherwise") {
  SweepConfig s;
  s.dataset = "-data";  // would be read as an option
  s.out = "x.json";
  CHECK_THROWS_AS(taskArgv(s), std::invalid_argument);
  s.dataset = "data";
  s.observable_out = "o.json";  // no option says it
  CHECK_THROWS_AS(taskArgv(s), std::invalid_argument);
  CHECK_THROWS_AS(taskArgv(MergeTask{{}, "out.json", true}), std::invalid_argument);
  CHECK_THROWS_AS(taskArgv(MergeTask{{"a.json", ""}, "out.json", true}), std::invalid_argument);
  CHECK_THROWS_AS(taskArgv(SelectTask{{"r.json"}, "--out"}), std::invalid_argument);
}

TEST_CASE("cluster plan --sweep-args are parsed as sweep parses them, and may not set what the plan sets") {
  const SweepConfig s = sharedSweepSettings({"--s-c", "4.5", "--engine", "direct", "--truth", "observable"});
  SweepConfig expected;
  expected.map.s_c = 4.5, expected.engine = "direct", expected.truth = TruthMode::Observable;
  CHECK(s == expected);
  CHECK(sharedSweepSettings({}) == SweepConfig{});
  for (const std::string_view own : {"--dataset", "--grid", "--out", "--shard", "--group", "--seed", "--threads"})
    CHECK_THROWS_AS(sharedSweepSettings({std::string(own), own == "--shard" || own == "--group" ? "0/2" : "1"}),
                    std::invalid_argument);
  CHECK_THROWS_AS(sharedSweepSettings({"--force"}), std::invalid_argument);
  CHECK_THROWS_AS(sharedSweepSettings({"--s-c", "0"}), std::invalid_argument);
  CHECK_THROWS_AS(sharedSweepSettings({"--no-such-flag"}), std::invalid_argument);
}

TEST_CASE("every task of a built plan parses back to the work the plan records for it") {
  PlanConfig c;
  c.occsweep = "/opt/occsweep/bin/occsweep";
  c.datasets = {"building-plain-I", "parking-voronoi-O"};
  c.blocks = 2, c.pcs_count = 6;
  c.grids = {{"octomap-opt", 1, false}, {"knn-opt", 3, false}, {"reduction", 2, true}};
  c.sweep.map.s_c = 3.5, c.sweep.engine = "direct";
  c.slurm.cpus_per_task = 4;
  const ClusterPlan p = buildPlan(c);
  auto args = [](const ClusterTask& t) {
    REQUIRE(t.argv.at(0) == "/opt/occsweep/bin/occsweep");
    return std::vector<std::string>(t.argv.begin() + 1, t.argv.end());
  };
  std::size_t grouped = 0;
  for (const auto& t : stageNamed(p, "sweep").tasks) {
    const SweepConfig s = parseSweep(args(t));
    CHECK(s.out == t.output);
    CHECK(s.selection.shard_index == t.expect_shard);
    CHECK(s.selection.shard_count == t.expect_shards);
    CHECK(s.map.s_c == 3.5);
    CHECK(s.engine == "direct");
    CHECK(s.threads == 4);
    CHECK(std::vector<std::string>{s.dataset.parent_path().string()} == t.inputs);  // the set is in its select's folder
    if (s.selection.group) {
      ++grouped;
      CHECK(s.grid == "reduction");
      CHECK(s.selection.group->count == 2);
    }
  }
  CHECK(grouped == 2 * 2);  // 2 data sets x 2 shards of the grouped grid, on the group set only
  for (const auto& t : stageNamed(p, "merge").tasks) {
    const MergeTask m = parseTask<MergeTask>(args(t), addMergeOptions);
    CHECK(m.out == t.output);
    CHECK(m.files == t.inputs);
    CHECK(m.force);
  }
  for (const auto& t : stageNamed(p, "select").tasks) {
    const SelectTask s = parseTask<SelectTask>(args(t), addSelectOptions);
    CHECK(s.out == t.output);
    CHECK(s.rankings == t.inputs);
    CHECK(s.rankings.size() == 2);
  }
  const auto& report = stageNamed(p, "report").tasks.at(0);
  const CompareTask compare = parseTask<CompareTask>(args(report), addCompareOptions);
  CHECK(compare.json == report.output);
  CHECK(compare.files.size() == 2 * 3 * 2);  // data sets x sets x optimisation grids; the grouped grid left out
}
