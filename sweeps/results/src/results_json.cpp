// Results files to and from JSON, with checks that catch a file edited by hand.
#include <cmath>
#include <fstream>
#include <functional>
#include <limits>
#include <stdexcept>
#include <unistd.h>

#include "occsweep/core/method_registry.hpp"
#include "occsweep/io/bounded_read.hpp"
#include "occsweep/sweeps/results.hpp"
#include "occsweep/sweeps/results_diff.hpp"
#include "occsweep/sweeps/results_store.hpp"
#include "occsweep/sweeps/results_verify.hpp"
#include "occsweep/eval/json_input.hpp"
#include "occsweep/eval/provenance.hpp"

namespace occsweep {
namespace {

using nlohmann::json;
constexpr const char* kFormat = "occsweep-results";
// Version 2 adds map.truth; full-truth files are still written as version 1 (byte for byte as before), so that
// only observable-truth files, which an older occsweep would misread as full truth, carry version 2.
constexpr int kVersion = 1, kTruthVersion = 2;

struct Reader {
  const std::string& file;
  [[noreturn]] void fail(const std::string& where, const std::string& rule) const {
    throw std::runtime_error(file + ": " + where + ": " + rule);
  }
  const json& at(const json& j, const std::string& key, const std::string& where) const {
    if (!j.is_object() || !j.contains(key)) fail(where.empty() ? key : where + "." + key, "is missing");
    return j.at(key);
  }
  std::string str(const json& j, const std::string& key, const std::string& where) const {
    const json& v = at(j, key, where);
    if (!v.is_string()) fail(where + "." + key, "must be a string");
    return v.get<std::string>();
  }
  std::uint64_t count(const json& j, const std::string& key, const std::string& where) const {
    const json& v = at(j, key, where);
    if (!v.is_number_unsigned()) fail(where + "." + key, "must be a non-negative integer");
    return v.get<std::uint64_t>();
  }
  double real(const json& j, const std::string& key, const std::string& where, bool nullable = false) const {
    const json& v = at(j, key, where);
    if (nullable && v.is_null()) return std::numeric_limits<double>::quiet_NaN();
    if (!v.is_number()) fail(where + "." + key, nullable ? "must be a number or null" : "must be a number");
    return v.get<double>();
  }
  Fixed fixed(const json& j, const std::string& key, const std::string& where) const {
    const double d = real(j, key, where);
    if (!std::isfinite(d) || d < 0 || d > 1e6) fail(where + "." + key, "must be a finite non-negative number");
    return std::llround(d * double(kFixedScale));
  }
  // A derived number must equal what its counts give: a hand edit of one or the other is caught.
  void agrees(double stored, double derived, const std::string& where) const {
    const bool both_nan = std::isnan(stored) && std::isnan(derived);
    if (!both_nan && !(std::abs(stored - derived) <= 1e-12 * std::max(1.0, std::abs(derived))))
      fail(where, "does not match the counts it is derived from (edited by hand?)");
  }
};

/// What resuming and merging say about the first header field that differs (incomparableHeaderFields' order).
std::string workDifferenceText(const ResultsDifference& d) {
  if (d.field.starts_with("grid.")) return "another grid";
  if (d.field.starts_with("dataset.")) return "another data set";
  if (d.field == "selection.group") return "another Eq. 16 group";
  if (d.field.starts_with("selection.shard.")) return "another shard";
  if (d.field == "map.resolution" || d.field == "map.s_c") return "another resolution or s_c";
  if (d.field == "map.variant" || d.field == "map.stats") return "another k-NN variant or statistics mode";
  return "another truth (map.truth: " + d.candidate + " against " + d.golden + ")";
}

// The parameters of a method this program has not registered, from a map's params: names in order, integers as
// written (docs/results-format.md).
ParameterLayout layoutFromMap(const json& map, const Reader& r) {
  const json& p = r.at(map, "params", "maps[0]");
  if (!p.is_object() || p.empty()) r.fail("maps[0].params", "must be an object of the method's parameters");
  ParameterLayout layout;
  for (const auto& [name, value] : p.items()) {
    layout.names.push_back(name);
    layout.integer.push_back(value.is_number_integer());
  }
  return layout;
}

}  // namespace

json finiteNumber(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

void setEngines(ResultsHeader& h, const std::set<std::string>& engines) {
  h.engines.assign(engines.begin(), engines.end());
  h.engine = engines.size() == 1 ? *engines.begin() : "mixed";
}

void refuseLargeJson(const std::filesystem::path& out, const std::string& writer, std::uint64_t combinations) {
  if (combinations > kMaxJsonCombinations)
    throw std::invalid_argument("--out " + out.string() + ": a JSON results file holds at most " +
                                std::to_string(kMaxJsonCombinations) + " combinations and " + writer + " writes " +
                                std::to_string(combinations) + "; use --out NAME.db (a results store, written batch "
                                "by batch; docs/results-format.md)");
}

bool sameWork(const ResultsHeader& a, const ResultsHeader& b, bool compare_shard, std::string* why) {
  const auto fields = incomparableHeaderFields(a, b, compare_shard);
  if (fields.empty()) return true;
  if (why) *why = workDifferenceText(fields.front());
  return false;
}

json toJson(const MapSettings& settings) {
  return {{"resolution", settings.resolution}, {"s_c", settings.s_c}, {"variant", toText(settings.variant)},
          {"stats", toText(settings.stats)}};
}

namespace {
// A setting's value in `j`: `fail` (which throws) for one missing, mistyped or out of range.
double lengthSetting(const json& j, const std::string& key,
                     const std::function<void(const std::string&, const std::string&)>& fail) {
  if (!j.contains(key)) fail(key, "is missing");
  if (!j.at(key).is_number() || !admitsLength(j.at(key).get<double>())) fail(key, kLengthRule);
  return j.at(key).get<double>();
}

template <class Enum, std::size_t N>
Enum namedSetting(const json& j, const std::string& key, const EnumNames<Enum, N>& names,
                  const std::function<void(const std::string&, const std::string&)>& fail) {
  if (!j.contains(key)) fail(key, "is missing");
  if (!j.at(key).is_string() || !names.accepts(j.at(key).get<std::string>()))
    fail(key, "must be " + names.alternatives("\""));
  return names.parse(j.at(key).get<std::string>());
}
}  // namespace

MapSettings parseMapSettings(const json& j, const std::function<void(const std::string&, const std::string&)>& fail) {
  MapSettings s;
  s.resolution = lengthSetting(j, "resolution", fail);
  s.s_c = lengthSetting(j, "s_c", fail);
  s.variant = namedSetting(j, "variant", kUpdateVariantNames, fail);
  s.stats = namedSetting(j, "stats", kStatsModeNames, fail);
  return s;
}

json toJson(const ResultsHeader& h) {
  json sel = {{"shard", {{"index", h.selection.shard_index}, {"count", h.selection.shard_count}}},
              {"group", nullptr}};
  if (h.selection.group)
    sel["group"] = {{"index", h.selection.group->index}, {"count", h.selection.group->count},
                    {"seed", h.selection.group->seed}};
  json j = {{"occsweep", {{"version", h.version}, {"commit", h.commit}}},
            {"grid", {{"name", h.grid_name}, {"file_hash", h.grid_hash}, {"method", h.method},
                      {"combinations", h.grid_combinations}}},
            {"selection", sel},
            {"dataset", {{"name", h.dataset_name}, {"content_hash", h.dataset_hash},
                         {"point_cloud_set", h.point_cloud_set}}},
            {"map", toJson(h.map)}};
  j["map"]["engine"] = h.engine;
  j["map"]["engines"] = h.engines.empty() ? std::vector<std::string>{h.engine} : h.engines;
  if (h.truth != TruthMode::Full) j["map"]["truth"] = truthModeName(h.truth);
  if (const auto& c = h.coverage)
    j["dataset"]["coverage"] = {{"truth_voxels", c->truth_voxels}, {"sampled_truth_voxels", c->sampled_truth},
                                {"observable_sampled", c->observable_sampled}, {"points", c->points},
                                {"points_in_region", c->points_in_region}, {"sampled_points", c->sampled_points},
                                {"median_point_distance", finiteNumber(c->median_point_distance)}};
  if (const auto& c = h.coverage; c && c->with_point_sampled)
    j["dataset"]["coverage"]["with_point_sampled"] = *c->with_point_sampled;
  if (const auto& c = h.coverage; c && c->offset_fit) {
    const OffsetFit& f = *c->offset_fit;
    j["dataset"]["coverage"]["offset_fit"] = {
        {"share_on_surface", f.share_on_surface}, {"offset_share_on_surface", f.offset_share_on_surface},
        {"offset_x", f.offset[0]}, {"offset_y", f.offset[1]}, {"offset_z", f.offset[2]}};
  }
  return j;
}

json toJson(const MapParams& p, const ParameterLayout& parameters) {
  json params = json::object();
  for (std::size_t i = 0; i < parameters.names.size(); ++i) {
    const Fixed v = p.values.at(i);
    params[parameters.names[i]] = parameters.integer[i] ? json(std::uint64_t(v / kFixedScale)) : json(toDouble(v));
  }
  return params;
}

json toJson(const MapResult& m, const ParameterLayout& parameters) {
  const json params = toJson(m.params, parameters);
  json thresholds = json::array();
  for (const auto& t : m.thresholds) {
    const auto& c = t.counts;
    thresholds.push_back({{"id", t.id}, {"p_t", toDouble(t.p_t)}, {"tp", c.tp}, {"fp", c.fp}, {"fn", c.fn},
                          {"tn", c.tn}, {"tpr", finiteNumber(c.tpr())}, {"fdr", finiteNumber(c.fdr())},
                          {"precision", finiteNumber(c.precision())}, {"fpr", finiteNumber(c.fpr())}});
  }
  return {{"map_index", m.map_index}, {"params", params}, {"thresholds", thresholds},
          {"auc", {{"anchored", finiteNumber(m.area.anchored)}, {"observed", finiteNumber(m.area.observed)},
                   {"points", m.area.points}}},
          {"seconds", m.seconds}};
}

json toJson(const ResultsFile& f) {
  json j = {{"format", kFormat}, {"version", f.header.truth == TruthMode::Full ? kVersion : kTruthVersion}};
  j.update(toJson(f.header));
  j["complete"] = f.complete;
  j["seconds"] = f.seconds;
  j["maps"] = json::array();
  for (const auto& m : f.maps) j["maps"].push_back(toJson(m, f.header.parameters));
  return j;
}

namespace {

// dataset.coverage.offset_fit (docs/results-format.md): shares of the `sampled` points, which must be some.
OffsetFit parseOffsetFit(const json& j, std::uint64_t sampled, const Reader& r) {
  const std::string where = "dataset.coverage.offset_fit";
  OffsetFit f;
  f.share_on_surface = r.real(j, "share_on_surface", where);
  f.offset_share_on_surface = r.real(j, "offset_share_on_surface", where);
  f.offset = {r.real(j, "offset_x", where), r.real(j, "offset_y", where), r.real(j, "offset_z", where)};
  for (double share : {f.share_on_surface, f.offset_share_on_surface})
    if (!(share >= 0 && share <= 1) || sampled == 0) r.fail(where, "shares that cannot hold (edited by hand?)");
  return f;
}

// dataset.coverage (docs/results-format.md), at the file's resolution and s_c; counts that cannot hold (more
// observable voxels than sampled) are refused as a hand edit.
TruthCoverage parseCoverage(const json& j, const MapSettings& map, const Reader& r) {
  const std::string where = "dataset.coverage";
  TruthCoverage c;
  c.resolution = map.resolution, c.s_c = map.s_c;
  c.truth_voxels = r.count(j, "truth_voxels", where);
  c.sampled_truth = r.count(j, "sampled_truth_voxels", where);
  c.observable_sampled = r.count(j, "observable_sampled", where);
  c.points = r.count(j, "points", where);
  c.points_in_region = r.count(j, "points_in_region", where);
  c.sampled_points = r.count(j, "sampled_points", where);
  c.median_point_distance = r.real(j, "median_point_distance", where, true);
  if (j.contains("with_point_sampled")) c.with_point_sampled = r.count(j, "with_point_sampled", where);
  if (c.observable_sampled > c.sampled_truth || c.with_point_sampled.value_or(0) > c.sampled_truth || c.sampled_truth > c.truth_voxels ||
      c.sampled_points > c.points_in_region || c.points_in_region > c.points || c.median_point_distance < 0 ||
      std::isnan(c.median_point_distance) != (c.sampled_points == 0) ||
      (c.sampled_points == 0) != (c.points_in_region == 0))
    r.fail(where, "counts that cannot hold (edited by hand?)");
  if (j.contains("offset_fit")) c.offset_fit = parseOffsetFit(j.at("offset_fit"), c.sampled_points, r);
  return c;
}

// The engines a results file may name (docs/results-format.md): each of `engines` "direct" or "replay", and
// `engine` the one of them, or "mixed" for several.
void requireKnownEngines(const ResultsHeader& h, const std::function<void(const std::string&)>& fail) {
  for (const std::string& e : h.engines)
    if (e != kDirectEngine && e != kReplayEngine)
      fail("'" + e + "' is not an engine (" + kDirectEngine + " or " + kReplayEngine + "; edited by hand?)");
  const std::string expected = h.engines.size() == 1 ? h.engines.front() : "mixed";
  if (h.engine != expected) fail("'" + h.engine + "' does not match map.engines (it must be '" + expected + "')");
}

}  // namespace

ResultsHeader parseHeader(const json& j, const std::string& file) {
  const Reader r{file};
  ResultsHeader h;
  const json& o = r.at(j, "occsweep", "");
  h.version = r.str(o, "version", "occsweep");
  h.commit = r.str(o, "commit", "occsweep");
  const json& g = r.at(j, "grid", "");
  h.grid_name = r.str(g, "name", "grid");
  h.grid_hash = r.str(g, "file_hash", "grid");
  h.method = r.str(g, "method", "grid");
  if (h.method.empty()) r.fail("grid.method", "must name a method");
  try {
    h.parameters = layoutOf(h.method);
  } catch (const std::invalid_argument&) {
    // Not registered here (a method of another program): parseResults takes the layout from the maps.
  }
  h.grid_combinations = r.count(g, "combinations", "grid");
  const json& sel = r.at(j, "selection", "");
  const json& shard = r.at(sel, "shard", "selection");
  h.selection.shard_index = r.count(shard, "index", "selection.shard");
  h.selection.shard_count = r.count(shard, "count", "selection.shard");
  if (h.selection.shard_count == 0 || h.selection.shard_index >= h.selection.shard_count)
    r.fail("selection.shard", "index must be < count");
  const json& group = r.at(sel, "group", "selection");
  if (!group.is_null()) {
    SweepSelection::Group gr{r.count(group, "index", "selection.group"), r.count(group, "count", "selection.group"),
                             r.count(group, "seed", "selection.group")};
    if (gr.count == 0 || gr.index >= gr.count) r.fail("selection.group", "index must be < count");
    h.selection.group = gr;
  }
  const json& d = r.at(j, "dataset", "");
  h.dataset_name = r.str(d, "name", "dataset");
  h.dataset_hash = r.str(d, "content_hash", "dataset");
  h.point_cloud_set = r.at(d, "point_cloud_set", "dataset");
  if (h.point_cloud_set.is_object() && h.point_cloud_set.contains("provenance"))
    checkProvenance(h.point_cloud_set.at("provenance"), file, "dataset.point_cloud_set.provenance");
  const json& m = r.at(j, "map", "");
  if (!m.is_object()) r.fail("map", "must be an object");
  h.map = parseMapSettings(m, [&](const std::string& key, const std::string& rule) { r.fail("map." + key, rule); });
  h.engine = r.str(m, "engine", "map");
  h.engines = {h.engine};
  if (m.contains("engines")) {
    const json& list = m.at("engines");
    if (!list.is_array() || list.empty()) r.fail("map.engines", "must be a non-empty array of engine names");
    h.engines.clear();
    for (const auto& e : list) {
      if (!e.is_string()) r.fail("map.engines", "must be a non-empty array of engine names");
      h.engines.push_back(e.get<std::string>());
    }
  }
  requireKnownEngines(h, [&](const std::string& why) { r.fail("map.engine", why); });
  if (m.contains("truth")) {
    try {
      h.truth = parseTruthMode(m.at("truth").is_string() ? m.at("truth").get<std::string>() : "");
    } catch (const std::invalid_argument&) {
      r.fail("map.truth", "must be \"full\" or \"observable\"");
    }
  }
  if (d.contains("coverage")) h.coverage = parseCoverage(d.at("coverage"), h.map, r);
  return h;
}

MapResult parseMapResult(const json& j, const ParameterLayout& parameters, const std::string& file,
                         const std::string& where) {
  const Reader r{file};
  MapResult m;
  m.map_index = r.count(j, "map_index", where);
  const json& p = r.at(j, "params", where);
  const std::string pw = where + ".params";
  if (!p.is_object() || p.size() != parameters.names.size())
    r.fail(pw, "must hold exactly the method's parameters (" + std::to_string(parameters.names.size()) + ")");
  for (std::size_t i = 0; i < parameters.names.size(); ++i) {
    const std::string& name = parameters.names[i];
    if (parameters.integer[i]) {
      const std::uint64_t v = r.count(p, name, pw);
      if (v > 1000000) r.fail(pw + "." + name, "must be an integer in [0, 1000000]");
      m.params.values.push_back(Fixed(v) * kFixedScale);
    } else {
      m.params.values.push_back(r.fixed(p, name, pw));
    }
  }
  const json& ts = r.at(j, "thresholds", where);
  if (!ts.is_array() || ts.empty()) r.fail(where + ".thresholds", "must be a non-empty array");
  std::uint64_t total = 0;
  for (std::size_t i = 0; i < ts.size(); ++i) {
    const std::string tw = where + ".thresholds[" + std::to_string(i) + "]";
    ThresholdResult t;
    t.id = r.count(ts[i], "id", tw);
    t.p_t = r.fixed(ts[i], "p_t", tw);
    t.counts = {r.count(ts[i], "tp", tw), r.count(ts[i], "fp", tw), r.count(ts[i], "fn", tw),
                r.count(ts[i], "tn", tw)};
    const auto& c = t.counts;
    std::uint64_t sum = 0;
    if (__builtin_add_overflow(c.tp, c.fp, &sum) || __builtin_add_overflow(sum, c.fn, &sum) ||
        __builtin_add_overflow(sum, c.tn, &sum))
      r.fail(tw, "TP+FP+FN+TN overflows 64 bits (edited by hand?)");
    if (i == 0) total = sum;
    if (sum != total) r.fail(tw, "TP+FP+FN+TN differs between thresholds of one map (edited by hand?)");
    r.agrees(r.real(ts[i], "tpr", tw, true), c.tpr(), tw + ".tpr");
    r.agrees(r.real(ts[i], "fdr", tw, true), c.fdr(), tw + ".fdr");
    r.agrees(r.real(ts[i], "precision", tw, true), c.precision(), tw + ".precision");
    r.agrees(r.real(ts[i], "fpr", tw, true), c.fpr(), tw + ".fpr");
    m.thresholds.push_back(t);
  }
  const json& auc = r.at(j, "auc", where);
  m.area = mapArea(m.thresholds);
  r.agrees(r.real(auc, "anchored", where + ".auc", true), m.area.anchored, where + ".auc.anchored");
  r.agrees(r.real(auc, "observed", where + ".auc", true), m.area.observed, where + ".auc.observed");
  if (auc.contains("points") && r.count(auc, "points", where + ".auc") != std::uint64_t(m.area.points))
    r.fail(where + ".auc.points", "is not the number of valid curve points of its thresholds (" +
                                      std::to_string(m.area.points) + "; edited by hand?)");
  m.seconds = r.real(j, "seconds", where);
  return m;
}

ResultsFile parseResults(const json& j, const std::string& file) {
  const Reader r{file};
  if (!j.is_object()) r.fail("(top)", "must be a JSON object");
  if (!j.contains("format") || j.at("format") != kFormat) r.fail("format", std::string("must be \"") + kFormat + "\"");
  if (!j.contains("version") || (j.at("version") != kVersion && j.at("version") != kTruthVersion))
    r.fail("version", "unsupported results version");
  ResultsFile f;
  f.header = parseHeader(j, file);
  const bool has_truth = j.at("map").contains("truth");
  if (j.at("version") == kVersion && has_truth) r.fail("map.truth", "is a version 2 field (this file says version 1)");
  if (j.at("version") == kTruthVersion && !has_truth) r.fail("map.truth", "is missing (required in version 2)");
  const json& complete = r.at(j, "complete", "");
  if (!complete.is_boolean()) r.fail("complete", "must be true or false");
  f.complete = complete.get<bool>();
  f.seconds = r.real(j, "seconds", "");
  const json& maps = r.at(j, "maps", "");
  if (!maps.is_array()) r.fail("maps", "must be an array");
  if (f.header.parameters.names.empty() && !maps.empty()) f.header.parameters = layoutFromMap(maps[0], r);
  for (std::size_t i = 0; i < maps.size(); ++i)
    f.maps.push_back(parseMapResult(maps[i], f.header.parameters, file, "maps[" + std::to_string(i) + "]"));
  verifyClaims(f, file);
  if (!f.maps.empty()) f.truth_voxels = f.maps.front().thresholds.front().counts.tp + f.maps.front().thresholds.front().counts.fn;
  return f;
}

ResultsFile readResults(const std::filesystem::path& file) {
  if (isResultsStore(file)) return readResultsAt(file, MapDetail::Full);
  return parseResults(readJsonFile(file), file.string());
}

ReplaceableOutput resultsOutput() {
  const ReplaceableOutput json_results = jsonOutput("results file", kFormat);
  return {json_results.name, [json_results](const std::filesystem::path& file) {
            if (!isResultsStore(file)) return json_results.is_own(file);
            if (!isOccsweepStore(file)) return false;  // no occsweep application_id: never replaced
            try {
              (void)ResultsStore::open(file);
              return true;
            } catch (const std::exception&) {
              return false;  // another program's SQLite database: never replaced
            }
          }};
}

void writeResults(const ResultsFile& f, const std::filesystem::path& file) { writeJsonAtomically(toJson(f), file); }

CurveArea mapArea(const std::vector<ThresholdResult>& thresholds) {
  std::vector<ConfusionCounts> counts;
  for (const auto& t : thresholds) counts.push_back(t.counts);
  return curveArea(curvePoints(counts));
}

}  // namespace occsweep
