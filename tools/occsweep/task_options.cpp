// Options of the commands a cluster plan runs (task_options.hpp).
#include "task_options.hpp"

#include "occsweep/sweeps/sweep_engine.hpp"
#include "option_checks.hpp"
#include "selection_options.hpp"

namespace occsweep::cli {

void addSweepOptions(CLI::App& app, SweepOptions& o) {
  app.add_option("--dataset", o.dataset, "Data-set folder")->type_name(kPath);
  app.add_option("--grid", o.grids, "Grid name (sweeps/grids) or path; several (--grid A --grid B) share one read "
                                    "and one recording of the data set, each with its --out in order")
      ->allow_extra_args(false);
  app.add_option("--out", o.outs, "Results file: a store for .db or .sqlite (written as it runs), else JSON; the same "
                                  "sweep's own file, or OUT.partial (store) / OUT.partial.jsonl (JSON), resumes")
      ->type_name(kPath)
      ->allow_extra_args(false);
  app.add_flag("--force", o.config.force, "Replace occsweep's own results of other work at --out (nothing else)");
  app.add_option("--shard", o.shard, "I/N: the I-th of N contiguous blocks of the grid's maps (I from 0)");
  app.add_option("--group", o.group, "G/N: only the G-th Eq. 16 group of the seeded permutation");
  app.add_option("--seed", o.seed, "Seed of the Eq. 16 permutation (with --group)")->capture_default_str();
  addMapSettingFlags(app, o.map);
  app.add_option("--threads", o.config.threads, "Worker threads (0: all cores)")->capture_default_str()->check(threadCount());
  app.add_option("--engine", o.config.engine, "replay: record events once, replay every combination; direct: build every map (the reference)")
      ->check(CLI::IsMember(sweepEngineNames()))->capture_default_str();
  app.add_option("--truth", o.truth, "full: every truth voxel counts; observable: only those a ray from a scan origin "
                                     "reaches within s_c before any other truth voxel (docs/results-format.md)")
      ->check(CLI::IsMember(kTruthModeNames.list()))->capture_default_str();
  app.add_flag("--quiet", o.config.quiet, "No progress on stderr");
}

std::vector<SweepConfig> sweepConfigsOf(const SweepOptions& o) {
  if (o.grids.size() != o.outs.size())
    throw std::invalid_argument("--out: give one per --grid, in the same order (" + std::to_string(o.grids.size()) +
                                " --grid, " + std::to_string(o.outs.size()) + " --out)");
  // Outputs that name one file, or one another's partial file, are refused by the sweep before it reads anything.
  std::vector<SweepConfig> out;
  for (std::size_t i = 0; i < o.grids.size(); ++i) {
    SweepOptions one = o;
    one.grids = {o.grids[i]};
    one.outs = {o.outs[i]};
    out.push_back(sweepConfigOf(one));
  }
  return out;
}

SweepConfig sweepConfigOf(const SweepOptions& o) {
  if (o.grids.size() > 1 || o.outs.size() > 1)
    throw std::invalid_argument("--grid, --out: one each here (several grids are swept by `occsweep sweep`)");
  SweepConfig c = o.config;
  c.dataset = o.dataset;
  if (!o.grids.empty()) c.grid = o.grids.front();
  if (!o.outs.empty()) c.out = o.outs.front();
  if (!o.shard.empty()) std::tie(c.selection.shard_index, c.selection.shard_count) = parseFraction(o.shard, "--shard");
  if (!o.group.empty()) {
    const auto [g, n] = parseFraction(o.group, "--group");
    c.selection.group = SweepSelection::Group{g, n, o.seed};
  }
  c.map = o.map.settings();
  c.truth = parseTruthMode(o.truth);
  return c;
}

SweepConfig sharedSweepSettings(const std::vector<std::string>& args) {
  CLI::App app{"cluster plan --sweep-args"};
  SweepOptions o;
  addSweepOptions(app, o);
  try {
    app.parse(std::vector<std::string>(args.rbegin(), args.rend()));  // CLI11 takes them last first
  } catch (const CLI::ParseError& e) {
    throw std::invalid_argument("--sweep-args: " + std::string(e.what()));
  }
  for (const char* own : {"--dataset", "--grid", "--out", "--shard", "--group", "--seed", "--threads", "--force"})
    if (app.get_option(own)->count())
      throw std::invalid_argument(std::string("--sweep-args: ") + own + " is set by the plan for each sweep");
  return sweepConfigOf(o);
}

void addMergeOptions(CLI::App& app, MergeTask& task) {
  app.add_option("files", task.files, "Results files of one sweep's shards")->type_name(kPath)->required();
  app.add_option("--out", task.out, "Merged results file")->type_name(kPath)->required();
  app.add_flag("--force", task.force, "Replace occsweep's own previous results file at --out (nothing else)");
}

void addCompareOptions(CLI::App& app, CompareTask& task) {
  app.add_option("files", task.files, "Complete results files of whole grids (any mix of methods and data sets; "
                                      "each passes `results check`)")->type_name(kPath)->required();
  app.add_option("--json", task.json, "Also write the table and the statistics as JSON")->type_name(kPath);
  app.add_option("--csv", task.csv, "Also write the table as CSV: one line per set, best parameters as fields")
      ->type_name(kPath);
  app.add_option("--markdown", task.markdown, "Also write the table and the statistics as Markdown")->type_name(kPath);
  app.add_option("--latex", task.latex, "Also write the table and the statistics as LaTeX (booktabs)")
      ->type_name(kPath);
  app.add_option("--baseline", task.baseline, "Method every other one is compared with (docs/statistics.md)")
      ->capture_default_str();
  app.add_option("--alpha", task.alpha, "Significance level of the verdicts, after Holm's correction over the methods "
                                        "compared with the baseline, from 1e-6 to 0.25 (docs/statistics.md, Verdicts)")
      ->check(numberIn(1e-6, 0.25))->capture_default_str();
  app.add_option("--smallest-effect", task.smallest_effect,
                 "Smallest improvement of interest, in percent of the baseline's AUC: a median and mean shown "
                 "within +-this are negligible")
      ->check(numberIn(0.0, 100.0))->capture_default_str();
  app.add_option("--units", task.units, "The unit of the tests: provenance (data sets sharing a recorded input, the "
                                        "truth in one region, or a generated scene are one scene) or names (declared: "
                                        "each data set name is one unit); docs/statistics.md, Verdicts")
      ->check(CLI::IsMember({"provenance", "names"}))->capture_default_str();
  app.add_flag("--force", task.force, "Replace occsweep's own previous outputs at --json, --csv, --markdown, --latex "
                                      "(nothing else)");
  app.add_flag("--allow-mixed", task.allow_mixed, "Compare anyway when files of one data set differ in resolution, "
                                                  "s_c, k-NN variant or statistics mode, are shards, or are two of "
                                                  "one method (the better best AUC taken); each is listed on stderr");
}

void addSelectOptions(CLI::App& app, SelectTask& task) {
  app.add_option("--out", task.out, "Folder of links to write")->type_name(kPath)->required();
  app.add_option("rankings", task.rankings, "ranking.json of every generation block of the data set")
      ->type_name(kPath)->required();
}

}  // namespace occsweep::cli
