// exportJson and exportCsv (results_export.hpp).
#include "occsweep/sweeps/results_export.hpp"

#include <nlohmann/json.hpp>

#include "occsweep/sweeps/csv_text.hpp"
#include "occsweep/sweeps/results_verify.hpp"

namespace occsweep {

using nlohmann::json;
namespace fs = std::filesystem;

// Both exports read their file once with every check of `results check` (readCheckedResults): what is written is
// what was checked, even when the file is replaced at its name meanwhile. The header is known before the first map.
void exportJson(const fs::path& file, std::ostream& out) {
  ResultsFile head;
  std::string text, marker;
  std::size_t at = 0;
  bool first = true;
  const auto writeOpening = [&] {  // the header, up to where the maps go
    json top = toJson(head);
    const std::string placeholder = "occsweep-export-maps";  // where the maps go, streamed one by one
    top["maps"] = placeholder;
    text = top.dump(1);
    marker = "\"maps\": \"" + placeholder + "\"";
    at = text.find(marker);
    out << text.substr(0, at) << "\"maps\": [";
  };
  // nlohmann's dump(1) puts an element of the top object's array 2 spaces in: each line of the map's own dump(1)
  // is indented by 2 more, so that the bytes equal writeResults' (a test compares them).
  (void)readCheckedResults(file, "", [&](MapResult&& m) {
    if (first) writeOpening();
    std::string element = toJson(m, head.header.parameters).dump(1);
    std::string indented = "  ";
    for (char ch : element) indented.append(ch == '\n' ? "\n  " : std::string(1, ch));
    out << (first ? "\n" : ",\n") << indented;
    first = false;
  }, &head);
  if (first) writeOpening();
  out << (first ? "]" : "\n ]") << text.substr(at + marker.size()) << '\n';
}

// Tidy: one line per combination, led by what the file is of (data set, method, grid, truth), so that the exports
// of several files concatenate into one frame; numbers and fields as every CSV occsweep writes (csv_text.hpp).
void exportCsv(const fs::path& file, std::ostream& out) {
  ResultsFile head;
  bool first = true;
  std::string lead;  // the columns every line of this file shares
  const auto writeHeaderLine = [&] {
    const ResultsHeader& h = head.header;
    out << "dataset,point_cloud_set,dataset_hash,method,grid,truth,id,map_index";
    for (const std::string& name : h.parameters.names) out << ',' << csvField(name);
    out << ",p_t,tp,fp,fn,tn,tpr,fdr,auc_anchored,auc_observed\n";
    for (const std::string& field :
         {h.dataset_name, pointCloudSetOf(h), h.dataset_hash, h.method, h.grid_name, std::string(truthModeName(h.truth))})
      lead += csvField(field) + ',';
  };
  (void)readCheckedResults(file, "", [&](MapResult&& m) {
    if (first) writeHeaderLine();
    first = false;
    const ParameterLayout& layout = head.header.parameters;
    std::string params;
    for (std::size_t i = 0; i < layout.names.size(); ++i) {
      const Fixed v = m.params.values[i];
      params += ',' + (layout.integer[i] ? std::to_string(v / kFixedScale) : csvNumber(toDouble(v)));
    }
    const std::string auc = ',' + csvNumber(m.area.anchored) + ',' + csvNumber(m.area.observed) + '\n';
    for (const ThresholdResult& t : m.thresholds) {
      const ConfusionCounts& c = t.counts;
      out << lead << t.id << ',' << m.map_index << params << ',' << csvNumber(toDouble(t.p_t)) << ',' << c.tp << ','
          << c.fp << ',' << c.fn << ',' << c.tn << ',' << csvNumber(c.tpr()) << ',' << csvNumber(c.fdr()) << auc;
    }
  }, &head);
  if (first) writeHeaderLine();
}

}  // namespace occsweep
