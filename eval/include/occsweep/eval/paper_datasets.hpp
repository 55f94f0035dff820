// The paper's 20 data sets (Section 4.1): ENVIRONMENT-TEXTURE-LAYOUT, two environments (building facades, an open
// parking lot), two textures (plain, Voronoi) and five box layouts (the free tetrominoes I O T L S). One home for
// the names: the stereo generator, `reproduce` (whose Eq. 16 groups follow this order) and `cluster` read them here.
#pragma once

#include <array>
#include <string>
#include <vector>

namespace occsweep {

inline constexpr std::array<const char*, 2> kPaperEnvironments{"building", "parking"};
inline constexpr std::array<const char*, 2> kPaperTextures{"plain", "voronoi"};
inline constexpr std::array<const char*, 5> kPaperLayouts{"I", "O", "T", "L", "S"};

/// The 20 names in canonical order: environment, then texture, then layout; e.g. building-plain-I first.
[[nodiscard]] std::vector<std::string> paperDatasetNames();

// ---------------------------------------------------------------------------------------------------------------

inline std::vector<std::string> paperDatasetNames() {
  std::vector<std::string> names;
  for (const char* environment : kPaperEnvironments)
    for (const char* texture : kPaperTextures)
      for (const char* layout : kPaperLayouts) names.push_back(std::string(environment) + "-" + texture + "-" + layout);
  return names;
}

}  // namespace occsweep
