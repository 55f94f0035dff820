// Reading grid files: every rule broken is named with the file and the key.
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <set>
#include <stdexcept>

#include "occsweep/eval/fnv1a.hpp"
#include "occsweep/sweeps/grid.hpp"

namespace occsweep {
namespace {

using nlohmann::json;

struct GridReader {
  std::string file;

  [[noreturn]] void fail(const std::string& where, const std::string& rule) const {
    throw std::runtime_error(file + ": " + where + ": " + rule);
  }

  Fixed fixed(const json& v, const std::string& where) const {
    if (!v.is_number()) fail(where, "must be a number");
    const double d = v.get<double>();
    if (!std::isfinite(d)) fail(where, "must be finite");
    if (d < 0) fail(where, "must not be negative");
    if (d > 1e6) fail(where, "is absurdly large");
    const double scaled = d * double(kFixedScale);
    const Fixed units = std::llround(scaled);
    if (std::abs(scaled - double(units)) > 1e-6) fail(where, "has more than 6 decimals");
    return units;
  }

  void onlyKeys(const json& obj, const std::set<std::string>& allowed, const std::string& where) const {
    if (!obj.is_object()) fail(where, "must be an object");
    for (const auto& [key, _] : obj.items())
      if (!allowed.count(key)) fail(where.empty() ? key : where + "." + key, "unknown key");
  }

  ParamRange range(const json& params, const std::string& name) const {
    const std::string where = "parameters." + name;
    if (!params.contains(name)) fail(where, "is missing");
    const json& v = params.at(name);
    onlyKeys(v, {"min", "max", "step", "value"}, where);
    ParamRange r;
    if (v.contains("value")) {
      if (v.contains("min") || v.contains("max") || v.contains("step")) fail(where, "give either value or min/max/step");
      r.min = r.max = fixed(v.at("value"), where + ".value");
      return r;
    }
    for (const char* key : {"min", "max"})
      if (!v.contains(key)) fail(where + "." + key, "is missing");
    r.min = fixed(v.at("min"), where + ".min");
    r.max = fixed(v.at("max"), where + ".max");
    if (r.min > r.max) fail(where, "inverted range: min > max");
    if (v.contains("step")) {
      if (!v.at("step").is_number() || v.at("step").get<double>() <= 0) fail(where + ".step", "must be > 0");
      r.step = fixed(v.at("step"), where + ".step");
      if (r.step == 0) fail(where + ".step", "must be > 0");
    } else if (r.min != r.max) {
      fail(where + ".step", "is missing for a range with min < max");
    }
    return r;
  }

  // Eq. 12's bounds on one parameter's whole range; the relations between parameters are enumerated.
  void bounds(const ParamRange& r, const std::string& name, Fixed lo, bool lo_open, Fixed hi, bool hi_open,
              const std::string& relation) const {
    const bool lo_ok = lo_open ? r.min > lo : r.min >= lo;
    const bool hi_ok = hi_open ? r.max < hi : r.max <= hi;
    if (!lo_ok || !hi_ok) fail("parameters." + name, "values must satisfy " + relation);
  }
};

constexpr Fixed kHalf = kFixedScale / 2, kOne = kFixedScale;

}  // namespace

GridSpec parseGrid(const json& j, const std::string& file) {
  const GridReader r{file};
  r.onlyKeys(j, {"name", "method", "description", "parameters"}, "");
  GridSpec g;
  if (!j.contains("name") || !j.at("name").is_string() || j.at("name").get<std::string>().empty())
    r.fail("name", "must be a non-empty string");
  g.name = j.at("name").get<std::string>();
  if (!j.contains("method") || !j.at("method").is_string()) r.fail("method", "must be \"knn\" or \"octomap\"");
  const std::string method = j.at("method").get<std::string>();
  if (method != "knn" && method != "octomap") r.fail("method", "must be \"knn\" or \"octomap\"");
  g.method = method == "knn" ? GridMethod::Knn : GridMethod::OctoMap;
  if (j.contains("description")) {
    if (!j.at("description").is_string()) r.fail("description", "must be a string");
    g.description = j.at("description").get<std::string>();
  }
  if (!j.contains("parameters")) r.fail("parameters", "is missing");
  const json& p = j.at("parameters");
  const bool knn = g.method == GridMethod::Knn;
  r.onlyKeys(p, knn ? std::set<std::string>{"p_max", "p_min", "p_m", "p_m_out", "p_u", "p_l", "p_t", "k"}
                    : std::set<std::string>{"p_max", "p_min", "p_m", "p_h", "p_t"},
             "parameters");
  g.p_max = r.range(p, "p_max");
  r.bounds(g.p_max, "p_max", kHalf, false, kOne, true, "1 > p_max >= 0.5 (Eq. 12)");
  g.p_min = r.range(p, "p_min");
  r.bounds(g.p_min, "p_min", 0, true, kHalf, true, "0.5 > p_min > 0 (Eq. 12)");
  g.p_m = r.range(p, "p_m");
  r.bounds(g.p_m, "p_m", 0, true, kHalf, true, "0.5 > p_m > 0 (Eq. 12)");
  if (knn) {
    g.p_m_out = r.range(p, "p_m_out");
    r.bounds(g.p_m_out, "p_m_out", 0, true, kHalf, true, "0.5 > p'_m > 0 (Eq. 12)");
    g.p_u = r.range(p, "p_u");
    r.bounds(g.p_u, "p_u", 0, true, kOne, true, "1 > p_u > 0 (l(p(s)) finite)");
    g.p_l = r.range(p, "p_l");
    r.bounds(g.p_l, "p_l", 0, true, kOne, true, "1 > p_l > 0 (l(p(s)) finite)");
    if (!p.contains("k") || !p.at("k").is_array() || p.at("k").empty())
      r.fail("parameters.k", "must be a non-empty list of integers >= 1");
    std::set<int> seen;
    for (const auto& v : p.at("k")) {
      if (!v.is_number_integer() || v.get<long long>() < 1 || v.get<long long>() > 100000)
        r.fail("parameters.k", "must be a non-empty list of integers >= 1");
      if (!seen.insert(v.get<int>()).second) r.fail("parameters.k", "lists " + v.dump() + " twice");
      g.k.push_back(v.get<int>());
    }
  } else {
    g.p_h = r.range(p, "p_h");
    r.bounds(g.p_h, "p_h", kHalf, false, kOne, true, "1 > p_h >= 0.5 (Eq. 12)");
  }
  if (!p.contains("p_t")) r.fail("parameters.p_t", "is missing");
  r.onlyKeys(p.at("p_t"), {"step"}, "parameters.p_t");
  if (!p.at("p_t").contains("step") || !p.at("p_t").at("step").is_number() ||
      p.at("p_t").at("step").get<double>() <= 0)
    r.fail("parameters.p_t.step", "must be > 0 (p_t runs from p_min to p_max by it)");
  g.p_t_step = r.fixed(p.at("p_t").at("step"), "parameters.p_t.step");
  if (g.p_t_step == 0) r.fail("parameters.p_t.step", "must be > 0");
  return g;
}

GridSpec loadGrid(const std::filesystem::path& file) {
  const std::string bytes = readFileBytes(file);  // refuses folders and FIFOs by name (issue 13)
  GridSpec g = parseGrid(parseJsonText(bytes, file), file.string());
  Fnv1a h;
  h.feed(bytes);
  g.file_hash = h.hex();
  return g;
}

namespace {
std::vector<std::filesystem::path>& gridFolders() {
  static std::vector<std::filesystem::path> folders;
  return folders;
}
}  // namespace

void addGridFolder(const std::filesystem::path& folder) { gridFolders().push_back(folder); }

std::filesystem::path resolveGridPath(const std::string& name_or_path) {
  namespace fs = std::filesystem;
  const fs::path given = name_or_path;
  // A path that exists but is no regular file (a folder, a FIFO, a link loop) goes to loadGrid, which says what it
  // is (issue 13), unless it is a bare name that may be a grid of a grid folder.
  if (fs::is_regular_file(given) ||
      (fs::exists(fs::symlink_status(given)) && (given.has_parent_path() || given.extension() == ".json")))
    return given;
  std::vector<fs::path> places;
  if (const char* env = std::getenv("OCCSWEEP_GRIDS")) places.emplace_back(env);
  places.insert(places.end(), gridFolders().begin(), gridFolders().end());
  for (const auto& dir : places)
    if (fs::is_regular_file(dir / (name_or_path + ".json"))) return dir / (name_or_path + ".json");
  std::string message = "grid '" + name_or_path + "': no such file, nor " + name_or_path + ".json in";
  for (const auto& dir : places) message.append(" ").append(dir.string());
  throw std::runtime_error(message);
}

const char* methodName(GridMethod m) { return m == GridMethod::Knn ? "knn" : "octomap"; }

}  // namespace occsweep
