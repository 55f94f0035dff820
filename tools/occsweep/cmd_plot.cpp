// occsweep plot curves|budget|improvement|params FILES... --out FIG.{png,pdf,svg} [--json DATA.json]: the figures of a
// comparison for the user's own sweeps, drawn by share/occsweep/plot_results.py from the data computed here
// (docs/statistics.md, "Figures").
#include <algorithm>
#include <charconv>
#include <cmath>
#include <optional>
#include <cctype>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <map>
#include <iostream>
#include <sys/stat.h>

#include "command_registry.hpp"
#include "limit_options.hpp"
#include "compare_tables.hpp"
#include "figure_script.hpp"
#include "method_style.hpp"
#include "option_checks.hpp"
#include "plot_data.hpp"
#include "occsweep/sweeps/baseline.hpp"
#include "occsweep/core/method_registry.hpp"
#include "occsweep/io/child_process.hpp"
#include "occsweep/io/data_error.hpp"
#include "occsweep/io/output_file.hpp"
#include "occsweep/io/ownership.hpp"
#include "occsweep/eval/png_text.hpp"
#include "occsweep/io/control_characters.hpp"

namespace occsweep::cli {
namespace {

struct PlotOptions {
  std::vector<std::string> files;
  std::string out, json, baseline = kDefaultBaseline, method, python, style;
  std::optional<std::string> width;  ///< --print-width as given
  double font_size = 0;  ///< 0: 8 pt at a --print-width, else 10 pt
  bool force = false;
};

// Print widths (docs/statistics.md, "Figures"): a column and a page of the common two-column layouts (IEEE, ACM:
// 3.5 in and 7.16 in); any other width in inches.
constexpr double kColumnInches = 3.5, kPageInches = 7.16, kMinWidthInches = 1.5, kMaxWidthInches = 20;

// --print-width as inches; 0 without one (the screen sizes of each figure).
double figureWidthInches(const std::optional<std::string>& given) {
  if (!given) return 0;
  const std::string& width = *given;
  if (width == "column") return kColumnInches;
  if (width == "page") return kPageInches;
  double inches = 0;
  const char* const last = width.data() + width.size();
  const auto [end, error] = std::from_chars(width.data(), last, inches);  // no sign, hex or space
  if (error != std::errc() || end != last || !(inches >= kMinWidthInches && inches <= kMaxWidthInches))
    throw std::invalid_argument("--print-width must be column, page or a width in inches from 1.5 to 20, got " + width);
  return inches;
}

// How the figure is laid out and each method drawn: the print width (figureWidthInches), the font size and every
// method's style.
nlohmann::json figureStyle(const PlotOptions& o, double width, const StyleOverrides& overrides,
                           const std::vector<ComparisonRow>& rows) {
  for (const std::string& m : unknownStyledMethods(overrides, comparedMethods(rows)))
    std::cerr << "occsweep plot: warning: " << o.style << ": methods." << m << ": no method of that name is registered "
              << "or in this figure (registered: " << registeredMethodNames() << "); its style is not used\n";
  return {{"width_in", width > 0 ? nlohmann::json(width) : nlohmann::json(nullptr)},
          {"font_size", o.font_size > 0 ? o.font_size : width > 0 ? 8.0 : 10.0},
          {"methods", methodStyles(comparedMethods(rows), overrides, o.style)}};
}

// The figure's format, by --out's name: PNG for the screen, PDF and SVG for print (docs/statistics.md, "Figures").
std::string figureFormat(const std::string& out) {
  std::string ending = std::filesystem::path(out).extension().string();
  std::transform(ending.begin(), ending.end(), ending.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  for (const char* format : {"png", "pdf", "svg"})
    if (ending == std::string(".") + format) return format;
  throw std::invalid_argument("--out " + out + ": a figure is PNG, PDF or SVG, chosen by the name's ending (.png, "
                              ".pdf or .svg)");
}

// Whether `file` is a figure occsweep plot drew: a regular file with one name, the format's first bytes and the
// script's mark (a PNG's Software text chunk exactly "occsweep plot", written by plot_results.py; a PDF's or SVG's
// Creator). What --force may replace (docs/io.md, "Ownership"), and how a script that exits 0 without
// drawing is caught: it leaves no empty figure behind.
bool drewFigure(const std::filesystem::path& file, const std::string& format) {
  if (format == "png") return markedPngOutput("figure", "occsweep plot").is_own(file);
  constexpr std::uint64_t kMaxFigureBytes = std::uint64_t(256) << 20;  // a figure is a few MB; a huge file is not one
  struct stat st {};
  if (::lstat(file.c_str(), &st) != 0 || !S_ISREG(st.st_mode) || st.st_nlink != 1 ||
      std::uint64_t(st.st_size) > kMaxFigureBytes)
    return false;
  std::ifstream in(file, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  return bytes.starts_with(format == "pdf" ? "%PDF-" : "<?xml") && bytes.find("occsweep plot") != std::string::npos;
}

// A PDF's or SVG's metadata a user could write as easily: only the bytes occsweep marked are its own to replace.
ReplaceableOutput figureOutput(const std::string& format) {
  return {"figure", [format](const std::filesystem::path& file) {
            return drewFigure(file, format) && (format == "png" || holdsMarkedBytes(file));
          }};
}

// The method `params` draws: --method, or the only one given, or the first that is not the baseline.
std::string paramsMethod(const PlotOptions& o, const std::vector<ComparisonRow>& rows) {
  if (!o.method.empty()) return o.method;
  const std::vector<std::string> methods = comparedMethods(rows);
  for (const std::string& m : methods)
    if (m != o.baseline || methods.size() == 1) return m;
  throw std::invalid_argument("plot params: no method to draw (--method)");
}

// A figure of curves or AUCs from a file that has none would be drawn empty, or would lose that file's set without a
// word: each file with no map of a defined AUC is refused, naming it and why (compare names it in a note).
void requireAucs(const std::vector<ResultsFile>& in, const std::vector<std::string>& names) {
  for (std::size_t i = 0; i < in.size(); ++i) {
    const ResultsFile& f = in[i];
    const bool any = std::any_of(f.maps.begin(), f.maps.end(), [](const MapResult& m) { return std::isfinite(m.area.anchored); });
    if (any) continue;
    const std::string why = f.truth_voxels == 0 ? "its data set " + f.header.dataset_name + " has no ground truth (TP+FN = "
                                                  "0), so TPR and AUC are undefined (add it with occsweep import truth)"
                                                : "every map's AUC is undefined";
    throw DataError(names[i], "", "no map has an AUC: " + why + "; a figure needs AUCs (nothing drawn)");
  }
}

int runPlot(const std::string& kind, const PlotOptions& o) {
  const std::string format = figureFormat(o.out);
  const double width = figureWidthInches(o.width);  // refused before anything is read
  const StyleOverrides overrides = o.style.empty() ? StyleOverrides{} : readStyleFile(o.style);
  requireSeparateOutputs({{"--out", o.out}, {"--json", o.json}});
  checkOutputTarget(o.out, o.force, figureOutput(format));
  if (!o.json.empty()) checkOutputTarget(o.json, o.force, jsonOutput("plot data", "occsweep-plot"));
  const std::string python = findPython(o.python, "plot");  // before any work: fail now if it cannot draw
  const std::string script = figureScript("plot_results.py").string();
  const std::vector<ResultsFile> in = readChecked(o.files, MapDetail::Full);
  requireAucs(in, o.files);
  const std::vector<ComparisonRow> rows = compareBest(in);
  const PlotInputs inputs{rows, in, o.baseline, kind == "params" ? paramsMethod(o, rows) : ""};
  nlohmann::json data = plotData(kind, inputs);
  data["format"] = "occsweep-plot";
  data["figure_format"] = format;
  data["style"] = figureStyle(o, width, overrides, rows);
  data["files"] = o.files;
  // Both written as registered temporaries (removed on an error or an interrupt) and committed only when the script
  // succeeded; the script draws into the figure's temporary, never beside it.
  OutputFile data_file(o.json.empty() ? o.out + ".data.json" : o.json);
  data_file.stream() << data.dump(1) << '\n';
  data_file.finish();
  OutputFile figure(o.out);
  figure.finish();
  const int code = runChild({python, script, data_file.temporary().string(), figure.temporary().string()});
  if (code != 0) throw std::runtime_error("plot: " + python + " " + script + " failed (exit code " + std::to_string(code) + ")");
  // A script that exits 0 without drawing (another Python, another script) leaves no empty figure behind.
  if (!drewFigure(figure.temporary(), format))
    throw std::runtime_error("plot: " + python + " " + script + " exited 0 but drew no figure (nothing written)");
  if (format != "png") markWrittenBytes(figure.temporary());  // what a later --force may replace (figureOutput)
  if (o.json.empty()) figure.commit();
  else OutputFile::commitTogether({&data_file, &figure});  // neither when the other's name was taken meanwhile
  std::cout << "wrote " << escapedControlCharacters(o.out) << (o.json.empty() ? "" : " and " + escapedControlCharacters(o.json)) << '\n';
  return 0;
}

const RegisterCommand kPlot{"plot", "Figures of a comparison: best curves, budget curves, improvement, AUC by "
                                    "parameter (docs/statistics.md)",
                            [](CLI::App& app) {
  auto o = std::make_shared<PlotOptions>();
  auto subs = std::make_shared<std::vector<std::pair<std::string, CLI::App*>>>();
  const std::map<std::string, std::string> what = {
      {"curves", "TPR against FDR of each method's best map on each set (up to 12 sets)"},
      {"budget", "each method's expected best AUC against the number of maps tried, and the baseline's best"},
      {"improvement", "per set, the improvement over the baseline against the baseline's AUC, with the mean's "
                      "95 % interval (Fig. 5)"},
      {"params", "AUC against each parameter: mean and best over the maps with each value (the grid's marginal)"}};
  for (const std::string& k : kPlotKinds) {
    CLI::App* sub = app.add_subcommand(k, what.at(k));
    addExample(*sub, "occsweep plot " + k + " oct.json knn.json --out " + k + ".png\n"
                     "occsweep plot " + k + " oct.json knn.json --print-width column --out " + k + ".pdf");
    sub->add_option("files", o->files, "Complete results files (as for compare)")->type_name(kPath)->required();
    sub->add_option("--out", o->out, "The figure: PNG, PDF or SVG by the name's ending (.png, .pdf, .svg)")
        ->type_name(kPath)->required();
    sub->add_option("--json", o->json, "Also write the plotted data")->type_name(kPath);
    sub->add_option("--baseline", o->baseline, "Method the others are measured against")->capture_default_str();
    if (k == "params") sub->add_option("--method", o->method, "Method whose grid is drawn (default: the first not the baseline)");
    sub->add_option("--style", o->style, "A style file: each method's display name, colour, marker and line "
                                         "(docs/statistics.md, \"Figures\")")->type_name(kPath);
    sub->add_option("--print-width", o->width, "Width in print: column (3.5 in), page (7.16 in) or inches; no "
                                               "title then, the caption says it (default: a screen size)");
    sub->add_option("--font-size", o->font_size, "Text size, points (default 8 at a --print-width, else 10)")
        ->check(numberIn(6, 24));
    sub->add_option("--python", o->python, "Python 3 with matplotlib (default $OCCSWEEP_PYTHON, /usr/bin/python3)")
        ->type_name(kPath);
    sub->add_flag("--force", o->force, "Replace occsweep's own previous figure or data (nothing else)");
    addLimitOptions(*sub, {Limit::Combinations, Limit::JsonBytes});
    subs->emplace_back(k, sub);
  }
  app.require_subcommand(1);
  return [o, subs] {
    for (const auto& [k, sub] : *subs)
      if (sub->parsed()) return runPlot(k, *o);
    return 2;  // unreachable: CLI11 requires one subcommand
  };
}};

}  // namespace
}  // namespace occsweep::cli
