// occsweep plot (docs/statistics.md, "Figures"): each figure is drawn, and its --json holds the numbers the
// comparison and the results files give, recomputed here by brute force.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <map>
#include <optional>

#include "occsweep/io/bounded_read.hpp"
#include "occsweep/sweeps/results.hpp"
#include "occsweep/eval/json_input.hpp"
#include "test_helpers.hpp"

using namespace occsweep;
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

bool haveMatplotlib() { return std::system("/usr/bin/python3 -c 'import matplotlib, numpy' >/dev/null 2>&1") == 0; }

const fs::path kGolden = occsweep::test::sourceTree() / "results" / "builtin";

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
  // One colour per method: range-octomap's (#CC79A7, docs/statistics.md) in each figure that draws it, and each
  // method's whole style (colour, marker, line) read back from every figure's data the same.
  std::optional<json> first_styles;
  for (const std::string kind : {"curves", "budget", "improvement"}) {
    const auto r = test::runIn(dir, "plot " + kind + files + " --out " + kind + ".svg --json " + kind + ".json");
    INFO(kind << ": " << r.output);
    REQUIRE(r.exit_code == 0);
    const json styles = readJsonFile(dir / (kind + ".json")).at("style").at("methods");
    for (const char* method : {"octomap", "knn", "range-octomap"}) CHECK(styles.contains(method));
    if (!first_styles) first_styles = styles;
    CHECK(styles == *first_styles);
    CHECK(styles.at("range-octomap").at("colour") == "#CC79A7");
    std::string svg = test::bytesOf(dir / (kind + ".svg"));
    std::transform(svg.begin(), svg.end(), svg.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    CHECK(svg.find("#cc79a7") != std::string::npos);  // range-octomap
    CHECK(svg.find("#d55e00") != std::string::npos);  // knn
  }
}

TEST_CASE("every plot of results without AUCs (a data set without truth) ends with a message naming the file, exit 2, "
          "nothing written") {
  // Old binary: curves and budget wrote empty figures, exit 0; improvement and params blamed the baseline or the
  // parameters.
  const auto dir = test::processScratch("plot-no-truth");
  {
    std::ofstream cloud(dir / "a.xyz");
    for (int i = 0; i < 200; ++i) cloud << 1 + 0.01 * i << " 0.5 " << 0.02 * (i % 50) << '\n';
  }
  REQUIRE(test::runIn(dir, "import cloud a.xyz --out nt").exit_code == 0);  // no --truth: no truth voxel
  REQUIRE(test::runIn(dir, "sweep --dataset nt --grid octomap-opt --grid knn-opt --quiet --out oct.json --out "
                           "knn.json").exit_code == 0);
  for (const std::string kind : {"curves", "budget", "improvement", "params --method knn"})
    for (const std::string format : {"png", "pdf", "svg"}) {
      const auto r = test::runIn(dir, "plot " + kind + " oct.json knn.json --out fig." + format + " --json fig.json");
      INFO(kind << " " << format << ": " << r.output);
      CHECK(r.exit_code == 2);
      CHECK(r.output.find("oct.json: no map has an AUC: its data set nt has no ground truth (TP+FN = 0)") !=
            std::string::npos);
      CHECK(r.output.find("Traceback") == std::string::npos);
      CHECK_FALSE(fs::exists(dir / ("fig." + format)));
      CHECK_FALSE(fs::exists(dir / "fig.json"));
    }
}

TEST_CASE("a style file's misspelt method is named in a warning, a registered method the figure does not draw is not") {
  // Old binary: the misspelt method's style was silently not used.
  if (!haveMatplotlib()) {
    WARN("no matplotlib: occsweep plot cannot draw here");
    return;
  }
  const auto dir = test::processScratch("plot-style-unknown");
  std::ofstream(dir / "style.json") << R"json({"methods": {"kmn": {"colour": "#112233"},
      "sor-octomap": {"colour": "#445566"}, "knn": {"colour": "#778899"}}})json";
  const auto r = test::runIn(dir, "plot budget " + goldenFiles() + " --style style.json --out budget.svg");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  CHECK(r.output.find("occsweep plot: warning: style.json: methods.kmn: no method of that name is registered or in "
                      "this figure (registered: ") != std::string::npos);
  CHECK(r.output.find("methods.sor-octomap") == std::string::npos);  // registered, drawn in other figures
  CHECK(r.output.find("methods.knn") == std::string::npos);
  const std::string svg = test::bytesOf(dir / "budget.svg");
  CHECK(svg.find("#778899") != std::string::npos);  // the other entries still apply
}

TEST_CASE("a style file names, colours, marks and lines a method alike in every figure, --print-width prints at that "
          "width, and a bad style is refused naming its field") {
  // Old binary: no --style, --print-width or --font-size, and figures named methods by their identifiers.
  if (!haveMatplotlib()) {
    WARN("no matplotlib: occsweep plot cannot draw here");
    return;
  }
  const auto dir = test::processScratch("plot-style");
  std::ofstream(dir / "style.json")
      << R"json({"methods": {"knn": {"name": "k-NN (ours)", "colour": "#112233", "marker": "D", "line": "dotted"}}})json";
  for (const std::string kind : {"curves", "budget", "improvement"}) {
    const auto r = test::runIn(dir, "plot " + kind + " " + goldenFiles() + " --style style.json --print-width column --out " +
                                        kind + ".svg --json " + kind + ".json");
    INFO(kind << ": " << r.output);
    REQUIRE(r.exit_code == 0);
    const std::string svg = test::bytesOf(dir / (kind + ".svg"));
    CHECK(svg.find("width=\"252pt\"") != std::string::npos);  // 3.5 in, a column: the size it prints at
    CHECK(svg.find("k-NN (ours)") != std::string::npos);      // text stays text, under its display name
    CHECK(svg.find("#112233") != std::string::npos);
    CHECK(svg.find("OctoMap") != std::string::npos);          // the registry's display name of octomap
    const json style = readJsonFile(dir / (kind + ".json")).at("style");
    CHECK(style.at("width_in") == 3.5);
    CHECK(style.at("font_size") == 8.0);
    CHECK(style.at("methods").at("knn") == json{{"name", "k-NN (ours)"}, {"colour", "#112233"}, {"marker", "D"},
                                                 {"line", "dotted"}, {"dash", {1, 1.65}}});
    CHECK(style.at("methods").at("octomap") == json{{"name", "OctoMap"}, {"colour", "#000000"}, {"marker", "o"},
                                                    {"line", "solid"}, {"dash", json::array()}});
  }
  // A page wide, at the screen's size without --print-width.
  const std::string page = " --print-width page --font-size 9 --out page.svg";
  REQUIRE(test::runIn(dir, "plot budget " + goldenFiles() + page).exit_code == 0);
  CHECK(test::bytesOf(dir / "page.svg").find("width=\"515.52pt\"") != std::string::npos);  // 7.16 in
  // Each bad style or size: exit 2, the file and field named with the rule, nothing written.
  const std::vector<std::pair<std::string, std::string>> bad = {
      {R"({"methods": {"knn": {"colour": "red"}}})", "bad.json: methods.knn.colour: must be a colour #RRGGBB, got 'red'"},
      {R"({"methods": {"knn": {"shape": "o"}}})", "bad.json: methods.knn.shape: unknown field"},
      {R"({"methods": {"knn": {"marker": "q"}}})", "bad.json: methods.knn.marker: must be one of 'o', 's'"},
      {R"({"methods": {"knn": {"line": "wavy"}}})", "bad.json: methods.knn.line: must be one of 'solid'"},
      {R"({"methods": {"knn": {"name": ""}}})", "bad.json: methods.knn.name: must be 1 to 60 characters"},
      {R"({"methods": {"knn": {"name": "ab\u202ecd"}}})", "bad.json: methods.knn.name: must be 1 to 60 characters"},
      {R"({"methods": {"knn": {"name": 3}}})", "bad.json: methods.knn.name: must be a string"},
      {R"({"methods": {"knn": {"name": "OctoMap"}}})", "bad.json: methods knn and octomap would both be shown as "
                                                       "'OctoMap'"},
      {R"({"methods": {"knn": {"colour": "#000000", "marker": "o", "line": "solid"}}})",
       "bad.json: methods knn and octomap would be drawn alike"},
      {R"({"colours": {}})", "bad.json: colours: unknown field"},
      {R"({"methods": [1]})", "bad.json: methods: must be an object"},
      {R"({"methods": )", "bad.json: not valid JSON"}};
  for (const auto& [text, message] : bad) {
    std::ofstream(dir / "bad.json", std::ios::trunc) << text;
    const auto r = test::runIn(dir, "plot budget " + goldenFiles() + " --style bad.json --out bad.png");
    INFO(text << "\n" << r.output);
    CHECK(r.exit_code == 2);
    CHECK(r.output.find(message) != std::string::npos);
    CHECK_FALSE(fs::exists(dir / "bad.png"));
  }
  // A name of 60 characters of two bytes each is a name of 60 characters; a "$" is a dollar, not mathtext.
  std::string sixty;
  for (int i = 0; i < 60; ++i) sixty += "\xc3\xa9";  // é
  std::ofstream(dir / "wide.json", std::ios::trunc) << R"({"methods": {"knn": {"name": ")" + sixty + R"("}}})";
  CHECK(test::runIn(dir, "plot budget " + goldenFiles() + " --style wide.json --out wide.svg").exit_code == 0);
  std::ofstream(dir / "dollar.json", std::ios::trunc) << R"({"methods": {"knn": {"name": "$\\frac{a$ x"}}})";
  const auto dollar = test::runIn(dir, "plot budget " + goldenFiles() + " --style dollar.json --out dollar.svg");
  INFO(dollar.output);
  CHECK(dollar.exit_code == 0);
  CHECK(test::bytesOf(dir / "dollar.svg").find("$\\frac{a$ x") != std::string::npos);
  // A legend entry wider than the figure: refused, never clipped.
  const auto narrow = test::runIn(dir, "plot budget " + goldenFiles() + " --style wide.json --print-width 1.5 "
                                       "--font-size 24 --out narrow.png");
  CHECK(narrow.exit_code == 2);
  CHECK(narrow.output.find("a legend entry is wider than the figure") != std::string::npos);
  CHECK_FALSE(fs::exists(dir / "narrow.png"));
  for (const std::string width : {"0.5", "21", "wide", "3in", "0x4", "''"}) {
    const auto r = test::runIn(dir, "plot budget " + goldenFiles() + " --print-width " + width + " --out bad.png");
    INFO(r.output);
    CHECK(r.exit_code == 2);
    CHECK(r.output.find("--print-width must be column, page or a width in inches from 1.5 to 20, got " +
                        (width == "''" ? "" : width)) != std::string::npos);
    CHECK_FALSE(fs::exists(dir / "bad.png"));
  }
}

TEST_CASE("a name with a character the figure's font lacks is refused naming the character and the name, not the width") {
  // Old binary: "the curves figure's text does not fit or cannot be drawn: Glyph 21517 ... missing from current font;
  // choose a wider --print-width, a smaller --font-size or shorter display names": a width would not help.
  if (!haveMatplotlib()) {
    WARN("no matplotlib: occsweep plot cannot draw here");
    return;
  }
  const auto dir = test::processScratch("plot-glyph");
  json named = json::parse(test::bytesOf(kGolden / "octomap-opt.json"));
  named["dataset"]["name"] = "名字";
  std::ofstream(dir / "zh.json") << named.dump();
  const auto r = test::runIn(dir, "plot curves zh.json --out zh.png");
  INFO(r.output);
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("has no glyph for the character '名' (U+540D) of the data set name '名字'") != std::string::npos);
  CHECK(r.output.find("occsweep import --name") != std::string::npos);
  CHECK(r.output.find("--print-width") == std::string::npos);
  CHECK_FALSE(fs::exists(dir / "zh.png"));
}
