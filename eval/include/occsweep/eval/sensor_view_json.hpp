// A scan's sensor view as manifest.json holds it (docs/dataset-format.md, "Sensor views"): the optional per-scan
// field `view`, {"model": "pinhole" | "cone" | "sphere", ...}.
#pragma once

#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "occsweep/core/sensor_view.hpp"

namespace occsweep {

/// The `view` object of a scan.
[[nodiscard]] nlohmann::json sensorViewJson(const SensorView& view);

/// The view a `view` object describes. Throws DataError naming `file` and the field (`where` + ".fx", ...) for a
/// missing or mistyped field, an unknown model, or a value breaking brokenViewRule's rules (a negative fx, a
/// half-angle outside (0, 180], a rotation that is not one).
[[nodiscard]] SensorView sensorViewFromJson(const nlohmann::json& view, const std::filesystem::path& file,
                                            const std::string& where);

}  // namespace occsweep
