// occsweep scene --out DIR: writes the built-in scene.
#include <iostream>

#include "command_registry.hpp"
#include "limit_options.hpp"
#include "option_checks.hpp"
#include "occsweep/core/limits.hpp"
#include "occsweep/core/point_cloud_set.hpp"
#include "occsweep/eval/builtin_scene.hpp"
#include "occsweep/io/output_target.hpp"
#include "occsweep/io/control_characters.hpp"

namespace occsweep::cli {
namespace {

const RegisterCommand kScene{"scene", "Write the built-in scene (four boxes in an O, an orbiting range sensor)",
                             [](CLI::App& app) {
  addExample(app, "occsweep scene --out ds --scans 8 --width 32 --height 24");
  struct Options {
    std::string out;
    BuiltinSceneConfig config;
    bool force = false;
  };
  auto o = std::make_shared<Options>();
  app.add_option("--out", o->out, "Output data-set folder (a new one, or occsweep's own with --force)")
      ->type_name(kPath)->required();
  app.add_flag("--force", o->force, "Replace occsweep's own previous data set at --out (nothing else)");
  app.add_option("--seed", o->config.seed, "Seed of noise and outliers")->capture_default_str();
  app.add_option("--scans", o->config.scans, "Keyframes over both orbits")->capture_default_str()->check(integerIn<int>(1, 100000));
  app.add_option("--width", o->config.width, "Rays per row")->capture_default_str()->check(integerIn<int>(1, 100000));
  app.add_option("--height", o->config.height, "Rows")->capture_default_str()->check(integerIn<int>(1, 100000));
  // Above a kilometre of range noise no point is near its ray, and 1e300 gave infinite coordinates.
  app.add_option("--noise", o->config.noise_sigma, "Range noise sigma, metres, from 0 to 1000")->capture_default_str()
      ->check(numberIn(0, 1000));
  app.add_option("--outliers", o->config.outlier_fraction, "Outlier fraction")->capture_default_str()->check(numberIn(0, 1));
  addLimitOptions(app, {Limit::Points});
  return [o] {
    // One point per ray: each option is bounded, and so is their product (docs/robustness.md, limits).
    const auto rays = saturatingProduct(saturatingProduct(std::uint64_t(o->config.scans), std::uint64_t(o->config.width)),
                                        std::uint64_t(o->config.height));
    checkLimit("the scene's rays (--scans x --width x --height)", rays, limits().points, "--max-points");
    checkOutputTarget(o->out, o->force, datasetOutput());
    const Dataset d = makeBuiltinScene(o->config);
    writeDataset(d, o->out);
    std::cout << "wrote " << escapedControlCharacters(o->out) << ": " << d.scans.size() << " scans, " << pointCount(d.scans) << " points\n";
    return 0;
  };
}};

}  // namespace
}  // namespace occsweep::cli
