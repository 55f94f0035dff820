// occsweep plot (docs/statistics.md, "Figures"): each figure is drawn, and its --json holds the numbers the
// comparison and the results files give, recomputed here by brute force.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <map>

#include "occsweep/eval/bounded_read.hpp"
#include "occsweep/sweeps/results.hpp"
#include "test_helpers.hpp"

using namespace occsweep;
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

bool haveMatplotlib() { return std::system("/usr/bin/python3 -c 'import matplotlib, numpy' >/dev/null 2>&1") == 0; }

const fs::path kGolden = fs::path(OCCSWEEP_SOURCE_DIR) / "results" / "builtin";

std::string goldenFiles() {
  return (kGolden / "octomap-opt.json").string() + " " + (kGolden / "knn-opt.json").string();
}

// Draws `kind` from the golden files into DIR/KIND.png and returns its data.
json plot(const fs::path& dir, const std::string& kind, const std::string& extra = "") {
  const auto r = test::runIn(dir, "plot " + kind + " " + goldenFiles() + " --out " + kind + ".png --json " + kind +
                                      ".json" + extra);
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  const std::string png = test::bytesOf(dir / (kind + ".png"));
  CHECK(png.starts_with("\x89PNG"));
  CHECK(png.size() > 10000);
  const json data = readJsonFile(dir / (kind + ".json"));
  CHECK(data.at("kind") == kind);
  return data;
}

double bestAuc(const ResultsFile& f) {
  double best = -1;
  for (const auto& m : f.maps) best = std::max(best, m.area.anchored);
  return best;
}

}  // namespace

TEST_CASE("plot draws each figure from the golden files, and its data is what the results give") {
  if (!haveMatplotlib()) {
    WARN("no matplotlib: occsweep plot cannot draw here");
    return;
  }
  const auto dir = test::processScratch("plot");
  const ResultsFile om = readResults(kGolden / "octomap-opt.json"), knn = readResults(kGolden / "knn-opt.json");

  const json budget = plot(dir, "budget");
  CHECK(budget.at("baseline_best").get<double>() == bestAuc(om));
  for (const auto& m : budget.at("methods")) {
    const ResultsFile& f = m.at("method") == "knn" ? knn : om;
    CHECK(m.at("curve").size() == f.maps.size());
    CHECK(m.at("curve").back().get<double>() == bestAuc(f));  // every map tried: the grid's best
    double mean = 0;
    for (const auto& map : f.maps) mean += map.area.anchored / double(f.maps.size());
    CHECK(m.at("curve").front().get<double>() == Approx(mean).epsilon(1e-12));  // one map: the grid's mean
  }

  const json improvement = plot(dir, "improvement");
  REQUIRE(improvement.at("methods").size() == 1);
  const json point = improvement.at("methods").at(0).at("points").at(0);
  CHECK(point.at(0).get<double>() == bestAuc(om));
  CHECK(point.at(1).get<double>() == Approx((bestAuc(knn) - bestAuc(om)) / bestAuc(om) * 100.0).epsilon(1e-12));

  const json params = plot(dir, "params", " --method knn");
  std::map<std::string, std::map<double, std::pair<double, int>>> brute;  // name -> value -> (sum, count)
  for (const auto& m : knn.maps)
    for (std::size_t i = 0; i < knn.header.parameters.names.size(); ++i) {
      auto& [sum, n] = brute[knn.header.parameters.names[i]][toDouble(m.params.values[i])];
      sum += m.area.anchored, ++n;
    }
  CHECK(params.at("parameters").size() == 4);  // p_u, p_l, p_m, p_m_out vary; k, p_max, p_min do not
  for (const auto& p : params.at("parameters"))
    for (std::size_t v = 0; v < p.at("values").size(); ++v) {
      const auto& [sum, n] = brute.at(p.at("name")).at(p.at("values").at(v).get<double>());
      CHECK(p.at("mean").at(v).get<double>() == Approx(sum / n).epsilon(1e-12));
    }

  const json curves = plot(dir, "curves");
  REQUIRE(curves.at("sets").size() == 1);
  for (const auto& m : curves.at("sets").at(0).at("methods")) {
    CHECK(m.at("points").size() >= 2);
    for (const auto& xy : m.at("points")) CHECK((xy.at(0) >= 0.0 && xy.at(0) <= 1.0 && xy.at(1) >= 0.0 && xy.at(1) <= 1.0));
  }
}

TEST_CASE("plot never replaces a file it did not draw, and refuses a figure kind it does not know") {
  const auto dir = test::processScratch("plot-refusals");
  std::ofstream(dir / "photo.png") << "\x89PNG not ours";
  const auto r = test::runIn(dir, "plot budget " + goldenFiles() + " --out photo.png --force");
  CHECK(r.exit_code == 2);
  CHECK(test::bytesOf(dir / "photo.png") == "\x89PNG not ours");
  CHECK(test::runIn(dir, "plot pie " + goldenFiles() + " --out x.png").exit_code == 2);
}

TEST_CASE("plot writes PNG, PDF or SVG by --out's ending, refuses any other before drawing, and gives each method "
          "one colour in every figure") {
  // Old binary: --out fig.pdf and fig.svg held PNG bytes, exit 0; range-octomap was green in one figure and orange
  // in another (colours by each figure's sorted methods).
  if (!haveMatplotlib()) {
    WARN("no matplotlib: occsweep plot cannot draw here");
    return;
  }
  const auto dir = test::processScratch("plot-formats");
  REQUIRE(test::runIn(dir, "scene --out ds").exit_code == 0);
  std::string files;
  for (const std::string grid : {"octomap-opt", "knn-opt", "range-octomap-opt"}) {
    REQUIRE(test::runIn(dir, "sweep --dataset ds --quiet --grid " + grid + " --out " + grid + ".json").exit_code == 0);
    files += " " + grid + ".json";
  }
  const std::map<std::string, std::string> magic = {{"png", "\x89PNG"}, {"pdf", "%PDF-"}, {"svg", "<?xml"}};
  for (const auto& [format, start] : magic) {
    const auto r = test::runIn(dir, "plot budget" + files + " --out b." + format);
    INFO(r.output);
    REQUIRE(r.exit_code == 0);
    CHECK(test::bytesOf(dir / ("b." + format)).starts_with(start));
  }
  // Its own PDF is replaced with --force; a user's, however it starts, never.
  CHECK(test::runIn(dir, "plot budget" + files + " --out b.pdf --force").exit_code == 0);
  std::ofstream(dir / "mine.pdf") << "%PDF-1.4 occsweep plot, my own";
  const auto mine = test::runIn(dir, "plot budget" + files + " --out mine.pdf --force");
  CHECK(mine.exit_code == 2);
  CHECK(test::bytesOf(dir / "mine.pdf") == "%PDF-1.4 occsweep plot, my own");
  for (const std::string other : {"b.jpg", "b", "b.png.txt"}) {
    const auto r = test::runIn(dir, "plot budget" + files + " --out " + other);
    INFO(r.output);
    CHECK(r.exit_code == 2);
    CHECK(r.output.find("a figure is PNG, PDF or SVG") != std::string::npos);
    CHECK_FALSE(fs::exists(dir / other));
  }
  // One colour per method: range-octomap's (#CC79A7, docs/statistics.md) in each figure that draws it.
  for (const std::string kind : {"curves", "budget", "improvement"}) {
    const auto r = test::runIn(dir, "plot " + kind + files + " --out " + kind + ".svg");
    INFO(kind << ": " << r.output);
    REQUIRE(r.exit_code == 0);
    std::string svg = test::bytesOf(dir / (kind + ".svg"));
    std::transform(svg.begin(), svg.end(), svg.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    CHECK(svg.find("#cc79a7") != std::string::npos);  // range-octomap
    CHECK(svg.find("#d55e00") != std::string::npos);  // knn
  }
}
