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

/// The markers and line styles a style may name: each is drawn distinct from the others in print.
inline const std::vector<std::string> kMarkers = {"o", "s", "^", "D", "v", "P", "X", "*", "<", ">", "p", "h"};
inline const std::vector<std::string> kLineStyles = {"solid",          "dashed",        "dashdot",        "dotted",
                                                     "densely dashed", "dashdotdotted", "densely dotted", "long dashed"};

/// The default style: Okabe and Ito's palette, which readers with the common colour-vision deficiencies tell apart.
/// The shipped methods keep theirs; any other method takes one by its name, so it too keeps it in every figure.
[[nodiscard]] MethodStyle defaultStyle(const std::string& method);

/// A style file (docs/statistics.md, "Figures"): {"methods": {"knn": {"name": ..., "colour": ..., "marker": ...,
/// "line": ...}}}, each field optional. DataError naming the file, the field and the rule on anything else.
using StyleOverrides = std::map<std::string, nlohmann::json>;
[[nodiscard]] StyleOverrides readStyleFile(const std::filesystem::path& file);

/// The style of each of `methods`: the default, with the style file's fields over it.
[[nodiscard]] nlohmann::json methodStyles(const std::vector<std::string>& methods, const StyleOverrides& overrides);

}  // namespace occsweep::cli
