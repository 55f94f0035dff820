// occsweep results check FILE: exit 0 only for a complete, consistent results file.
// occsweep results export FILE --out OUT: a results file or store converted, map by map, into the format OUT's name
// asks for (.csv, .db/.sqlite, else JSON).
// occsweep results diff GOLDEN NEW: exit 0 only when NEW has GOLDEN's numbers (docs/results-format.md, "Regression
// checks against a golden file").
#include <cstdio>
#include <iostream>

#include "command_registry.hpp"
#include "limit_options.hpp"
#include "option_checks.hpp"

#include "occsweep/sweeps/results_diff.hpp"
#include "occsweep/sweeps/results_export.hpp"
#include "occsweep/sweeps/results_store.hpp"
#include "occsweep/sweeps/results_verify.hpp"
#include "occsweep/io/output_target.hpp"

namespace occsweep::cli {
namespace {

void printDifferences(const std::vector<ResultsDifference>& rows) {
  std::printf("%-6s %-10s %-22s %-24s %-24s %s\n", "map", "id", "field", "golden", "new", "parameters");
  for (const auto& d : rows)
    std::printf("%-6s %-10s %-22s %-24s %-24s %s\n", d.map_index ? std::to_string(*d.map_index).c_str() : "-",
                d.id ? std::to_string(*d.id).c_str() : "-", d.field.c_str(), d.golden.c_str(), d.candidate.c_str(),
                d.combination.empty() ? "(header)" : d.combination.c_str());
}

// Exit 0 when nothing differs, 1 with the table of what does; unreadable input throws (exit 2, the file named).
int runDiff(const std::string& golden_file, const std::string& new_file, double auc_tolerance, CountsCheck counts) {
  // What `results check` refuses is never compared: a damaged file is exit 2, not a table of differences.
  const ResultsFile golden = readCheckedResults(golden_file, MapDetail::Full);
  const ResultsFile candidate = readCheckedResults(new_file, MapDetail::Full);
  const ResultsDiff diff = diffResults(golden, candidate, auc_tolerance, counts);
  const std::string checked = std::string(counts == CountsCheck::Exact ? "confusion counts exact, " : "") +
                              "AUC within " + plainNumber(auc_tolerance);
  const std::string shown_new = escapedControlCharacters(new_file);
  const std::string shown_golden = escapedControlCharacters(golden_file);
  if (diff.empty()) {
    std::cout << shown_new << ": same numbers as " << shown_golden << ": " << diff.golden_maps << " maps, "
              << diff.golden_combinations << " combinations, " << checked << '\n';
    return 0;
  }
  if (!diff.header.empty()) {
    printDifferences(diff.header);
    std::cout << shown_new << ": not comparable with " << shown_golden << ": " << diff.header.size()
              << " header field(s) differ; no combination compared\n";
    return 1;
  }
  printDifferences(diff.combinations);
  std::cout << shown_new << ": " << diff.combinations.size() << " difference(s) from " << shown_golden << " ("
            << checked << ")\n";
  return 1;
}

struct ExportTarget {
  std::string out;
  bool force = false;
};

bool isCsvPath(const std::filesystem::path& p) { return p.extension() == ".csv"; }

// The format follows --out's name, as for `sweep --out` (docs/results-format.md, "Export").
int runExport(const std::string& source, const ExportTarget& to) {
  if (isStorePath(to.out)) {
    checkOutputTarget(to.out, to.force, resultsOutput());
    // What `results check` refuses is never exported; checked and read in one pass, so what is written is what was
    // checked even when the source is replaced at its name meanwhile.
    writeResultsStore(readCheckedResults(source, MapDetail::Full), to.out);
    std::cout << "wrote " << escapedControlCharacters(to.out) << '\n';
    return 0;
  }
  const bool csv = isCsvPath(to.out);
  checkOutputTarget(to.out, to.force, csv ? textOutput("CSV export", "dataset,") : resultsOutput());
  const ResultsCheck checked = checkResultsFile(source, "");  // what `results check` refuses fails before writing
  if (!csv) refuseLargeJson(to.out, "the export of " + source, checked.combinations);  // as sweep into JSON does
  OutputFile out(to.out);
  if (csv) exportCsv(source, out.stream());
  else exportJson(source, out.stream());
  if (csv) out.markWritten();  // what a later --force may replace (textOutput)
  out.commit();
  std::cout << "wrote " << escapedControlCharacters(to.out) << '\n';
  return 0;
}

const RegisterCommand kResults{"results", "Check results files, compare one with a golden one, or export one (CSV, JSON, store)", [](CLI::App& app) {
  auto file = std::make_shared<std::string>();
  CLI::App* check = app.add_subcommand("check", "Exit 0 when FILE is a complete, consistent results file (docs/results-format.md)");
  auto dataset = std::make_shared<std::string>();
  addExample(*check, "occsweep results check knn.json");
  check->add_option("file", *file, "Results file")->type_name(kPath)->required();
  check->add_option("--dataset", *dataset, "Also check against this data set: its content hash, and every threshold "
                                           "counting its region's and its truth's voxels")->type_name(kPath);
  // The grid is enumerated to check every map; a JSON file is read whole.
  addLimitOptions(*check, {Limit::Combinations, Limit::JsonBytes});
  CLI::App* diff = app.add_subcommand("diff", "Exit 0 when NEW has GOLDEN's confusion counts and AUCs, else 1 with a "
                                              "table of what changed (docs/results-format.md)");
  auto golden = std::make_shared<std::string>();
  addExample(*diff, "occsweep sweep --dataset ds --grid knn-opt --engine direct --out knn-direct.json\n"
                    "occsweep results diff knn.json knn-direct.json");
  auto candidate = std::make_shared<std::string>();
  auto auc_tolerance = std::make_shared<double>(0.0);
  diff->add_option("golden", *golden, "The results file to match")->type_name(kPath)->required();
  diff->add_option("new", *candidate, "The results file to check")->type_name(kPath)->required();
  addLimitOptions(*diff, {Limit::Combinations, Limit::JsonBytes});  // as check, for each file
  diff->add_option("--auc-tolerance", *auc_tolerance, "How far an AUC may move (default 0: exactly)")
      ->check(numberAtLeast(0.0));
  auto auc_only = std::make_shared<bool>(false);
  diff->add_flag("--auc-only", *auc_only, "Compare the AUCs alone, not the confusion counts (a missing combination "
                                          "still differs)");
  CLI::App* export_ = app.add_subcommand("export", "Convert a results file or store, map by map (docs/results-format.md, "
                                                  "\"Export\"), into the format --out's name asks for: NAME.csv one "
                                                  "row per combination, NAME.db or NAME.sqlite a results store, "
                                                  "anything else the JSON results file");
  auto source = std::make_shared<std::string>();
  addExample(*export_, "occsweep results export knn.json --out knn.csv");
  auto to = std::make_shared<ExportTarget>();
  export_->add_option("file", *source, "Results file or store")->type_name(kPath)->required();
  export_->add_option("--out", to->out, "The converted file: .csv, .db/.sqlite or JSON, by its name")
      ->type_name(kPath)->required();
  export_->add_flag("--force", to->force, "Replace occsweep's own output of the same kind at the target");
  addLimitOptions(*export_, {Limit::Combinations, Limit::JsonBytes});  // as check
  app.require_subcommand(1);
  return [=] {
    return runChosen({{check, [=] {
                         const ResultsCheck f = checkResultsFile(*file, *dataset);
                         // docs/results-format.md lists what each line vouches for.
                         std::cout << escapedControlCharacters(*file) << ": complete, " << f.maps << " maps";
                         if (f.grid_checked)
                           std::cout << ", every map and threshold of the selection once, parameters match grid ";
                         else if (f.header.selection.shard_count == 1)
                           std::cout << ", every id of the selection once; grid file not found, parameters not "
                                        "checked against grid ";
                         else
                           std::cout << "; grid file not found: parameters and the shard's maps not checked against "
                                        "grid ";
                         std::cout << f.header.grid_name;
                         if (f.header.truth == TruthMode::Observable) std::cout << ", observable truth (map.truth)";
                         if (!dataset->empty())
                           std::cout << "; counts match the region and truth of " << escapedControlCharacters(*dataset);
                         std::cout << '\n';
                         return 0;
                       }},
                      {export_, [=] { return runExport(*source, *to); }},
                      {diff, [=] {
                         return runDiff(*golden, *candidate, *auc_tolerance,
                                        *auc_only ? CountsCheck::Ignored : CountsCheck::Exact);
                       }}});
  };
}};

}  // namespace
}  // namespace occsweep::cli
