// A results file of either format (results_file.hpp): the format by the file's first bytes, never by its name.
#include "occsweep/sweeps/results_file.hpp"

#include "occsweep/sweeps/results_store.hpp"
#include "occsweep/sweeps/results_verify.hpp"

namespace occsweep {
namespace fs = std::filesystem;

bool isStorePath(const fs::path& file) {
  const std::string ext = file.extension().string();
  return ext == ".db" || ext == ".sqlite";
}

ResultsFile readResultsHeader(const fs::path& file) {
  if (!isResultsStore(file)) {
    ResultsFile f = readResults(file);
    f.maps.clear();
    return f;
  }
  const ResultsStore store = ResultsStore::open(file);
  ResultsFile f;
  f.header = store.header();
  f.complete = store.complete();
  f.seconds = store.seconds();
  f.truth_voxels = store.truthVoxels();
  return f;
}

void forEachResultsMap(const fs::path& file, MapDetail detail, const MapVisitor& visit) {
  if (isResultsStore(file)) return ResultsStore::open(file).forEachMap(detail, visit);
  ResultsFile f = readResults(file);
  for (MapResult& m : f.maps) {
    if (detail == MapDetail::Summary) m.dropThresholds();
    visit(std::move(m));
  }
}

ResultsFile readResultsAt(const fs::path& file, MapDetail detail) {
  if (!isResultsStore(file)) {
    ResultsFile f = readResults(file);
    if (detail == MapDetail::Summary)
      for (MapResult& m : f.maps) m.dropThresholds();
    return f;
  }
  ResultsFile f = readResultsHeader(file);
  forEachResultsMap(file, detail, [&](MapResult&& m) { f.maps.push_back(std::move(m)); });
  if (detail == MapDetail::Full) verifyClaims(f, file.string());
  return f;
}

}  // namespace occsweep
