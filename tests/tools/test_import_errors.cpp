// Broken inputs (docs/robustness.md): each gives a DataError naming the file and the rule, and through
// the command a non-zero exit, the file named, and no output folder.
#include <catch2/catch.hpp>

#include <fstream>

#include "import_error_cases.hpp"
#include "test_helpers.hpp"

using namespace occsweep;
namespace fs = std::filesystem;

namespace {

void writeFile(const fs::path& file, const std::string& bytes) {
  std::ofstream(file, std::ios::binary) << bytes;
}

// The command line that reads `file` as its kind, from a folder holding valid companions.
std::string commandFor(const test::BadInput& c, const fs::path& dir, const fs::path& file, const fs::path& out) {
  const std::string o = " --out " + out.string();
  const std::string cam = " --fx 500 --fy 500 --cx 1 --cy 1";
  if (c.kind == "depth") return "import depth " + file.string() + " --poses " + (dir / "pose1.txt").string() + cam + o;
  if (c.kind == "pose") return "import depth " + (dir / "ok.pgm").string() + " --poses " + file.string() + cam + o;
  if (c.kind == "matrix")
    return "import depth " + (dir / "ok.pgm").string() + " --pose-format matrix --poses " + file.string() + cam + o;
  if (c.kind == "graph") return "import graph " + file.string() + o;
  if (c.kind == "cloud") return "import cloud " + file.string() + o;
  if (c.kind == "truth") return "import truth " + file.string() + " --dataset " + (dir / "okset").string() + o;
  if (c.kind == "grid") return "grid count " + file.string();
  if (c.kind == "dataset" || c.kind == "manifest") return "map --dataset " + file.parent_path().string() + " --out " + out.string() + ".ot";
  return "results check " + file.string();
}

// Writes the case's file (or edits a copy of a good data set) and returns its path.
fs::path prepare(const test::BadInput& c, const fs::path& dir) {
  fs::path file = dir / c.name;
  if (c.kind == "dataset" || c.kind == "manifest") {
    fs::remove_all(dir / "edited");
    fs::copy(dir / "okset", dir / "edited", fs::copy_options::recursive);
    file = dir / "edited" / "manifest.json";
    std::string m = c.kind == "manifest" ? c.bytes : test::fileBytes(file);
    if (c.kind == "dataset") {  // one scan's point count changed by hand
      const auto at = m.find("\"points\": 2");
      REQUIRE(at != std::string::npos);
      m.replace(at, 12, "\"points\": 3");
    }
    writeFile(file, m);
    return file;
  }
  if (c.name == "folder.xyz") fs::create_directories(file);
  if (c.write) writeFile(file, c.bytes);
  return file;
}

void checkRefused(const test::BadInput& c, const fs::path& dir) {
  INFO(c.label << " (" << c.name << ")");
  const fs::path file = prepare(c, dir);
  const fs::path out = dir / ("out-" + c.name);
  fs::remove_all(out);
  const auto r = test::runCli(commandFor(c, dir, file, out));
  INFO(r.output);
  CHECK(r.exit_code != 0);
  CHECK(r.output.find(c.name) != std::string::npos);    // names the file
  CHECK(r.output.find(c.expect) != std::string::npos);  // and what is wrong
  CHECK(r.output.find("Segmentation") == std::string::npos);
  CHECK(!fs::exists(out));  // no partial output
  CHECK(!fs::exists(out.string() + ".ot"));
  bool leftover = false;
  for (const auto& e : fs::directory_iterator(dir)) leftover |= e.path().string().find(".tmp-") != std::string::npos;
  CHECK(!leftover);
}

void makeCompanions(const fs::path& dir) {
  writeFile(dir / "pose1.txt", "0 0 0 0 0 0 1\n");
  writeFile(dir / "ok.pgm", "P2 2 1 65535\n1000 2000\n");
  writeFile(dir / "ok.xyz", "1 2 3\n4 5 6\n");
  REQUIRE(test::runCli("import cloud " + (dir / "ok.xyz").string() + " --out " + (dir / "okset").string()).exit_code == 0);
}

}  // namespace

TEST_CASE("Every bad input of the robustness table: clear error, non-zero exit, no output") {
  const fs::path dir = test::scratch("import_errors");
  makeCompanions(dir);
  for (const test::BadInput& c : test::badInputs()) checkRefused(c, dir);
}

// Found by fuzz_grid_json in the sweeps' loaders: nlohmann throws out_of_range, not parse_error, for 1e999.
TEST_CASE("JSON numbers beyond double in grid and results files name the file") {
  const fs::path dir = test::scratch("import_errors_overflow");
  makeCompanions(dir);
  for (const test::BadInput& c : test::jsonOverflowInSweepsFiles()) checkRefused(c, dir);
}

// Prints the robustness table of docs/robustness.md from what the command really says: ./test_import_errors [.table]
TEST_CASE("Robustness table", "[.table]") {
  const fs::path dir = test::scratch("import_errors");
  makeCompanions(dir);
  auto cases = test::badInputs();
  for (const auto& c : test::jsonOverflowInSweepsFiles()) cases.push_back(c);
  for (const test::BadInput& c : cases) {
    const fs::path file = prepare(c, dir);
    const auto r = test::runCli(commandFor(c, dir, file, dir / ("out-" + c.name)));
    std::string msg = r.output.substr(0, r.output.find_last_not_of('\n') + 1);
    if (auto p = msg.rfind('\n'); p != std::string::npos) msg = msg.substr(p + 1);  // last line: the error
    if (auto p = msg.find(dir.string()); p != std::string::npos) msg.replace(p, dir.string().size() + 1, "");
    const std::string cmd = commandFor(c, dir, file, dir / "out");
    const std::string verb = cmd.substr(0, cmd.find(' ', cmd.find(' ') + 1));  // "import depth", "results check"
    std::cout << "| " << c.label << " | `occsweep " << verb << "` | " << r.exit_code << " | " << msg << " |\n";
  }
}
