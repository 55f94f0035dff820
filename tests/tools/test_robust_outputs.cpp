// No data loss or corruption: no command replaces what a user owns, outputs appear whole or not at all,
// temporaries do not outlive their run, and a resumed sweep records every engine that made its maps
// (docs/io.md, "Outputs and --force"). OCCSWEEP_TEST_CLI=/path/to/occsweep runs these claims
// against another binary (the original one fails them).
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>
#include <sys/wait.h>

#include "occsweep/sweeps/results.hpp"
#include "robust_outputs_helpers.hpp"
#include "test_paths.hpp"

namespace fs = std::filesystem;
using namespace occsweep;
using namespace occsweep::test;

namespace {

const std::string kThesis = "\\documentclass{article} my thesis, five years of work\n";

// A folder holding a user's file.
fs::path userFolder(const fs::path& dir) {
  fs::create_directories(dir);
  writeBytes(dir / "thesis.tex", kThesis);
  return dir;
}

void writeCloud(const fs::path& file) {
  std::ofstream out(file);
  for (int i = 0; i < 50; ++i) out << 1 + 0.01 * i << ' ' << 0.5 << ' ' << 0.02 * i << '\n';
}

// The scratch folder with a tiny scene `scene` and a tiny grid `tiny.json` (made with the binary under test).
fs::path withScene(const std::string& name) {
  const fs::path dir = scratch(name);
  REQUIRE(runIn(dir, std::string(kTinyScene) + " --out scene").exit_code == 0);
  writeTinyGrid(dir / "tiny.json");
  return dir;
}

bool mentions(const CommandResult& r, const std::string& what) { return r.output.find(what) != std::string::npos; }

}  // namespace

TEST_CASE("scene and import --out refuse a folder holding a user's file, even with --force", "[outputs]") {
  const fs::path dir = scratch("robust_outputs/user_folder");
  const fs::path w = userFolder(dir / "w");
  writeCloud(dir / "a.xyz");
  const auto before = snapshot(dir);
  for (const std::string& args : {std::string(kTinyScene) + " --out w", std::string(kTinyScene) + " --out w --force",
                                 std::string("import cloud a.xyz --out w"),
                                 std::string("import cloud a.xyz --out w --force")}) {
    const CommandResult r = runIn(dir, args);
    INFO(args << "\n" << r.output);
    CHECK(r.exit_code == 2);
    CHECK(mentions(r, "w: exists"));
  }
  CHECK(snapshot(dir) == before);  // thesis.tex byte-identical, nothing added (no temporary)
}

TEST_CASE("every --out refuses to replace a user's file, even with --force", "[outputs]") {
  const fs::path dir = withScene("robust_outputs/user_file");
  REQUIRE(runIn(dir, "sweep --dataset scene --grid tiny.json --quiet --out r.json").exit_code == 0);
  writeBytes(dir / "notes.txt", kThesis);
  const auto before = snapshot(dir);
  for (const std::string& args :
       {std::string(kTinyScene) + " --out notes.txt", std::string("map --dataset scene --out notes.txt"),
        std::string("sweep --dataset scene --grid tiny.json --quiet --out notes.txt"),
        std::string("merge r.json --out notes.txt"), std::string("compare r.json --json notes.txt")}) {
    for (const std::string force : {"", " --force"}) {
      const CommandResult r = runIn(dir, args + force);
      INFO(args + force << "\n" << r.output);
      CHECK(r.exit_code == 2);
      CHECK(mentions(r, "notes.txt"));
    }
  }
  CHECK(snapshot(dir) == before);
}

TEST_CASE("occsweep's own output is replaced with --force only", "[outputs]") {
  const fs::path dir = withScene("robust_outputs/own");
  REQUIRE(runIn(dir, "map --dataset scene --method octomap --out m.ot").exit_code == 0);
  REQUIRE(runIn(dir, "sweep --dataset scene --grid tiny.json --quiet --out r.json").exit_code == 0);
  REQUIRE(runIn(dir, "merge r.json --out merged.json").exit_code == 0);
  REQUIRE(runIn(dir, "compare merged.json --json c.json").exit_code == 0);
  const auto before = snapshot(dir);
  const std::vector<std::string> commands = {std::string(kTinyScene) + " --seed 2 --out scene",
                                             "map --dataset scene --method knn --out m.ot",
                                             "merge r.json --out merged.json", "compare merged.json --json c.json"};
  for (const auto& args : commands) {
    const CommandResult r = runIn(dir, args);
    INFO(args << "\n" << r.output);
    CHECK(r.exit_code == 2);
    CHECK(mentions(r, "--force"));
  }
  CHECK(snapshot(dir) == before);
  for (const auto& args : commands) {
    const CommandResult r = runIn(dir, args + " --force");
    INFO(args << " --force\n" << r.output);
    CHECK(r.exit_code == 0);
  }
  CHECK(fileBytes(dir / "scene/manifest.json") != before.at("scene/manifest.json"));  // really replaced
  CHECK(nlohmann::json::parse(fileBytes(dir / "m.ot.json"))["method"] == "knn");
  CHECK(leftovers(dir).empty());
}

TEST_CASE("a .ot from another tool (no occsweep .ot.json) is not replaced, even with --force", "[outputs]") {
  const fs::path dir = withScene("robust_outputs/foreign_ot");
  REQUIRE(runIn(dir, "map --dataset scene --method octomap --out m.ot").exit_code == 0);
  fs::remove(dir / "m.ot.json");
  const auto before = snapshot(dir);
  const CommandResult r = runIn(dir, "map --dataset scene --method octomap --out m.ot --force");
  INFO(r.output);
  CHECK(r.exit_code == 2);
  CHECK(mentions(r, "m.ot: exists and is not occsweep's"));
  CHECK(snapshot(dir) == before);
}

TEST_CASE("scene --out . is refused by name and leaves nothing behind", "[outputs]") {
  const fs::path dir = scratch("robust_outputs/dot");
  const fs::path here = userFolder(dir / "here");
  const auto before = snapshot(dir);
  const CommandResult r = runIn(here, std::string(kTinyScene) + " --out .");
  INFO(r.output);
  CHECK(r.exit_code == 2);
  CHECK(mentions(r, ".: is the current folder"));
  CHECK(snapshot(dir) == before);
}

TEST_CASE("an --out with a trailing slash writes that folder, with no temporary inside or beside it", "[outputs]") {
  const fs::path dir = scratch("robust_outputs/slash");
  const CommandResult r = runIn(dir, std::string(kTinyScene) + " --out s1/");
  INFO(r.output);
  CHECK(r.exit_code == 0);
  CHECK(fs::is_regular_file(dir / "s1/manifest.json"));
  CHECK(leftovers(dir).empty());
  CHECK(std::distance(fs::directory_iterator(dir), fs::directory_iterator()) == 1);
}

TEST_CASE("an empty folder is not a user's output: scene writes into it", "[outputs]") {
  const fs::path dir = scratch("robust_outputs/empty");
  fs::create_directories(dir / "w");
  const CommandResult r = runIn(dir, std::string(kTinyScene) + " --out w");
  INFO(r.output);
  CHECK(r.exit_code == 0);
  CHECK(fs::is_regular_file(dir / "w/manifest.json"));
}

TEST_CASE("map --out x.bt is refused with a reason, and writes nothing", "[outputs]") {
  const fs::path dir = withScene("robust_outputs/bt");
  const auto before = snapshot(dir);
  const CommandResult r = runIn(dir, "map --dataset scene --method octomap --out x.bt");
  INFO(r.output);
  CHECK(r.exit_code == 2);
  CHECK(mentions(r, "x.bt"));
  CHECK(mentions(r, ".ot"));
  CHECK(snapshot(dir) == before);
}

TEST_CASE("a map write past the file-size limit fails by name, exit 2, with no partial .ot", "[outputs]") {
  const fs::path dir = withScene("robust_outputs/ulimit");
  const auto before = snapshot(dir);
  // `ulimit -f 2`: 2 KiB, less than the tiny scene's .ot; without SIGXFSZ ignored the process would be killed.
  const CommandResult r = runIn(dir, "map --dataset scene --method octomap --out m.ot", "ulimit -f 2;");
  INFO(r.output);
  CHECK(r.exit_code == 2);
  CHECK(mentions(r, "m.ot: file size limit exceeded"));
  CHECK(snapshot(dir) == before);
}

TEST_CASE("a sweep begun under --engine direct and resumed under replay records both engines", "[outputs]") {
  const fs::path dir = withScene("robust_outputs/engines");
  const std::string sweep = "sweep --dataset scene --grid knn-opt --threads 1 --quiet";
  REQUIRE(runIn(dir, sweep + " --engine direct --out direct.json").exit_code == 0);
  // A direct run killed once a few maps are logged: the state it leaves is what a replay run resumes from.
  const fs::path partial = dir / "resumed.json.partial.jsonl";
  const KilledRun killed = killOnceLogged(dir, sweep + " --engine direct --out resumed.json", partial, 6);
  REQUIRE(killed.killed);
  REQUIRE(killed.lines >= 6);  // its header and at least five maps
  const CommandResult r = runIn(dir, sweep + " --engine replay --out resumed.json");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  const auto resumed = nlohmann::json::parse(fileBytes(dir / "resumed.json"));
  CHECK(resumed["map"]["engines"] == nlohmann::json::array({"direct", "replay"}));
  CHECK(resumed["map"]["engine"] == "mixed");
  CHECK(resultDifferences(readResults(dir / "direct.json"), readResults(dir / "resumed.json")).empty());
  CHECK(readResults(dir / "resumed.json").header.engines == std::vector<std::string>{"direct", "replay"});
  CHECK(!fs::exists(partial));
}

TEST_CASE("a sweep's own unfinished work is resumed without --force: resuming is not replacing", "[outputs]") {
  const fs::path dir = withScene("robust_outputs/resume");
  REQUIRE(runIn(dir, "sweep --dataset scene --grid tiny.json --quiet --out r.json").exit_code == 0);
  const std::string first = fileBytes(dir / "r.json");
  const CommandResult again = runIn(dir, "sweep --dataset scene --grid tiny.json --quiet --out r.json");
  INFO(again.output);
  CHECK(again.exit_code == 0);
  CHECK(fileBytes(dir / "r.json") == first);  // the complete file is returned as it is
}

TEST_CASE("sweep refuses two grids into one file however it is spelt, before any work", "[outputs]") {
  // Old binary: --out x.json --out ./x.json (or d/../x.json, or through a linked folder) wrote both grids to one
  // file; the first grid's results were lost, exit 0.
  const fs::path dir = withScene("robust_outputs/same_out");
  fs::create_directories(dir / "d");
  fs::create_directory_symlink(dir, dir / "here");
  for (const std::string second : {"./x.json", "d/../x.json", "here/x.json", "x.json/"}) {
    const CommandResult r = runIn(dir, "sweep --dataset scene --grid tiny.json --grid tiny.json --quiet --out x.json "
                                       "--out " + second);
    INFO(second << ": " << r.output);
    CHECK(r.exit_code == 2);
    CHECK(mentions(r, "--out 1 and --out 2 name one file"));
    CHECK_FALSE(fs::exists(dir / "x.json"));
    CHECK_FALSE(fs::exists(dir / "x.json.partial.jsonl"));
    CHECK(leftovers(dir).empty());  // no temporary either
  }
  const CommandResult two = runIn(dir, "sweep --dataset scene --grid tiny.json --grid tiny.json --quiet --out a.json "
                                       "--out d/b.json");
  INFO(two.output);
  CHECK(two.exit_code == 0);
  CHECK(fs::exists(dir / "a.json"));
  CHECK(fs::exists(dir / "d" / "b.json"));
}

TEST_CASE("compare's CSV, Markdown and LaTeX show 24 names of random printable characters and line breaks as they are",
          "[outputs]") {
  // Old binary: a `$` broke the LaTeX ("Missing $ inserted"), a `|` added a Markdown column, a carriage return went
  // into the CSV unquoted; then `*`, `` ` ``, `<b>`, `&amp;` and `[l](u)` rendered as Markdown, `--`, `''`, `,,` and
  // `<<` as LaTeX ligatures. The oracle (tests/reference/read_tables.py) reads each name back through Python's csv,
  // markdown-it-py and pdflatex + pdftotext.
  const fs::path dir = withScene("robust_outputs/escaping");
  REQUIRE(runIn(dir, "sweep --dataset scene --grid tiny.json --quiet --out r.json").exit_code == 0);
  const nlohmann::json swept = nlohmann::json::parse(fileBytes(dir / "r.json"));
  std::vector<std::string> names = {"C&D_%$#{x}~^\\ a|b,\"q\"\rz", "*em* `code` <b>x</b> &amp; [l](u) ~~s~~",
                                    "a--b---c ``q'' ,,d << e >> !`?`", "\\|\\\\|"};
  SplitMix64 rng(29);
  while (names.size() < 24) {
    std::string name;
    for (std::size_t n = 8 + rng.next() % 17; name.size() < n;) {
      const std::uint64_t c = rng.next() % 96;  // the 95 printable ASCII characters and a line break
      name += c == 95 ? '\n' : char(0x20 + c);
    }
    names.push_back(name);
  }
  for (std::size_t i = 0; i < names.size(); ++i) {
    nlohmann::json named = swept;  // the name as another program's results (or import --name) may carry it
    named["dataset"]["name"] = names[i];
    const std::string in = "n-" + std::to_string(i) + ".json", t = "t-" + std::to_string(i);
    std::ofstream(dir / in) << named.dump();
    const CommandResult r = runIn(dir, "compare " + in + " --csv " + t + ".csv --markdown " + t + ".md --latex " + t +
                                           ".tex");
    INFO(names[i] << "\n" << r.output);
    REQUIRE(r.exit_code == 0);
  }
  std::ofstream(dir / "names.json") << nlohmann::json(names).dump();
  // The CSV is always read back (Python's csv); Markdown and LaTeX where their readers are installed.
  const bool readers = runShell("command -v pdflatex && command -v pdftotext && /usr/bin/python3 -c 'import "
                                "markdown_it'").exit_code == 0;
  if (!readers && std::getenv("CI"))  // CI (.ci/run exports CI) installs them: missing there is a broken set-up
    FAIL("pdflatex, pdftotext or markdown-it-py missing under CI (tools/setup.sh installs them)");
  if (!readers)
    WARN("pdflatex, pdftotext or markdown-it-py missing (the test command installs them: tools/setup.sh): "
         "the CSV alone is read back");
  const CommandResult read = runShell("/usr/bin/python3 " +
                                      shellQuoted(occsweep::test::sourceTree() / "tests/reference/read_tables.py") +
                                      " " + shellQuoted(dir) + (readers ? "" : " --csv-only") + " 2>&1");
  INFO(read.output);
  CHECK(read.exit_code == 0);
  std::string all_same;
  for (std::size_t i = 0; i < names.size(); ++i) all_same += "same\n";
  CHECK(read.output == all_same);
}

TEST_CASE("compare and sweep show a data set name's line breaks and escape sequences escaped, forging no line",
          "[outputs]") {
  // Old binary: the name (from a data set folder made by hand, or another program's results) was printed as it is:
  // ESC [2J cleared the terminal and the line break put a forged "knn 0.99" line under it.
  const fs::path dir = withScene("robust_outputs/terminal_names");
  const std::string forged = "a\nknn     AUC 0.9900 \x1b[2J\r\xc2\x9b" "2K\xe2\x80\xae";  // CSI (U+009B), then 2K
  const std::string shown = "a\\nknn     AUC 0.9900 \\x1b[2J\\r\\u009b2K\\u202e";
  nlohmann::json manifest = nlohmann::json::parse(fileBytes(dir / "scene/manifest.json"));
  manifest["name"] = forged;
  writeBytes(dir / "scene/manifest.json", manifest.dump());
  const CommandResult sweep = runIn(dir, "sweep --dataset scene --grid tiny.json --out r.json");  // its phases
  REQUIRE(sweep.exit_code == 0);
  const CommandResult compare = runIn(dir, "compare r.json");
  REQUIRE(compare.exit_code == 0);
  for (const CommandResult& r : {sweep, compare}) {
    INFO(r.output);
    CHECK(mentions(r, shown));
    for (const std::string control : {"\x1b", "\r", "\xc2\x9b", "\xe2\x80\xae"}) CHECK_FALSE(mentions(r, control));
    CHECK_FALSE(mentions(r, "\nknn     AUC 0.9900"));
  }
}

TEST_CASE("compare --latex refuses a name pdflatex cannot typeset, naming it and what to do, and the rest compiles",
          "[outputs]") {
  // Old binary: exit 0 with a table pdflatex stops on ("Unicode character ... not set up for use with LaTeX").
  const fs::path dir = withScene("robust_outputs/latex_names");
  REQUIRE(runIn(dir, "sweep --dataset scene --grid tiny.json --quiet --out r.json").exit_code == 0);
  const nlohmann::json swept = nlohmann::json::parse(fileBytes(dir / "r.json"));
  auto named = [&](const std::string& file, const std::string& name) {
    nlohmann::json j = swept;
    j["dataset"]["name"] = name;
    writeBytes(dir / file, j.dump());
  };
  const std::vector<std::pair<std::string, std::string>> refused = {
      {"名字", "'名' (U+540D)"}, {"set \xf0\x9f\x98\x80", "'\xf0\x9f\x98\x80' (U+1F600)"}, {"Ħ", "'Ħ' (U+0126)"},
      {"esc\x1b", "'\\x1b' (U+001B)"}};
  for (const auto& [name, character] : refused) {
    named("n.json", name);
    const auto before = snapshot(dir);
    const CommandResult r = runIn(dir, "compare n.json --latex t.tex --csv t.csv");
    INFO(r.output);
    CHECK(r.exit_code == 2);
    CHECK(mentions(r, "--latex: n.json: the data set name '"));
    CHECK(mentions(r, "holds " + character + ", which pdflatex cannot typeset"));
    CHECK(mentions(r, "write --markdown or --csv, which hold any character, or import the data set again under a "
                      "name pdflatex can typeset (import --name)"));
    CHECK(snapshot(dir) == before);  // no table written, the CSV neither
  }
  // Every character the check lets through: printable ASCII and U+00A0-U+017E but the eight T1 has no glyph for.
  std::string latin = "ASCII ~^_$ ";
  for (char32_t c = 0xA0; c <= 0x17E; ++c)
    if (c != 0x126 && c != 0x127 && c != 0x138 && c != 0x13F && c != 0x140 && c != 0x149 && c != 0x166 && c != 0x167)
      latin += std::string{char(0xC0 | (c >> 6)), char(0x80 | (c & 0x3F))};  // UTF-8: two bytes below U+0800
  named("latin.json", latin);
  const CommandResult r = runIn(dir, "compare latin.json --latex latin.tex");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  if (runShell("command -v pdflatex").exit_code != 0) {
    WARN("pdflatex not installed: the table of every Latin character is not compiled");
    return;
  }
  writeBytes(dir / "doc.tex", "\\documentclass{article}\n\\usepackage[T1]{fontenc}\n\\usepackage{booktabs}\n"
                              "\\usepackage{graphicx}\n\\usepackage{array}\n\\begin{document}\n\\input{latin.tex}\n"
                              "\\end{document}\n");
  const CommandResult tex = runShell("cd " + shellQuoted(dir) + " && pdflatex -interaction=nonstopmode -halt-on-error doc.tex");
  INFO(tex.output);
  CHECK(tex.exit_code == 0);
}

TEST_CASE("cluster select replaces its own folder of links, never a user's folder", "[outputs]") {
  const fs::path dir = scratch("robust_outputs/select");
  fs::create_directories(dir / "ds/pcs-0000");
  std::ofstream(dir / "ds/ranking.json") << R"({"format": "occsweep-pointcloud-ranking",
    "sets": [{"folder": "pcs-0000", "id": 0, "naive": {"fdr": 0.1, "tpr": 0.9}}]})";
  REQUIRE(runIn(dir, "cluster select ds/ranking.json --out sel").exit_code == 0);
  CHECK(runIn(dir, "cluster select ds/ranking.json --out sel").exit_code == 0);  // a re-run task: its own folder
  userFolder(dir / "w");
  const auto before = snapshot(dir);
  const CommandResult r = runIn(dir, "cluster select ds/ranking.json --out w");
  INFO(r.output);
  CHECK(r.exit_code == 2);
  CHECK(mentions(r, "w: exists and is not occsweep's"));
  // What to do instead, and no word of --force, which cluster select does not have (old binary: "refused even with
  // --force").
  CHECK(mentions(r, "move it away, or give another --out (nothing was written)"));
  CHECK_FALSE(mentions(r, "--force"));
  CHECK_FALSE(mentions(runIn(dir, "cluster select --help"), "--force"));
  CHECK(snapshot(dir) == before);
  CHECK(leftovers(dir).empty());
}

TEST_CASE("reproduce --out refuses a folder holding a user's file before any work", "[outputs]") {
  const fs::path dir = scratch("robust_outputs/reproduce");
  if (runIn(dir, "reproduce --help").exit_code != 0) {
    WARN("occsweep built without the stereo tools: no reproduce command, case skipped");
    return;
  }
  userFolder(dir / "w");
  const auto before = snapshot(dir);
  const CommandResult r = runIn(dir, "reproduce --scale ci --no-figures --quiet --name parking-plain-I --out w");
  INFO(r.output);
  CHECK(r.exit_code == 2);
  CHECK(mentions(r, "w: exists and is not occsweep's reproduction folder"));
  CHECK(snapshot(dir) == before);
}

TEST_CASE("reproduce --out refuses a folder whose report, step file or figure is not occsweep's, whatever its name",
          "[outputs]") {
  // Old binary: any *.json, *.md or *.png counted as the reproduction's own, and the run replaced a user's
  // report.md, fits.json or fig5_improvement.png.
  const fs::path dir = scratch("robust_outputs/reproduce_names");
  if (runIn(dir, "reproduce --help").exit_code != 0) {
    WARN("occsweep built without the stereo tools: no reproduce command, case skipped");
    return;
  }
  const std::vector<std::pair<std::string, std::string>> users = {
      {"report.md", "# My reproduction notes\n"},
      {"notes.md", "# notes\n"},
      {"fits.json", "{\"format\": \"my own fits\"}\n"},
      {"results.json", "{}\n"},
      {"fig5_improvement.png", "\x89PNG\r\n\x1a\n a user's figure"},
      {".fits.json.tmp-1-0123456789abcdef0123456789abcdef", "not a temporary occsweep recorded"}};
  for (const auto& [name, bytes] : users) {
    INFO(name);
    fs::remove_all(dir / "w");
    fs::create_directories(dir / "w" / "data");
    writeBytes(dir / "w" / name, bytes);
    const auto before = snapshot(dir);
    const CommandResult r =
        runIn(dir, "reproduce --scale ci --no-figures --quiet --steps real-stereo --name parking-plain-I --out w");
    INFO(r.output);
    CHECK(r.exit_code == 2);
    CHECK(mentions(r, "w: exists and is not occsweep's reproduction folder (" + name + " is not one of its files"));
    CHECK(snapshot(dir) == before);
  }
}
