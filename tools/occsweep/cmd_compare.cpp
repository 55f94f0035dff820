// occsweep compare: best AUC of each method per data set and point cloud set (the table behind Fig. 5).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <set>

#include "command_registry.hpp"
#include "limit_options.hpp"
#include "task_options.hpp"
#include "compare_cells.hpp"
#include "occsweep/io/control_characters.hpp"
#include "occsweep/io/output_file.hpp"
#include "occsweep/sweeps/compare.hpp"
#include "occsweep/sweeps/csv_text.hpp"

namespace occsweep::cli {
namespace {

nlohmann::json bestJson(const BestMap& b, const std::vector<ResultsFile>& in, const std::vector<std::string>& names) {
  return {{"auc", b.auc},           {"auc_observed", b.observed}, {"map_index", b.map_index},
          {"params", bestParametersText(b, in)}, {"parameters", parameterFields(b, in)}, {"file", names[b.file]},
          {"settings", toJson(in[b.file].header.map)}};
}

// The settings of a best map's file that differ from `map`'s defaults, as NAME=VALUE like its parameters: typed back
// as flags (--resolution, --s-c, --variant, --stats) with them, a row rebuilds its map (docs/methods.md, "One map").
std::string changedSettingsText(const MapSettings& s) {
  const MapSettings defaults;
  std::string text;
  const auto add = [&text](const char* name, const std::string& value) {
    text += std::string(" ") + name + "=" + value;
  };
  if (s.resolution != defaults.resolution) add("resolution", csvNumber(s.resolution));
  if (s.s_c != defaults.s_c) add("s_c", csvNumber(s.s_c));
  if (s.variant != defaults.variant) add("variant", toText(s.variant));
  if (s.stats != defaults.stats) add("stats", toText(s.stats));
  return text;
}

// Files of one data set that differ in their settings: refused, or with --allow-mixed each listed on stderr.
std::vector<std::string> checkMixed(const std::vector<ResultsFile>& in, const CompareTask& o) {
  const auto mixed = mixedSettings(in, o.files);
  if (!mixed.empty() && !o.allow_mixed)
    throw std::runtime_error("cannot compare: " + mixed.front() +
                             (mixed.size() > 1 ? " (and " + std::to_string(mixed.size() - 1) + " more)" : "") +
                             "; pass --allow-mixed to compare anyway");
  for (const auto& m : mixed)
    std::cerr << "occsweep compare: warning (--allow-mixed): " << escapedControlCharacters(m) << '\n';
  return mixed;
}

// The methods in the order compare shows them: the baseline first, then the others by name.
std::vector<std::string> shownMethods(const std::vector<ResultsFile>& in, const std::string& baseline) {
  std::set<std::string> names{baseline};
  for (const ResultsFile& f : in) names.insert(f.header.method);
  std::vector<std::string> order{baseline};
  for (const std::string& name : names)
    if (name != baseline) order.push_back(name);
  return order;
}

// "  NAME" padded to the AUC column; a name longer than `name_width` goes on over lines, the AUC after its last.
std::string methodLabel(const std::string& method, std::size_t name_width) {
  std::string lines = wrappedLines(method, 2, 2 + name_width);
  if (lines.empty()) return std::string(2 + name_width, ' ');  // a name of blanks
  lines.pop_back();                                             // the last line's '\n'
  const std::size_t last = lines.rfind('\n') + 1;              // 0 when there is one line
  return lines + std::string(2 + name_width - std::min(2 + name_width, lines.size() - last), ' ');
}

// "map N of FILE: NAME=VALUE ..." four spaces in: on one line when it fits; else the file's path exactly as it is,
// cut only at the lines' ends, then the parameters wrapped.
std::string bestMapLines(const BestMap& best, const std::string& file, const std::string& parameters) {
  const std::string head = "map " + std::to_string(best.map_index) + " of " + file + ":";
  if (4 + head.size() + 1 + parameters.size() <= kTerminalColumns && head.find('\n') == std::string::npos)
    return "    " + head + " " + parameters + "\n";
  return cutLines(head, 4, kTerminalColumns) + wrappedLines(parameters, 4, kTerminalColumns);
}

// Within kTerminalColumns whatever the parameters, paths and names: each data set's line, then one line per method
// with its AUC, its improvement over the baseline and the file and map behind it, then the map's parameters
// (docs/statistics.md, "In occsweep compare"). Every digit is in --json and --csv. Names and paths, from users' files
// and arguments, show their control characters escaped: a line break or an escape sequence in a name would forge or
// erase lines of the table.
void printRow(const ComparisonRow& r, const std::vector<ResultsFile>& in, const std::vector<std::string>& files,
              const std::vector<std::string>& methods, const std::string& baseline) {
  const std::string set = r.point_cloud_set == "-" ? "" : " (point cloud set " + r.point_cloud_set + ")";
  std::printf("%s", cutLines(escapedControlCharacters(r.dataset + set), 0, kTerminalColumns).c_str());
  std::size_t name_width = 16;  // the AUCs in one column, however long a method's name (up to half a line)
  for (const std::string& m : methods)
    name_width = std::max(name_width, std::min<std::size_t>(m.size(), kTerminalColumns / 2));
  for (const std::string& m : methods) {
    const std::optional<BestMap> best = r.best(m);
    if (!best && !r.files_of.count(m)) continue;
    const std::string versus = m == baseline ? "" : cell(r.improvementPercent(m, baseline), "%+.2f %%");
    std::printf("%s AUC %6s  %10s", methodLabel(m, name_width).c_str(), cell(best ? best->auc : NAN, "%.4f").c_str(),
                versus.c_str());
    if (!best) {
      std::printf("\n");
      continue;
    }
    const std::string parameters = bestParametersText(*best, in) + changedSettingsText(in[best->file].header.map);
    std::printf("\n%s", bestMapLines(*best, escapedControlCharacters(files[best->file]), parameters).c_str());
  }
}

// Why a row lacks a number: in the row's JSON, and (with its data set) in `notes` for the lines after the table.
nlohmann::json rowNotes(const ComparisonRow& r, const std::vector<ResultsFile>& in, const std::vector<std::string>& files,
                        const std::vector<std::string>& methods, const std::string& baseline,
                        std::vector<std::string>& notes) {
  nlohmann::json row_notes = nlohmann::json::array();
  for (const std::string& m : methods)
    if (const std::string why = missingReason(r, m, in, files); !why.empty()) {
      row_notes.push_back(why);
      notes.push_back(r.dataset + ": " + why);
    }
  if (const std::string why = coverageWarningOf(r, in); !why.empty()) {
    row_notes.push_back(why);
    notes.push_back(r.dataset + ": " + why);
  }
  const std::optional<BestMap> base = r.best(baseline);
  if (base && !(base->auc > 0) && r.best_of.size() > 1) {
    row_notes.push_back("no improvement: the " + baseline + " AUC is 0");
    notes.push_back(r.dataset + ": no improvement in percent: the " + baseline + " AUC is 0");
  }
  return row_notes;
}

// Each method's best map, and its improvement over the baseline (none for the baseline itself); null for a method
// whose files hold no AUC (the row's notes say why).
nlohmann::json rowJson(const ComparisonRow& r, const std::vector<ResultsFile>& in, const std::vector<std::string>& files,
                       const std::string& baseline, const std::string& unit, nlohmann::json notes) {
  nlohmann::json methods = nlohmann::json::object();
  for (const auto& [name, _] : r.files_of) methods[name] = nullptr;
  for (const auto& [name, best] : r.best_of) {
    methods[name] = bestJson(best, in, files);
    if (name != baseline) methods[name]["improvement_percent"] = finiteNumber(r.improvementPercent(name, baseline));
  }
  return {{"dataset", r.dataset}, {"point_cloud_set", r.point_cloud_set}, {"dataset_hash", r.dataset_hash},
          {"unit", unit}, {"methods", std::move(methods)}, {"notes", std::move(notes)}};
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
    checkOutputTarget(o.csv, o.force, textOutput("comparison CSV", "dataset,point_cloud_set,"));
  if (!o.markdown.empty())
    checkOutputTarget(o.markdown, o.force, textOutput("comparison Markdown", "<!-- occsweep compare"));
  if (!o.latex.empty())
    checkOutputTarget(o.latex, o.force, textOutput("comparison LaTeX", "% occsweep compare"));
}

CompareStatisticsOptions statisticsOptions(const CompareTask& o) {
  CompareStatisticsOptions options = statisticsAgainst(o.baseline);
  options.rules = {o.alpha, o.smallest_effect};
  options.units = o.units == "names" ? UnitRule::Names : UnitRule::Provenance;
  return options;
}

// The statistics against the baseline; none (with a note) when the default baseline has no best map: no file of it
// given, or none with an AUC (a data set without truth).
std::vector<MethodStatistics> statisticsOf(const std::vector<ComparisonRow>& rows, const std::vector<ResultsFile>& in,
                                           const CompareTask& o, std::vector<std::string>& notes) {
  const std::vector<std::string> methods = comparedMethods(rows);
  if (o.baseline == CompareTask{}.baseline && std::find(methods.begin(), methods.end(), o.baseline) == methods.end()) {
    const bool given = std::any_of(in.begin(), in.end(), [&](const ResultsFile& f) { return f.header.method == o.baseline; });
    notes.push_back("no statistics: " + (given ? "no results file of the baseline " + o.baseline + " holds an AUC"
                                               : "no results file of the baseline " + o.baseline + " given") +
                    " (--baseline chooses another)");
    return {};
  }
  for (const std::string& name : pooledDatasetNames(rows, statisticsOptions(o).units))
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
  for (const auto& f : files) {
    f->markWritten();  // the tables: what a later --force may replace (textOutput)
    all.push_back(f.get());
  }
  OutputFile::commitTogether(all);
}

int runCompare(const CompareTask& o) {
  checkOutputs(o);
  const std::vector<ResultsFile> in = readChecked(o.files, MapDetail::Summary);
  if (!o.latex.empty()) requireLatexCharacters(in, o.files);  // before any table is printed
  if (const std::string why = mixedTruths(in, o.files); !why.empty()) throw std::runtime_error("cannot compare: " + why);
  const TruthMode truth = in.front().header.truth;
  const auto mixed = checkMixed(in, o);
  const auto rows = compareBest(in);
  const std::vector<std::string> shown = shownMethods(in, o.baseline);
  nlohmann::json j = nlohmann::json::array();
  std::vector<std::string> notes;
  const SampleUnits units = sampleUnits(rows, statisticsOptions(o).units);  // each row's, for --json and --csv
  for (std::size_t i = 0; i < rows.size(); ++i)
    j.push_back(rowJson(rows[i], in, o.files, o.baseline, units.of_row[i],
                        rowNotes(rows[i], in, o.files, shown, o.baseline, notes)));
  // Before anything is printed: a --baseline that was not given is refused with no table above the error.
  const std::vector<MethodStatistics> statistics = statisticsOf(rows, in, o, notes);
  for (const auto& r : rows) printRow(r, in, o.files, shown, o.baseline);
  for (const auto& n : notes)
    std::cout << "note: " << wrappedLines(escapedControlCharacters(n), 6, kTerminalColumns).substr(6);
  std::cout << truthLine(truth) << '\n';
  std::vector<std::string> methods;
  for (const auto& s : statistics) methods.push_back(s.method);
  const ComparisonTables tables{rows,      in, o.files, methods, statistics, o.baseline, {o.alpha, o.smallest_effect},
                                mixed, units.of_row, truth};
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
  // Each file's grid is enumerated to check its maps; a JSON file is read whole.
  addLimitOptions(app, {Limit::Combinations, Limit::JsonBytes});
  return [task] { return runCompare(*task); };
}};

}  // namespace
}  // namespace occsweep::cli
