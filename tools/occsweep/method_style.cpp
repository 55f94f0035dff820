// How a method is shown to a reader (docs/statistics.md, "Figures").
#include "method_style.hpp"

#include <algorithm>
#include <cctype>
#include <numeric>

#include "occsweep/core/method_registry.hpp"
#include "occsweep/io/bounded_read.hpp"
#include "occsweep/io/control_characters.hpp"
#include "occsweep/io/data_error.hpp"
#include "occsweep/eval/json_input.hpp"

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

// 1 to kMaxDisplayName characters, no control or bidirectional-control character, which would hide or reorder the
// name's text (the style file is valid UTF-8: the JSON reader refused it otherwise).
bool isDisplayName(const std::string& s) {
  const std::vector<Utf8Character> characters = utf8Characters(s);
  return !characters.empty() && characters.size() <= kMaxDisplayName && !hasControlCharacters(s);
}

const LineStyle& lineStyle(const std::string& name) {
  return *std::find_if(kLineStyles.begin(), kLineStyles.end(), [&](const LineStyle& l) { return l.name == name; });
}

std::vector<std::string> lineStyleNames() {
  std::vector<std::string> names;
  for (const LineStyle& l : kLineStyles) names.push_back(l.name);
  return names;
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
      throw DataError(file, field, "must be 1 to " + std::to_string(kMaxDisplayName) +
                                       " characters, no control or bidirectional-control character");
    if (key == "colour" && !isColour(v)) throw DataError(file, field, "must be a colour #RRGGBB, got '" + v + "'");
    auto oneOf = [&](const std::vector<std::string>& allowed) {
      if (std::find(allowed.begin(), allowed.end(), v) != allowed.end()) return;
      const std::string list = std::accumulate(std::next(allowed.begin()), allowed.end(), "'" + allowed[0] + "'",
                                               [](std::string a, const std::string& b) { return a + ", '" + b + "'"; });
      throw DataError(file, field, "must be one of " + list + ", got '" + v + "'");
    };
    if (key == "marker") oneOf(kMarkers);
    if (key == "line") oneOf(lineStyleNames());
  }
}

// Two methods a reader could not tell apart in a figure: one display name, or one colour, marker and line.
void requireDistinctStyles(const nlohmann::json& styles, const std::filesystem::path& style_file) {
  const std::string where = style_file.empty() ? "" : style_file.string() + ": ";
  const std::string fix = style_file.empty() ? "give them styles of their own with --style"
                                             : "give them styles of their own in " + style_file.string();
  for (auto a = styles.begin(); a != styles.end(); ++a)
    for (auto b = std::next(a); b != styles.end(); ++b) {
      if ((*a)["name"] == (*b)["name"])
        throw std::invalid_argument(where + "methods " + a.key() + " and " + b.key() + " would both be shown as '" +
                                    (*a)["name"].get<std::string>() + "': " + fix);
      if ((*a)["colour"] == (*b)["colour"] && (*a)["marker"] == (*b)["marker"] && (*a)["line"] == (*b)["line"])
        throw std::invalid_argument(where + "methods " + a.key() + " and " + b.key() +
                                    " would be drawn alike (one colour, marker and line): " + fix);
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
  if (const auto shipped = kShipped.find(method); shipped != kShipped.end()) {
    const std::size_t i = shipped->second;
    return {displayNameOf(method), kOkabeIto[i], kMarkers[i], kLineStyles[i].name};
  }
  // Any other method: the colours, markers and lines no shipped method takes, each chosen by the sum of the name's
  // bytes (stable from run to run): 3 x 7 x 3 combinations, so two such methods are drawn alike once in 63
  // (requireDistinctStyles then asks for --style).
  const std::size_t first = kShipped.size();
  std::size_t h = std::accumulate(method.begin(), method.end(), std::size_t{0},
                                  [](std::size_t s, char c) { return s * 31 + static_cast<unsigned char>(c); });
  const std::size_t colour = first + h % (kOkabeIto.size() - first);
  h /= kOkabeIto.size() - first;
  const std::size_t marker = first + h % (kMarkers.size() - first);
  h /= kMarkers.size() - first;
  const std::size_t line = first + h % (kLineStyles.size() - first);
  return {displayNameOf(method), kOkabeIto[colour], kMarkers[marker], kLineStyles[line].name};
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

nlohmann::json methodStyles(const std::vector<std::string>& methods, const StyleOverrides& overrides,
                            const std::filesystem::path& style_file) {
  nlohmann::json styles = nlohmann::json::object();
  for (const std::string& m : methods) {
    const MethodStyle d = defaultStyle(m);
    nlohmann::json s = {{"name", d.name}, {"colour", d.colour}, {"marker", d.marker}, {"line", d.line}};
    if (const auto o = overrides.find(m); o != overrides.end()) s.update(o->second);
    s["dash"] = lineStyle(s["line"].get<std::string>()).dash;
    styles[m] = s;
  }
  requireDistinctStyles(styles, style_file);
  return styles;
}

std::vector<std::string> unknownStyledMethods(const StyleOverrides& overrides,
                                              const std::vector<std::string>& methods) {
  const auto registered = registeredMethods();
  std::vector<std::string> unknown;
  for (const auto& entry : overrides) {
    const std::string& method = entry.first;  // a name, not a structured binding: clang 14 cannot capture those
    const bool drawn = std::find(methods.begin(), methods.end(), method) != methods.end();
    const bool known = std::any_of(registered.begin(), registered.end(), [&](const auto& m) { return m->name() == method; });
    if (!drawn && !known) unknown.push_back(method);
  }
  return unknown;
}

}  // namespace occsweep::cli
