// How a method is shown to a reader: its display name, in tables and figures, and in every figure one colour,
// marker and line style (docs/statistics.md, "Figures"). A style file overrides any of them per method.
#pragma once

#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace occsweep::cli {

/// A method's name as a paper shows it (MappingMethod::displayName); a method this program has not registered keeps
/// its registered name.
[[nodiscard]] std::string displayNameOf(const std::string& method);

struct MethodStyle {
  std::string name;    ///< display name
  std::string colour;  ///< "#RRGGBB"
  std::string marker;  ///< one of kMarkers (matplotlib's marker codes)
  std::string line;    ///< one of kLineStyles
};

/// The markers a style may name: each is drawn distinct from the others in print.
inline const std::vector<std::string> kMarkers = {"o", "s", "^", "D", "v", "P", "X", "*", "<", ">", "p", "h"};

/// The line styles a style may name, each with its dash pattern (on, off, ... in line widths; empty: solid), which
/// the figure's JSON carries to the drawing script.
struct LineStyle {
  std::string name;
  std::vector<double> dash;
};
inline const std::vector<LineStyle> kLineStyles = {
    {"solid", {}},          {"dashed", {3.7, 1.6}},          {"dashdot", {6.4, 1.6, 1, 1.6}}, {"dotted", {1, 1.65}},
    {"densely dashed", {5, 1}}, {"dashdotdotted", {3, 1, 1, 1, 1, 1}}, {"densely dotted", {1, 1}},
    {"long dashed", {8, 2}}};

/// The default style: Okabe and Ito's palette, which readers with the common colour-vision deficiencies tell apart.
/// The shipped methods keep theirs; any other method takes one by its name, so it too keeps it in every figure.
[[nodiscard]] MethodStyle defaultStyle(const std::string& method);

/// A style file (docs/statistics.md, "Figures"): {"methods": {"knn": {"name": ..., "colour": ..., "marker": ...,
/// "line": ...}}}, each field optional. DataError naming the file, the field and the rule on anything else.
using StyleOverrides = std::map<std::string, nlohmann::json>;
[[nodiscard]] StyleOverrides readStyleFile(const std::filesystem::path& file);

/// The style of each of `methods`, as the drawing script reads it (name, colour, marker, line and its dash): the
/// default, with the style file's fields over it. Two of them with one display name, or one colour, marker and line,
/// would read as one method: DataError naming both (and `style_file`).
[[nodiscard]] nlohmann::json methodStyles(const std::vector<std::string>& methods, const StyleOverrides& overrides,
                                          const std::filesystem::path& style_file);

/// The style file's methods that are neither registered nor among `methods` (the figure's): a misspelt name, whose
/// style would silently not apply. A method the figure does not draw but that is registered is not one: one style
/// file serves every figure.
[[nodiscard]] std::vector<std::string> unknownStyledMethods(const StyleOverrides& overrides,
                                                            const std::vector<std::string>& methods);

}  // namespace occsweep::cli
