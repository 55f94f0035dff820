// occsweep compare: best AUC of each method per data set and point cloud set (the table behind Fig. 5).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>

#include "command_registry.hpp"
#include "limit_options.hpp"
#include "task_options.hpp"
#include "compare_tables.hpp"
#include "occsweep/eval/output_file.hpp"
#include "occsweep/eval/ownership.hpp"
#include "occsweep/sweeps/merge.hpp"

namespace occsweep::cli {
namespace {

nlohmann::json bestJson(const std::optional<BestMap>& b, const std::vector<ResultsFile>& in,
                        const std::vector<std::string>& names) {
  if (!b) return nullptr;
  return {{"auc", b->auc}, {"auc_observed", b->observed}, {"map_index", b->map_index},
          {"params", bestParametersText(*b, in)}, {"parameters", parameterFields(*b, in)}, {"file", names[b->file]}};
}

// A number occsweep prints is either right or not printed (docs/robustness.md): "-" where there is none.
std::string cell(double v, const char* format) {
  if (!std::isfinite(v)) return "-";
  char buf[32];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

// Files of one data set that differ in their settings: refused, or with --allow-mixed each listed on stderr.
std::vector<std::string> checkMixed(const std::vector<ResultsFile>& in, const CompareTask& o) {
  const auto mixed = mixedSettings(in, o.files);
  if (!mixed.empty() && !o.allow_mixed)
    throw std::runtime_error("cannot compare: " + mixed.front() +
                             (mixed.size() > 1 ? " (and " + std::to_string(mixed.size() - 1) + " more)" : "") +
                             "; pass --allow-mixed to compare anyway");
  for (const auto& m : mixed) std::cerr << "occsweep compare: warning (--allow-mixed): " << m << '\n';
  return mixed;
}

void printHeader(const std::vector<std::string>& others) {
  std::printf("%-28s %-8s %9s %9s %9s  %s | %s | %s | %s", "data set", "pcs", "OctoMap", "k-NN", "improve%",
              "OctoMap best", "k-NN best", "OctoMap file", "k-NN file");
  for (const std::string& m : others) std::printf(" | %s AUC, vs OctoMap %%, best", m.c_str());
  std::printf("\n");
}

// Other methods (docs/methods.md) follow the paper's two, each as AUC, improvement over OctoMap and best map.
void printRow(const ComparisonRow& r, const std::vector<ResultsFile>& in, const std::vector<std::string>& files,
              const std::vector<std::string>& others) {
  auto auc = [](const std::optional<BestMap>& b) { return b ? b->auc : std::nan(""); };
  auto file = [&](const std::optional<BestMap>& b) { return b ? files[b->file] : std::string("-"); };
  std::printf("%-28s %-8s %9s %9s %9s  %s | %s | %s | %s", r.dataset.c_str(), r.point_cloud_set.c_str(),
              cell(auc(r.octomap), "%.4f").c_str(), cell(auc(r.knn), "%.4f").c_str(),
              cell(r.improvementPercent(), "%.2f").c_str(), r.octomap ? bestParametersText(*r.octomap, in).c_str() : "-",
              r.knn ? bestParametersText(*r.knn, in).c_str() : "-", file(r.octomap).c_str(), file(r.knn).c_str());
  for (const std::string& m : others) {
    const auto it = r.others.find(m);
    std::printf(" | %s %s %s", cell(it == r.others.end() ? std::nan("") : it->second.auc, "%.4f").c_str(),
                cell(r.improvementPercent(m), "%+.2f").c_str(),
                it == r.others.end() ? "-" : bestParametersText(it->second, in).c_str());
  }
  std::printf("\n");
}

// Why a row lacks a number: in the row's JSON, and (with its data set) in `notes` for the lines after the table.
nlohmann::json rowNotes(const ComparisonRow& r, const std::vector<ResultsFile>& in, const std::vector<std::string>& files,
                        std::vector<std::string>& notes) {
  nlohmann::json row_notes = nlohmann::json::array();
  for (const bool knn : {false, true})
    if (const std::string why = missingReason(r, knn, in, files); !why.empty()) {
      row_notes.push_back(why);
      notes.push_back(r.dataset + ": " + why);
    }
  if (r.octomap && r.knn && !std::isfinite(r.improvementPercent())) {
    row_notes.push_back("no improvement: the OctoMap AUC is 0");
    notes.push_back(r.dataset + ": no improvement in percent: the OctoMap AUC is 0");
  }
  return row_notes;
}

nlohmann::json rowJson(const ComparisonRow& r, const std::vector<ResultsFile>& in, const std::vector<std::string>& files,
                       nlohmann::json notes) {
  nlohmann::json j = {{"dataset", r.dataset}, {"point_cloud_set", r.point_cloud_set}, {"dataset_hash", r.dataset_hash},
                      {"octomap", bestJson(r.octomap, in, files)}, {"knn", bestJson(r.knn, in, files)},
                      {"improvement_percent", finiteNumber(r.improvementPercent())}, {"notes", std::move(notes)}};
  // The other methods only when given: a comparison of the paper's two stays as it was.
  for (const auto& [name, best] : r.others) {
    j["others"][name] = bestJson(best, in, files);
    j["others"][name]["improvement_percent"] = finiteNumber(r.improvementPercent(name));
  }
  return j;
}

void printTruth(TruthMode truth) {
  std::cout << "truth: " << truthModeName(truth)
            << (truth == TruthMode::Full ? " (every truth voxel of the region counts)"
                                         : " (only truth voxels observable from the scan origins count)")
            << '\n';
}

// Every output needs a file of its own on a path that can hold it, checked before the first is written: a failure
// at the third output must not leave the first two behind (docs/robustness.md, outputs).
void requireDistinctOutputs(const CompareTask& o) {
  requireSeparateOutputs({{"--json", o.json}, {"--csv", o.csv}, {"--markdown", o.markdown}, {"--latex", o.latex}});
}

// Each output given is checked before anything is read or written: a user's file is never replaced.
void checkOutputs(const CompareTask& o) {
  requireDistinctOutputs(o);
  if (!o.json.empty()) checkOutputTarget(o.json, o.force, jsonOutput("comparison", "occsweep-comparison"));
  if (!o.csv.empty())
    checkOutputTarget(o.csv, o.force, recordedTextOutput("comparison CSV", "dataset,point_cloud_set,"));
  if (!o.markdown.empty())
    checkOutputTarget(o.markdown, o.force, recordedTextOutput("comparison Markdown", "<!-- occsweep compare"));
  if (!o.latex.empty())
    checkOutputTarget(o.latex, o.force, recordedTextOutput("comparison LaTeX", "% occsweep compare"));
}

CompareStatisticsOptions statisticsOptions(const CompareTask& o) {
  CompareStatisticsOptions options = statisticsAgainst(o.baseline);
  options.rules = {o.alpha, o.smallest_effect};
  return options;
}

// The statistics against the baseline; none (with a note) when the default baseline was not given at all.
std::vector<MethodStatistics> statisticsOf(const std::vector<ComparisonRow>& rows, const std::vector<ResultsFile>& in,
                                           const CompareTask& o, std::vector<std::string>& notes) {
  const std::vector<std::string> methods = comparedMethods(rows);
  if (o.baseline == CompareTask{}.baseline && std::find(methods.begin(), methods.end(), o.baseline) == methods.end()) {
    notes.push_back("no statistics: no results of the baseline " + o.baseline + " given (--baseline names another)");
    return {};
  }
  for (const std::string& name : pooledDatasetNames(rows))
    notes.push_back("sets of several contents are all named " + name + ": counted as one data set (the unit of the "
                    "verdicts); data sets of their own need names of their own (docs/statistics.md, Verdicts)");
  return compareStatistics(rows, in, statisticsOptions(o));
}

// --json, --csv, --markdown and --latex, each written out, then committed together: a failed write or a file put at
// any of their names meanwhile leaves none of them.
void writeOutputs(const CompareTask& o, const nlohmann::json& comparison, const ComparisonTables& t) {
  std::vector<std::unique_ptr<OutputFile>> files;
  auto add = [&files](const std::string& path, const std::string& bytes) {
    if (path.empty()) return;
    files.push_back(std::make_unique<OutputFile>(path));
    files.back()->stream() << bytes;
  };
  add(o.json, comparison.dump(1) + "\n");
  add(o.csv, csvTable(t));
  add(o.markdown, "<!-- occsweep compare --markdown -->\n" + markdownTables(t));
  add(o.latex, latexTables(t));  // its first line names occsweep compare
  std::vector<OutputFile*> all;
  for (const auto& f : files) all.push_back(f.get());
  OutputFile::commitTogether(all);
  for (const std::string& table : {o.csv, o.markdown, o.latex})
    if (!table.empty()) recordTextOutput(table);  // what a later --force may replace (recordedTextOutput)
}

int runCompare(const CompareTask& o) {
  checkOutputs(o);
  const std::vector<ResultsFile> in = readChecked(o.files, MapDetail::Summary);
  if (const std::string why = mixedTruths(in, o.files); !why.empty()) throw std::runtime_error("cannot compare: " + why);
  const TruthMode truth = in.front().header.truth;
  const auto mixed = checkMixed(in, o);
  const auto rows = compareBest(in);
  const std::vector<std::string> others = otherMethods(rows);
  printHeader(others);
  nlohmann::json j = nlohmann::json::array();
  std::vector<std::string> notes;
  for (const auto& r : rows) {
    printRow(r, in, o.files, others);
    j.push_back(rowJson(r, in, o.files, rowNotes(r, in, o.files, notes)));
  }
  const std::vector<MethodStatistics> statistics = statisticsOf(rows, in, o, notes);
  for (const auto& n : notes) std::cout << "note: " << n << '\n';
  printTruth(truth);
  std::vector<std::string> methods;
  for (const auto& s : statistics) methods.push_back(s.method);
  const ComparisonTables tables{rows, in, o.files, methods, statistics, o.baseline, {o.alpha, o.smallest_effect}};
  std::cout << statisticsText(tables);
  const nlohmann::json comparison = {{"format", "occsweep-comparison"}, {"files", o.files},
                                     {"allow_mixed", o.allow_mixed}, {"mixed", mixed}, {"truth", truthModeName(truth)},
                                     {"rows", j}, {"baseline", o.baseline},
                                     {"statistics", toJson(statistics, statisticsOptions(o))}};
  writeOutputs(o, comparison, tables);
  return 0;
}

const RegisterCommand kCompare{"compare", "Best AUC of every method per data set, the improvement over a baseline, and "
                                          "whether it is real (docs/statistics.md)",
                               [](CLI::App& app) {
  addExample(app, "occsweep compare oct.json knn.json --latex table.tex");
  auto task = std::make_shared<CompareTask>();
  addCompareOptions(app, *task);  // task_options.cpp: also what `cluster plan` tasks are parsed with
  addLimitOptions(app, {Limit::Combinations});  // each file's grid is enumerated to check its maps
  return [task] { return runCompare(*task); };
}};

}  // namespace
}  // namespace occsweep::cli
