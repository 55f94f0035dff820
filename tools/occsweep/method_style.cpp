// How a method is shown to a reader (docs/statistics.md, "Figures").
#include "method_style.hpp"

#include <algorithm>
#include <numeric>

#include "occsweep/core/method_registry.hpp"
#include "occsweep/eval/bounded_read.hpp"
#include "occsweep/eval/data_error.hpp"

namespace occsweep::cli {
namespace {

// Okabe and Ito's eight colours; the shipped methods take the first five in this order.
const std::vector<std::string> kOkabeIto = {"#000000", "#D55E00", "#0072B2", "#009E73",
                                            "#CC79A7", "#E69F00", "#56B4E9", "#F0E442"};
const std::map<std::string, std::size_t> kShipped = {
    {"octomap", 0}, {"knn", 1}, {"sor-octomap", 2}, {"ror-octomap", 3}, {"range-octomap", 4}};

// The longest display name a style may give: a legend entry, not a sentence.
constexpr std::size_t kMaxDisplayName = 60;

bool isColour(const std::string& s) {
  return s.size() == 7 && s[0] == '#' && std::all_of(s.begin() + 1, s.end(), [](unsigned char c) {
           return std::isxdigit(c) != 0;
         });
}

bool isDisplayName(const std::string& s) {
  return !s.empty() && s.size() <= kMaxDisplayName &&
         std::none_of(s.begin(), s.end(), [](unsigned char c) { return c < 0x20 || c == 0x7f; });
}

// One method's fields, checked: each a string that its rule allows.
void checkMethodFields(const std::filesystem::path& file, const std::string& method, const nlohmann::json& fields) {
  const std::string where = "methods." + method;
  if (!fields.is_object()) throw DataError(file, where, "must be an object of name, colour, marker and line");
  for (const auto& [key, value] : fields.items()) {
    const std::string field = where + "." + key;
    if (key != "name" && key != "colour" && key != "marker" && key != "line")
      throw DataError(file, field, "unknown field (a method's style has name, colour, marker and line)");
    if (!value.is_string()) throw DataError(file, field, "must be a string");
    const std::string v = value.get<std::string>();
    if (key == "name" && !isDisplayName(v))
      throw DataError(file, field, "must be 1 to " + std::to_string(kMaxDisplayName) + " characters, no control character");
    if (key == "colour" && !isColour(v)) throw DataError(file, field, "must be a colour #RRGGBB, got '" + v + "'");
    auto oneOf = [&](const std::vector<std::string>& allowed) {
      if (std::find(allowed.begin(), allowed.end(), v) != allowed.end()) return;
      const std::string list = std::accumulate(std::next(allowed.begin()), allowed.end(), "'" + allowed[0] + "'",
                                               [](std::string a, const std::string& b) { return a + ", '" + b + "'"; });
      throw DataError(file, field, "must be one of " + list + ", got '" + v + "'");
    };
    if (key == "marker") oneOf(kMarkers);
    if (key == "line") oneOf(kLineStyles);
  }
}

}  // namespace

std::string displayNameOf(const std::string& method) {
  try {
    return findMethod(method).displayName();
  } catch (const std::invalid_argument&) {
    return method;
  }
}

MethodStyle defaultStyle(const std::string& method) {
  std::size_t index = 0;
  if (const auto shipped = kShipped.find(method); shipped != kShipped.end()) {
    index = shipped->second;
  } else {  // the three colours no shipped method takes, by the sum of the name's bytes: stable from run to run
    const unsigned sum = std::accumulate(method.begin(), method.end(), 0u,
                                         [](unsigned s, char c) { return s + static_cast<unsigned char>(c); });
    index = kShipped.size() + sum % (kOkabeIto.size() - kShipped.size());
  }
  return {displayNameOf(method), kOkabeIto[index], kMarkers[index], kLineStyles[index]};
}

StyleOverrides readStyleFile(const std::filesystem::path& file) {
  constexpr std::uint64_t kMaxStyleBytes = 1 << 20;  // a few lines per method
  const nlohmann::json style = parseJsonTextUniqueKeys(readFileBytes(file, kMaxStyleBytes), file);
  if (!style.is_object()) throw DataError(file, "", "a style file is a JSON object {\"methods\": {...}}");
  for (const auto& [key, value] : style.items())
    if (key != "methods") throw DataError(file, key, "unknown field (a style file has methods)");
  StyleOverrides overrides;
  if (!style.contains("methods")) return overrides;
  if (!style["methods"].is_object()) throw DataError(file, "methods", "must be an object, by method name");
  for (const auto& [method, fields] : style["methods"].items()) {
    checkMethodFields(file, method, fields);
    overrides[method] = fields;
  }
  return overrides;
}

nlohmann::json methodStyles(const std::vector<std::string>& methods, const StyleOverrides& overrides) {
  nlohmann::json styles = nlohmann::json::object();
  for (const std::string& m : methods) {
    const MethodStyle d = defaultStyle(m);
    nlohmann::json s = {{"name", d.name}, {"colour", d.colour}, {"marker", d.marker}, {"line", d.line}};
    if (const auto o = overrides.find(m); o != overrides.end()) s.update(o->second);
    styles[m] = s;
  }
  return styles;
}

}  // namespace occsweep::cli
