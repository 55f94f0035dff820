// The reproduction in order: data, Fig. 3-7 step files, report.md, then the figures (drawn by the command's draw_figures).
#include <algorithm>
#include <chrono>
#include <exception>
#include <fstream>
#include <stdexcept>

#include "occsweep/io/output_file.hpp"
#include "occsweep/io/ownership.hpp"
#include "occsweep/eval/png_text.hpp"
#include "reproduce_internal.hpp"

namespace occsweep {
namespace fs = std::filesystem;
using nlohmann::json;

ReproduceConfig reproduceDefaults(const std::string& scale) {
  ReproduceConfig c;
  c.scale = scale;
  if (scale == "ci") {
    // Under 10 minutes on 2 cores with data generation (measured in docs/reproduction.md): NCA is O(n^2) per
    // objective evaluation, so 800 samples per fit and 3 folds over 3 lambdas around 1/n.
    c.nca_samples = 800, c.nca_folds = 3, c.nca_lambda_factors = {0.25, 1.0, 4.0};
    c.runtime_datasets = 4, c.runtime_repeats = 2;
  } else if (scale == "small") {
    // About 40 minutes on 2 cores after the data (docs/reproduction.md).
    c.nca_samples = 1000, c.nca_lambda_factors = {0.25, 1.0, 4.0};
    c.runtime_datasets = 4, c.runtime_repeats = 2;
  } else if (scale == "paper") {
    c.nca_samples = 0, c.runtime_datasets = 20, c.runtime_repeats = 3;
  } else {
    throw std::invalid_argument("scale '" + scale + "': must be ci, small or paper");
  }
  return c;
}

void checkReproductionSteps(const std::vector<std::string>& steps) {
  const auto known = reproductionSteps();
  auto has = [&](const std::string& name) { return std::find(steps.begin(), steps.end(), name) != steps.end(); };
  for (std::size_t i = 0; i < steps.size(); ++i) {
    if (std::find(known.begin(), known.end(), steps[i]) == known.end())
      throw std::invalid_argument("--steps: '" + steps[i] +
                                  "' is not a step (fits, nca, comparison, curves, runtime, real-stereo)");
    if (std::find(steps.begin(), steps.begin() + std::ptrdiff_t(i), steps[i]) != steps.begin() + std::ptrdiff_t(i))
      throw std::invalid_argument("--steps: '" + steps[i] + "' is given twice");
  }
  if (steps.empty()) throw std::invalid_argument("--steps: no step given");
  if (has("curves") && !has("comparison"))
    throw std::invalid_argument("--steps: curves needs comparison (Fig. 6 draws the best maps of Fig. 5's sweeps)");
}

namespace {

// The step files a reproduction writes, each proven occsweep's by its own "format" field (occsweep-reproduce-NAME).
constexpr const char* kStepFiles[] = {"fits", "nca", "comparison", "curves", "runtime", "real-stereo", "run"};

// A step file of a reproduction, proven by its own "format" field.
ReplaceableOutput stepFileOutput(const std::string& step) {
  return jsonOutput("reproduction step file", "occsweep-reproduce-" + step);
}

// report.md of a reproduction, proven by its first line.
ReplaceableOutput reportOutput() {
  return {"reproduction report", [](const fs::path& file) {
            std::ifstream in(file);
            std::string first;
            return std::getline(in, first) && first == kReproductionReportMark;
          }};
}

// An entry of a reproduction folder that is occsweep's (docs/io.md, "Ownership"): a step file whose
// "format" is its own; report.md under its first-line mark; a PNG carrying the figures' Software mark; a temporary a
// killed run left (reported, never removed: ownership.hpp); the data, sweeps and maps folders, whose every file is
// proven again when a run rewrites it (its kind's check: a data set's manifest, a results header, a map's PLY
// comment, a ranking's format). Any other name, or content without its proof, makes the folder a user's.
bool isOwnReproductionEntry(const fs::directory_entry& entry) {
  const std::string name = entry.path().filename().string();
  std::error_code ec;
  if (entry.is_symlink(ec)) return false;
  if (entry.is_directory(ec) && (name == "data" || name == "sweeps" || name == "maps")) return true;
  const fs::path stem = entry.path().stem();
  if (entry.is_regular_file(ec)) {
    if (entry.path().extension() == ".json" && std::ranges::find(kStepFiles, stem.string()) != std::end(kStepFiles))
      return stepFileOutput(stem.string()).is_own(entry.path());
    if (name == "report.md") return reportOutput().is_own(entry.path());
    if (entry.path().extension() == ".png")
      return markedPngOutput("", kReproductionFigureMark).is_own(entry.path());
  }
  return isLeftoverTemporaryOf(entry.path(), entry.path().parent_path() / outputNameOf(name));
}

// The first entry of `dir` that is not occsweep's; empty when every one is (a folder a re-run resumes in).
fs::path foreignEntry(const fs::path& dir) {
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec))
    if (!isOwnReproductionEntry(*it)) return it->path();
  return ec ? dir : fs::path();
}

// --out: new, empty, or a reproduction folder. Any other (a user's thesis.tex beside it) is refused with or without
// --force, naming the entry, so that no file of the user's is replaced.
void checkReproductionFolder(const fs::path& out) {
  std::error_code ec;
  if (fs::is_directory(fs::symlink_status(out, ec)))
    if (const fs::path foreign = foreignEntry(out); !foreign.empty())
      throw OutputError(out.string() + ": exists and is not occsweep's reproduction folder (" +
                        foreign.filename().string() + " is not one of its files: docs/io.md, \"Ownership\"); "
                        "refused with or without --force (nothing was changed): choose another --out");
  checkOutputTarget(out, true, {"reproduction folder", [](const fs::path& dir) { return foreignEntry(dir).empty(); }});
}

}  // namespace

double runReproduction(const ReproduceConfig& c) {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  checkReproductionFolder(c.out);
  // A run that fails before it finishes anything (a full disk) leaves no empty folder of its own behind; a folder
  // holding finished steps stays, for the next run to resume from (docs/robustness.md).
  struct RemoveIfEmptyOnFailure {
    fs::path made;
    ~RemoveIfEmptyOnFailure() {
      std::error_code ec;
      if (!made.empty() && std::uncaught_exceptions() > 0) fs::remove(made, ec);  // refuses a non-empty folder
    }
  } cleanup{fs::exists(c.out) ? fs::path() : c.out};
  fs::create_directories(c.out);
  json timing = json::object();
  auto step = [&](const char* name, auto&& fn) {
    const auto t0 = Clock::now();
    if (!c.quiet) std::fprintf(stderr, "reproduce: %s\n", name);
    auto result = fn();
    timing[name] = std::chrono::duration<double>(Clock::now() - t0).count();
    return result;
  };
  // real-stereo brings its own data: a run of it alone generates no rendered data set.
  const bool rendered = std::any_of(c.steps.begin(), c.steps.end(), [](const std::string& s) { return s != "real-stereo"; });
  const auto datasets = rendered ? step("data", [&] { return prepareDatasets(c); }) : std::vector<RankedDataset>{};
  ReproductionResults r;
  r.datasets = datasets.size();
  if (!datasets.empty()) r.generator_options = datasets.front().generator_options;
  auto runs = [&](const std::string& name) { return std::find(c.steps.begin(), c.steps.end(), name) != c.steps.end(); };
  // Each file is checked again just before it is written: one a user put at its name while the run went on is
  // refused, not replaced (the commit replaces only what this check accepted: output_file.hpp).
  auto writeStepFile = [&](const std::string& name, const json& result) {
    const fs::path file = c.out / (name + ".json");
    checkOutputTarget(file, true, stepFileOutput(name));
    writeJsonAtomically(result, file);
  };
  auto stepFile = [&](const char* name, auto&& fn) {
    if (!runs(name)) return json();
    const json result = step(name, fn);
    writeStepFile(name, result);
    return result;
  };
  r.fits = stepFile("fits", [&] { return runDistributionFits(c, datasets); });
  r.nca = stepFile("nca", [&] { return runNcaWeights(c, datasets); });
  r.comparison = stepFile("comparison", [&] { return runOptimalComparison(c, datasets); });
  r.curves = stepFile("curves", [&] { return runCurvesAndMaps(c, datasets, r.comparison); });
  r.runtime = stepFile("runtime", [&] { return runRuntimeModels(c, datasets); });
  r.real_stereo = stepFile("real-stereo", [&] { return runRealStereo(c); });
  checkOutputTarget(c.out / "report.md", true, reportOutput());
  writeFileAtomically(c.out / "report.md", reproductionReport(c, r));
  if (c.draw_figures) step("figures", [&] { return c.draw_figures(c.out, c.steps), 0; });
  const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
  timing["total"] = seconds;
  writeStepFile("run", {{"format", "occsweep-reproduce-run"}, {"scale", c.scale}, {"seconds", timing},
                       {"datasets", datasets.size()}, {"nca_samples", c.nca_samples}, {"nca_folds", c.nca_folds},
                       {"seed", c.seed}, {"figures", bool(c.draw_figures)}, {"steps", c.steps},
                       {"realistic", c.realistic}, {"generator_options", r.generator_options}});
  return seconds;
}

}  // namespace occsweep
