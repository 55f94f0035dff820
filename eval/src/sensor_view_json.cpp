#include "occsweep/eval/sensor_view_json.hpp"

#include <climits>

#include "occsweep/io/data_error.hpp"

namespace occsweep {
namespace {

using nlohmann::json;

struct ViewFields {
  const json& view;
  const std::filesystem::path& file;
  const std::string& where;

  [[nodiscard]] const json& at(const char* key) const {
    if (!view.contains(key)) throw DataError(file, where + "." + key, "field is missing");
    return view.at(key);
  }
  [[nodiscard]] double number(const char* key) const {
    const json& v = at(key);
    if (!v.is_number()) throw DataError(file, where + "." + key, "must be a number");
    return v.get<double>();
  }
  [[nodiscard]] int pixels(const char* key) const {
    const json& v = at(key);
    if (!v.is_number_integer() || v.get<std::int64_t>() < 1 || v.get<std::int64_t>() > INT_MAX)
      throw DataError(file, where + "." + key, "must be an integer >= 1");
    return int(v.get<std::int64_t>());
  }
  template <std::size_t N>
  [[nodiscard]] std::array<double, N> numbers(const char* key) const {
    const json& v = at(key);
    const std::string rule = "must be an array of " + std::to_string(N) + " numbers";
    if (!v.is_array() || v.size() != N) throw DataError(file, where + "." + key, rule);
    std::array<double, N> out{};
    for (std::size_t i = 0; i < N; ++i) {
      if (!v[i].is_number()) throw DataError(file, where + "." + key, rule);
      out[i] = v[i].get<double>();
    }
    return out;
  }
};

SensorView parsedView(const ViewFields& f) {
  const json& model = f.at("model");
  const std::string name = model.is_string() ? model.get<std::string>() : "";
  if (name == "pinhole")
    return PinholeView{f.number("fx"),    f.number("fy"),     f.number("cx"),          f.number("cy"),
                       f.pixels("width"), f.pixels("height"), f.numbers<9>("rotation")};
  if (name == "cone") return ConeView{f.numbers<3>("axis"), f.number("half_angle_deg")};
  if (name == "sphere") return SphereView{};
  throw DataError(f.file, f.where + ".model", "must be \"pinhole\", \"cone\" or \"sphere\"");
}

}  // namespace

json sensorViewJson(const SensorView& view) {
  if (const auto* p = std::get_if<PinholeView>(&view))
    return {{"model", "pinhole"}, {"fx", p->fx},        {"fy", p->fy},         {"cx", p->cx},
            {"cy", p->cy},        {"width", p->width},  {"height", p->height}, {"rotation", p->rotation}};
  if (const auto* c = std::get_if<ConeView>(&view))
    return {{"model", "cone"}, {"axis", c->axis}, {"half_angle_deg", c->half_angle_deg}};
  return {{"model", "sphere"}};
}

SensorView sensorViewFromJson(const json& view, const std::filesystem::path& file, const std::string& where) {
  if (!view.is_object()) throw DataError(file, where, "must be an object with a \"model\"");
  const SensorView parsed = parsedView(ViewFields{view, file, where});
  if (const auto broken = brokenViewRule(parsed)) throw DataError(file, where + "." + broken->field, broken->rule);
  return parsed;
}

}  // namespace occsweep
