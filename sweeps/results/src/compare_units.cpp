// The units of compare's tests (compare_units.hpp, docs/statistics.md "Verdicts").
#include "occsweep/sweeps/compare_units.hpp"

#include <algorithm>
#include <map>
#include <numeric>
#include <set>

namespace occsweep {
namespace {

bool isPointCloudSetName(const std::string& name, std::size_t slash) {
  const std::string tail = name.substr(slash + 1);
  return tail.size() > 4 && tail.compare(0, 4, "pcs-") == 0 &&
         std::all_of(tail.begin() + 4, tail.end(), [](char c) { return c >= '0' && c <= '9'; });
}

// What a data set shares with the others of its scene: each recorded input file, the points read from them, the
// generated scene, the truth (one room, whatever its region, trajectory or scan count: fewer units can only make a
// verdict "too few to tell", never a false "gain"; docs/statistics.md, "Verdicts"). None when its provenance
// records neither inputs nor a scene (an older occsweep made its scans).
std::vector<std::string> provenanceKeys(const nlohmann::json& p) {
  std::vector<std::string> keys;
  if (!p.is_object() || !(p.contains("inputs") || p.contains("scene"))) return keys;
  if (p.contains("scene")) keys.push_back("scene " + p.at("scene").dump());
  for (const auto& input : p.value("inputs", nlohmann::json::array())) keys.push_back("input " + input.dump());
  if (p.contains("points")) keys.push_back("points " + p.at("points").dump());
  if (p.contains("truth")) keys.push_back("truth " + p.at("truth").dump());
  return keys;
}

// Rows joined into groups (union-find with path halving).
struct Groups {
  std::vector<std::size_t> parent;
  explicit Groups(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), std::size_t(0)); }
  std::size_t root(std::size_t i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  }
  void join(std::size_t a, std::size_t b) { parent[root(a)] = root(b); }
};

// A unit's label: its data sets' names ("a", "a + b", "a + 9 more"), made unique with "#2", "#3".
std::string labelOf(const std::set<std::string>& names, std::set<std::string>& used) {
  std::string label = *names.begin();
  if (names.size() == 2) label += " + " + *std::next(names.begin());
  if (names.size() > 2) label += " + " + std::to_string(names.size() - 1) + " more";
  std::string unique = label;
  for (int k = 2; !used.insert(unique).second; ++k) unique = label + " #" + std::to_string(k);
  return unique;
}

std::string declarationOf(UnitRule rule, bool grouped, const std::vector<std::string>& without) {
  if (rule == UnitRule::Names) return "units declared by --units names: one per data set name";
  const std::string older = "no content hashes recorded (made by an older occsweep)";
  if (!grouped) return "units: data set names, assumed independent: " + older;
  std::string text = "scenes by content hashes: data sets sharing an input file, the points read, the truth, or a "
                     "generated scene are one";
  if (!without.empty())
    text += "; " + std::to_string(without.size()) + (without.size() == 1 ? " data set has " : " data sets have ") +
            older + ": each name assumed a scene of its own";
  return text;
}

}  // namespace

std::string datasetOf(const std::string& name) {
  const std::size_t slash = name.rfind('/');
  return slash != std::string::npos && isPointCloudSetName(name, slash) ? name.substr(0, slash) : name;
}

SampleUnits sampleUnits(const std::vector<ComparisonRow>& rows, UnitRule rule) {
  SampleUnits u;
  Groups groups(rows.size());
  std::map<std::string, std::size_t> first_with_key;
  std::set<std::string> without;
  bool grouped = false;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    std::vector<std::string> keys;
    if (rule == UnitRule::Provenance) keys = provenanceKeys(rows[i].provenance);
    grouped = grouped || !keys.empty();
    if (keys.empty()) {
      keys.push_back("name " + datasetOf(rows[i].dataset));
      if (rule == UnitRule::Provenance) without.insert(datasetOf(rows[i].dataset));
    }
    for (const std::string& key : keys)
      if (const auto [first, fresh] = first_with_key.try_emplace(key, i); !fresh) groups.join(i, first->second);
  }
  std::map<std::size_t, std::set<std::string>> names;
  for (std::size_t i = 0; i < rows.size(); ++i) names[groups.root(i)].insert(datasetOf(rows[i].dataset));
  std::map<std::size_t, std::string> label;
  std::set<std::string> used;
  for (const auto& [root, of_unit] : names) label[root] = labelOf(of_unit, used);
  for (std::size_t i = 0; i < rows.size(); ++i) u.of_row.push_back(label.at(groups.root(i)));
  u.without_provenance.assign(without.begin(), without.end());
  u.noun = grouped ? "scenes" : "data sets";
  u.declaration = declarationOf(rule, grouped, u.without_provenance);
  return u;
}

std::string sampleText(const SampleUnits& units, std::size_t datasets, std::size_t scenes) {
  std::string text = std::to_string(datasets) + (datasets == 1 ? " data set" : " data sets");
  if (units.noun != "data sets")
    text += " over " + std::to_string(scenes) + " " + (scenes == 1 ? "scene" : units.noun);
  return text + " (" + units.declaration + ")";
}

}  // namespace occsweep
