// The commands a cluster plan runs, typed. The planner renders each task's argv from one of these (taskArgv) and
// the occsweep command parses that argv back into the same value (tools/occsweep/task_options.hpp), so the
// grammar of a task is written once per side and tests/tools/test_cluster_argv.cpp checks parse(render(task)) == task.
#pragma once

#include <string>
#include <vector>

#include "occsweep/sweeps/baseline.hpp"
#include "occsweep/sweeps/sweep.hpp"

namespace occsweep {

/// `occsweep merge FILES --out OUT [--force]`.
struct MergeTask {
  std::vector<std::string> files;  ///< results files of one sweep's shards
  std::string out;
  bool force = false;              ///< replace occsweep's own earlier result at `out`
  friend bool operator==(const MergeTask&, const MergeTask&) = default;
};

/// `occsweep compare FILES [--json OUT] [--force] [--allow-mixed]`.
struct CompareTask {
  std::vector<std::string> files;  ///< complete results files
  std::string json;                ///< the table as JSON; empty: none
  bool force = false, allow_mixed = false;
  std::string baseline = kDefaultBaseline;  ///< every other method's statistics are against it (docs/statistics.md)
  std::string csv, markdown, latex;  ///< the table in these formats too; empty: none
  double alpha = 0.05;               ///< of the verdicts, after Holm's correction (docs/statistics.md, "Verdicts")
  double smallest_effect = 0.1;      ///< percent of the baseline's AUC: an interval within +-this is negligible
  std::string units = "provenance";  ///< the unit of the tests: "provenance" (scenes) or "names" (declared)
  friend bool operator==(const CompareTask&, const CompareTask&) = default;
};

/// `occsweep cluster select --out OUT RANKINGS`: a data set's generated blocks linked as pcs-NNNN and rank-N.
struct SelectTask {
  std::vector<std::string> rankings;  ///< ranking.json of every generation block
  std::string out;
  friend bool operator==(const SelectTask&, const SelectTask&) = default;
};

/// The argv of a task without the program: {"sweep", "--dataset", D, "--grid", G, "--out", O, "--shard", "I/N",
/// "--threads", T, ...}; a setting at its SweepConfig default is left out (but --shard and --threads). Throws
/// std::invalid_argument for what the command line cannot say: an observable_out, a value or file that starts
/// with '-' (it would be read as an option) or is empty where a value is required.
[[nodiscard]] std::vector<std::string> taskArgv(const SweepConfig& sweep);
[[nodiscard]] std::vector<std::string> taskArgv(const MergeTask& merge);
[[nodiscard]] std::vector<std::string> taskArgv(const CompareTask& compare);
[[nodiscard]] std::vector<std::string> taskArgv(const SelectTask& select);

}  // namespace occsweep
