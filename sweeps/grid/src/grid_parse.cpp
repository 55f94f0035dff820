// Reading grid files: every rule broken is named with the file and the key.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <set>
#include <stdexcept>

#include "occsweep/core/method_registry.hpp"
#include "occsweep/io/fnv1a.hpp"
#include "occsweep/io/path_component.hpp"
#include "occsweep/sweeps/grid.hpp"
#include "occsweep/eval/json_input.hpp"

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

  // A method's bounds on one parameter's whole range (Eq. 12's for OctoMap and k-NN); the relations between
  // parameters are enumerated.
  void bounds(const ParamRange& r, const MethodParameter& p) const {
    const double lo = toDouble(r.listed.empty() ? r.min : *std::min_element(r.listed.begin(), r.listed.end()));
    const double hi = toDouble(r.listed.empty() ? r.max : *std::max_element(r.listed.begin(), r.listed.end()));
    if (!admits(p, lo) || !admits(p, hi)) fail("parameters." + p.name, "values must lie in " + boundText(p));
  }

  // An integer parameter (k): a non-empty list of distinct integers within its bounds.
  ParamRange integers(const json& params, const MethodParameter& p) const {
    const std::string where = "parameters." + p.name;
    const std::string rule = "must be a non-empty list of distinct integers in " + boundText(p);
    if (!params.contains(p.name) || !params.at(p.name).is_array() || params.at(p.name).empty()) fail(where, rule);
    ParamRange r;
    std::set<long long> seen;
    for (const auto& v : params.at(p.name)) {
      if (!v.is_number_integer() || v.get<long long>() < 0 || v.get<long long>() > 1000000) fail(where, rule);
      if (!seen.insert(v.get<long long>()).second) fail(where, "lists " + v.dump() + " twice");
      r.listed.push_back(Fixed(v.get<long long>()) * kFixedScale);
    }
    bounds(r, p);
    return r;
  }
};

// The method named by the file, registered (method_registry.hpp).
const MappingMethod& gridMethod(const GridReader& r, const json& j) {
  const std::string rule = "must name a registered method: " + registeredMethodNames();
  if (!j.contains("method") || !j.at("method").is_string()) r.fail("method", rule);
  try {
    return findMethod(j.at("method").get<std::string>());
  } catch (const std::invalid_argument&) {
    r.fail("method", "'" + j.at("method").get<std::string>() + "' " + rule);
  }
}

}  // namespace

GridSpec parseGrid(const json& j, const std::string& file) {
  const GridReader r{file};
  r.onlyKeys(j, {"name", "method", "description", "parameters"}, "");
  GridSpec g;
  if (!j.contains("name") || !j.at("name").is_string() || j.at("name").get<std::string>().empty())
    r.fail("name", "must be a non-empty string");
  g.name = j.at("name").get<std::string>();
  if (const auto broken = brokenPathComponentRule(g.name)) r.fail("name", *broken);
  const MappingMethod& method = gridMethod(r, j);
  g.method = method.name();
  g.layout = layoutOf(g.method);
  if (j.contains("description")) {
    if (!j.at("description").is_string()) r.fail("description", "must be a string");
    g.description = j.at("description").get<std::string>();
  }
  if (!j.contains("parameters")) r.fail("parameters", "is missing");
  const json& p = j.at("parameters");
  std::set<std::string> keys(g.layout.names.begin(), g.layout.names.end());
  keys.insert("p_t");
  r.onlyKeys(p, keys, "parameters");
  for (const MethodParameter& parameter : method.parameters()) {
    g.ranges.push_back(parameter.integer ? r.integers(p, parameter) : r.range(p, parameter.name));
    r.bounds(g.ranges.back(), parameter);
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
  const std::string bytes = readJsonBytes(file);  // refuses folders, FIFOs and files past --max-json-bytes by name
  GridSpec g = parseGrid(parseJsonTextUniqueKeys(bytes, file), file.string());
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
  // is, unless it is a bare name that may be a grid of a grid folder.
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

}  // namespace occsweep
