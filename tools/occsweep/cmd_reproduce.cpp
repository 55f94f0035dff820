// occsweep reproduce: every experiment of the paper's Section 4 (Fig. 3-7) in one command (docs/reproduction.md).
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "cmd_dataset.hpp"
#include "cmd_dataset_middlebury.hpp"
#include "command_registry.hpp"
#include "figure_script.hpp"
#include "install_paths.hpp"
#include "option_checks.hpp"
#include "occsweep/io/child_process.hpp"
#include "occsweep/io/output_file.hpp"
#include "occsweep/eval/paper_datasets.hpp"
#include "occsweep/eval/png_text.hpp"
#include "occsweep/sweeps/reproduce.hpp"
#include "occsweep/io/temporaries.hpp"

namespace occsweep::cli {
namespace {

struct ReproduceOptions {
  std::string scale = "ci", out, data, python;
  std::vector<std::string> datasets;
  std::vector<std::string> steps = reproductionSteps();
  std::uint64_t seed = 1;
  long nca_samples = -1;
  int runtime_repeats = 0;
  int threads = 0;
  bool no_figures = false, quiet = false, realistic = false;
};

// A figure the script drew, moved into OUT: over nothing, or over a figure of an earlier reproduction (its Software
// chunk, kReproductionFigureMark); a user's PNG at that name stays and the run fails naming it.
void placeFigure(const std::filesystem::path& drawn, const std::filesystem::path& out) {
  const std::filesystem::path target = out / drawn.filename();
  checkOutputTarget(target, true, markedPngOutput("reproduction figure", kReproductionFigureMark));
  renameIntoPlace(drawn, target);
}

/// The figures: plot_reproduction.py (installed beside the binary, install_paths.hpp) on the step files. Python and
/// the script are looked up now, so that a run cannot fail at its end for want of them.
auto figureDrawer(const std::string& configured_python) {
  const std::string python = findPython(configured_python, "reproduce");
  const std::string script = figureScript("plot_reproduction.py").string();
  return [python, script](const std::filesystem::path& out, const std::vector<std::string>& steps) {
    const RegisteredTemporary drawn(out / "figures", TemporaryKind::Folder);  // the script draws here; removed whatever happens
    std::vector<std::string> argv{python, script, out.string(), "--into", drawn.path().string()};
    argv.insert(argv.end(), steps.begin(), steps.end());
    if (const int code = runChild(argv); code != 0)
      throw std::runtime_error("reproduce: " + python + " " + script + " failed (exit code " + std::to_string(code) +
                               ")");
    for (const auto& figure : std::filesystem::directory_iterator(drawn.path())) placeFigure(figure.path(), out);
  };
}

/// Missing data sets: `dataset generate --name NAME --scale SCALE --out OUT --no-preview --force [--realistic]`, the
/// command's own code in this process. --force: a data set a killed reproduction began (sets without their
/// ranking) is regenerated over its own sets, each proven occsweep's; a user's file there is still refused.
auto datasetGenerator(bool quiet) {
  return [quiet](const std::string& name, const std::string& scale, const std::filesystem::path& out, bool realistic) {
    DatasetOptions o;
    o.name = name, o.scale = scale, o.out = out.string();
    o.no_preview = true, o.realistic = realistic, o.quiet = quiet, o.force = true;
    generateDatasets(o);
  };
}

/// The real-stereo step's sets: `dataset middlebury --leaf RESOLUTION [--voxel-filter LEAF | --no-voxel-filter]` on the
/// Aloe pair of Debian's opencv-doc, the command's own code in this process; or why the pair is not there.
auto realStereoWriter() {
  return [](const std::filesystem::path& folder, double resolution, double filter_leaf) {
    MiddleburyOptions o = middleburyDefaults();
    o.out = folder.string(), o.leaf = resolution;
    o.no_voxel_filter = filter_leaf == 0, o.voxel_filter = filter_leaf;
    RealStereoSets sets;
    sets.not_available = middleburyUnavailable(o);
    if (!sets.not_available.empty()) return sets;
    sets.pair = "Middlebury 2006 Aloe, full size (" + o.left + ", " + o.right + ", " + o.gt +
                "), as `occsweep dataset middlebury --leaf RESOLUTION [--voxel-filter LEAF | --no-voxel-filter]` writes it";
    const MiddleburySetsWritten written = writeMiddleburySets(o, true);
    sets.folders = written.folders;
    sets.ids.assign(written.ids.begin(), written.ids.end());
    sets.points = written.points;
    return sets;
  };
}

const RegisterCommand kReproduce{"reproduce",
                                 "Reproduce the paper's Section 4: distribution fits, NCA weights, optimal-AUC "
                                 "comparison, curves and maps, run-time models; report.md and five figures",
                                 [](CLI::App& app) {
  addExample(app, "occsweep reproduce --scale ci --name building-plain-I --steps fits --no-figures --out repro");
  auto o = std::make_shared<ReproduceOptions>();
  app.add_option("--scale", o->scale, "ci (under 10 min on 2 cores), small, paper: data scale and reductions")
      ->check(CLI::IsMember({"ci", "small", "paper"}))->capture_default_str();
  app.add_option("--out", o->out, "Output folder: *.json, report.md, fig*.png, maps/, sweeps/, data/")
      ->type_name(kPath)->required();
  app.add_option("--data-root", o->data, "Folder of generated data sets to use, one folder per name (default "
                                       "OUT/data; missing ones are generated)")->type_name(kPath);
  app.add_option("--name", o->datasets, "Only this paper data set (repeatable; default: the paper's 20)");
  app.add_flag("--realistic", o->realistic, "Data with the realism options the experiments of docs/fidelity.md point "
               "to (dataset generate --realistic); report.md says which data was used");
  app.add_option("--steps", o->steps, "Only these steps: fits, nca, comparison, curves (needs comparison), runtime, "
                 "real-stereo (default all; docs/reproduction.md)")->delimiter(',');
  app.add_option("--seed", o->seed, "Eq. 16 split of the reduction grid, NCA subsample and folds")->capture_default_str();
  app.add_option("--nca-samples", o->nca_samples, "NCA samples per data set and response (0: all; default per scale)")
      ->check(integerAtLeast<long>(0));
  app.add_option("--runtime-repeats", o->runtime_repeats, "Times each Fig. 7 build is timed, fastest kept (default per scale)")
      ->check(integerAtLeast<int>(1));
  app.add_option("--threads", o->threads, "Worker threads (0: all cores)")->capture_default_str()->check(threadCount());
  app.add_option("--python", o->python, "Python 3 with matplotlib for the figures (default: search)")->type_name(kPath);
  app.add_flag("--no-figures", o->no_figures, "JSON and report.md only");
  app.add_flag("--quiet", o->quiet, "No progress on stderr");
  return [o] {
    ReproduceConfig c = reproduceDefaults(o->scale);
    c.out = o->out;
    c.data = o->data;
    c.datasets = o->datasets;
    c.realistic = o->realistic;
    c.seed = o->seed;
    checkReproductionSteps(o->steps);
    c.steps = o->steps;
    if (o->nca_samples >= 0) c.nca_samples = std::size_t(o->nca_samples);
    c.threads = o->threads;
    if (o->runtime_repeats > 0) c.runtime_repeats = o->runtime_repeats;
    c.quiet = o->quiet;
    c.generate_dataset = datasetGenerator(o->quiet);
    c.write_real_stereo = realStereoWriter();
    const auto known = paperDatasetNames();
    for (const auto& d : c.datasets)
      if (std::find(known.begin(), known.end(), d) == known.end())
        throw std::invalid_argument("--name: '" + d + "' is not one of the paper's 20 (docs/datasets.md)");
    if (!o->no_figures) c.draw_figures = figureDrawer(o->python);  // before hours of work: fail now if it cannot
    const double seconds = runReproduction(c);
    std::printf("reproduce --scale %s: %.1f s; report %s/report.md\n", c.scale.c_str(), seconds, c.out.string().c_str());
    return 0;
  };
}};

}  // namespace
}  // namespace occsweep::cli
