// report.md: real stereo with the voxel filter as a swept choice (real-stereo.json; docs/fidelity.md, "Real stereo
// with truth").
#include <algorithm>

#include "reproduce_internal.hpp"

namespace occsweep::reproduce {
using nlohmann::json;

namespace {

constexpr const char* kTitle =
    "## 7. Real stereo with and without the voxel filter (Middlebury Aloe; no figure of the paper)";

double auc(const json& best) { return best.is_null() ? NAN : get(best.at("auc")); }

// The configuration's filter in words: "none", or its leaf in metres.
std::string filterText(const json& configuration) {
  const json& filter = configuration.at("voxel_filter");
  return filter.is_boolean() ? std::string("none") : num(filter.get<double>(), "%.3g") + " m";
}

// One row per set and truth: OctoMap, k-NN and the ablation's best AUC, each improvement over OctoMap.
void setRows(std::ostringstream& o, const json& configuration, std::vector<double> (&knn)[2],
             std::vector<double> (&equal)[2]) {
  const char* truths[2] = {"full", "observable"};
  for (const json& set : configuration.at("sets"))
    for (int t = 0; t < 2; ++t) {
      const json& side = set.at("truths").at(truths[t]);
      const double gain = get(side.at("knn_improvement_percent")),
                   equal_gain = get(side.at("knn_equal_hit_improvement_percent"));
      o << "| " << num(configuration.at("resolution").get<double>(), "%.2f") << " | " << filterText(configuration)
        << " | " << set.at("points").get<std::uint64_t>() << " | " << set.at("point_cloud_set").get<std::string>() << " | " << truths[t] << " | "
        << side.at("true_voxels").get<std::uint64_t>() << " | " << num(auc(side.at("octomap"))) << " | "
        << num(auc(side.at("knn"))) << " | " << num(gain, "%+.2f") << " | " << num(auc(side.at("knn_equal_hit")))
        << " | " << num(equal_gain, "%+.2f") << " |\n";
      if (std::isfinite(gain)) knn[t].push_back(gain);
      if (std::isfinite(equal_gain)) equal[t].push_back(equal_gain);
    }
}

// One configuration's truth coverage as its sweeps measured it (real-stereo.json's coverage; docs/import.md, "Truth
// coverage and alignment"), over its sets; where `sweep` warns, the warning and the observable-truth result beside
// the full-truth one. "" when the sets record no coverage (an older run).
std::string coverageLine(const json& configuration, const std::string& where, const std::vector<double> (&knn)[2]) {
  std::vector<double> share, distance;
  std::string warning;
  for (const json& set : configuration.at("sets")) {
    const json& c = set.value("coverage", json());
    if (c.is_null()) return "";
    share.push_back(100 * get(c.at("observable_share"))), distance.push_back(get(c.at("median_point_distance_m")));
    if (warning.empty()) warning = c.at("warning").get<std::string>();
  }
  if (share.empty()) return "";
  const auto range = [](const std::vector<double>& v, const char* format, const char* unit) {
    const auto [lo, hi] = std::minmax_element(v.begin(), v.end());
    std::string text = num(*lo, format);  // appended: g++ 12 warns wrongly (-Wrestrict) on some chains of operator+
    if (num(*hi, format) != text) text.append("-").append(num(*hi, format));
    return text.append(unit);
  };
  std::string line = "- " + where + ": " + range(share, "%.0f", " %") + " of the truth voxels observable from the "
                     "scans, median distance from the points to the nearest truth voxel " +
                     range(distance, "%.2g", " m");
  if (warning.empty()) return line + ".";
  return line + ". `sweep` warns: " + warning + ". Under observable truth (what the camera can see) k-NN gains " +
         num(mean(knn[1]), "%+.2f") + " % on average, against " + num(mean(knn[0]), "%+.2f") + " % under full truth.";
}

}  // namespace

void realStereoSection(std::ostringstream& o, const json& r) {
  o << kTitle << "\n\n";
  if (r.contains("not_run")) {
    o << "Not run: " << r.at("not_run").get<std::string>() << ".\n\n";
    return;
  }
  o << "Pair: " << r.value("pair", std::string("?")) << ". The voxel filter is swept: none (one point per valid "
    << "disparity), PCL VoxelGrid at half the map resolution, and at the resolution; truth at the map resolution. "
    << "The rendered sets of sections 3-4 are voxel-filtered at the map resolution, which leaves one point per voxel "
    << "and scan: then Eq. 7 sums one term per voxel, as OctoMap's one update per voxel and scan. The ablation, the "
    << "best `knn-opt` map with p_u = p_l (every point weighted alike: Eq. 7's per-voxel sum with no k-NN "
    << "weighting), shows how much of k-NN's gain that sum alone gives. Best AUC of `octomap-opt` and `knn-opt`; "
    << "improvements in percent of OctoMap's best.\n\n"
    << "| resolution m | voxel filter | points | set | truth | true voxels | OctoMap AUC | k-NN AUC | k-NN % | "
    << "k-NN p_u = p_l AUC | p_u = p_l % |\n|---|---|---|---|---|---|---|---|---|---|---|\n";
  std::vector<std::string> means, verdicts, coverage;
  for (const json& configuration : r.at("configurations")) {
    std::vector<double> knn[2], equal[2];
    setRows(o, configuration, knn, equal);
    const std::string resolution = num(configuration.at("resolution").get<double>(), "%.2f"),
                      filter = filterText(configuration);
    if (const std::string line = coverageLine(configuration, resolution + " m, filter " + filter, knn); !line.empty())
      coverage.push_back(line);
    const char* truths[2] = {"full", "observable"};
    for (int t = 0; t < 2; ++t) {
      const json& s = configuration.at("statistics").at(truths[t]);
      means.push_back("| " + resolution + " | " + filter + " | " + truths[t] + " | " + num(mean(knn[t]), "%+.2f") +
                      " | " + num(mean(equal[t]), "%+.2f") + " | " + std::to_string(s.at("better").get<std::size_t>()) +
                      " of " + std::to_string(s.at("sets").get<std::size_t>()) + " |");
      verdicts.push_back("- " + resolution + " m, filter " + filter + ", " + truths[t] + " truth: k-NN better on " +
                         std::to_string(s.at("better").get<std::size_t>()) + " of " +
                         std::to_string(s.at("sets").get<std::size_t>()) + " sets; verdict on the optima **" +
                         s.at("verdict").get<std::string>() + "** (" + s.at("basis").get<std::string>() +
                         "); cross-validated **" + s.at("cross_validated_verdict").get<std::string>() + "**.");
    }
  }
  o << "\n| resolution m | voxel filter | truth | mean k-NN improvement % | mean p_u = p_l improvement % | k-NN better "
    << "(sets) |\n|---|---|---|---|---|---|\n";
  for (const auto& line : means) o << line << '\n';
  if (!coverage.empty())
    o << "\nTruth coverage, as `sweep` measures and warns on it (docs/import.md, \"Truth coverage and alignment\"): "
      << "one view sees part of the truth, and under full truth every map misses the rest:\n\n";
  for (const auto& line : coverage) o << line << '\n';
  o << "\nIs the gain real? compareStatistics over each configuration's sets (docs/statistics.md):\n\n";
  for (const auto& line : verdicts) o << line << '\n';
  o << "\nThe sets are three SGBM settings of one pair, one data set of one scene: the verdicts' unit is the scene "
    << "(their basis above), so one pair cannot tell whether the gain holds beyond it, however large it is on its sets. Holm families: each "
    << "configuration and truth is a comparison of its own (k-NN against OctoMap alone, no correction), the "
    << verdicts.size() << " not corrected jointly.\n\n";
}

}  // namespace occsweep::reproduce
