// occsweep compare: best AUC of each method per data set and point cloud set (the table behind Fig. 5).
#include <cmath>
#include <cstdio>
#include <iostream>

#include "command_registry.hpp"
#include "occsweep/sweeps/merge.hpp"

namespace occsweep::cli {
namespace {

std::string paramsText(const MapParams& p, bool knn) {
  char buf[160];
  if (knn)
    std::snprintf(buf, sizeof buf, "p_u=%g p_l=%g p_m=%g p'_m=%g k=%d", toDouble(p.p_u), toDouble(p.p_l),
                  toDouble(p.p_m), toDouble(p.p_m_out), p.k);
  else
    std::snprintf(buf, sizeof buf, "p_h=%g p_m=%g", toDouble(p.p_h), toDouble(p.p_m));
  return buf;
}

nlohmann::json bestJson(const std::optional<BestMap>& b, bool knn) {
  if (!b) return nullptr;
  return {{"auc", b->auc}, {"auc_observed", b->observed}, {"map_index", b->map_index},
          {"params", paramsText(b->params, knn)}};
}

const RegisterCommand kCompare{"compare", "Best AUC of OctoMap and k-NN per data set, and the improvement in percent",
                               [](CLI::App& app) {
  auto files = std::make_shared<std::vector<std::string>>();
  auto json_out = std::make_shared<std::string>();
  auto force = std::make_shared<bool>(false);
  app.add_option("files", *files, "Complete results files (any mix of methods and data sets)")->required();
  app.add_option("--json", *json_out, "Also write the table as JSON");
  app.add_flag("--force", *force, "Replace occsweep's own previous comparison at --json (nothing else)");
  return [files, json_out, force] {
    if (!json_out->empty()) checkOutputTarget(*json_out, *force, jsonOutput("comparison", "occsweep-comparison"));
    std::vector<ResultsFile> in;
    for (const auto& f : *files) {
      in.push_back(readResults(f));
      if (!in.back().complete) throw std::runtime_error(f + ": incomplete results");
    }
    const auto rows = compareBest(in);
    std::printf("%-28s %-8s %9s %9s %9s  %s | %s\n", "data set", "pcs", "OctoMap", "k-NN", "improve%",
                "OctoMap best", "k-NN best");
    nlohmann::json j = nlohmann::json::array();
    for (const auto& r : rows) {
      auto auc = [](const std::optional<BestMap>& b) { return b ? b->auc : std::nan(""); };
      std::printf("%-28s %-8s %9.4f %9.4f %9.2f  %s | %s\n", r.dataset.c_str(), r.point_cloud_set.c_str(),
                  auc(r.octomap), auc(r.knn), r.improvementPercent(),
                  r.octomap ? paramsText(r.octomap->params, false).c_str() : "-",
                  r.knn ? paramsText(r.knn->params, true).c_str() : "-");
      const double imp = r.improvementPercent();
      j.push_back({{"dataset", r.dataset}, {"point_cloud_set", r.point_cloud_set}, {"dataset_hash", r.dataset_hash},
                   {"octomap", bestJson(r.octomap, false)}, {"knn", bestJson(r.knn, true)},
                   {"improvement_percent", std::isfinite(imp) ? nlohmann::json(imp) : nlohmann::json(nullptr)}});
    }
    if (!json_out->empty()) writeJsonAtomically({{"format", "occsweep-comparison"}, {"rows", j}}, *json_out);
    return 0;
  };
}};

}  // namespace
}  // namespace occsweep::cli
