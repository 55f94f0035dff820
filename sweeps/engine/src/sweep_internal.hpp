// Helpers of runSweep (sweep_run.cpp, sweep_partial.cpp); not part of the public API.
#pragma once

#include <filesystem>
#include <map>
#include <string>

#include "occsweep/sweeps/results.hpp"

namespace occsweep::sweep_detail {

/// Finished maps of an interrupted run: OUT.partial.jsonl, a header line then one map per line. A line cut by a
/// kill is ignored (its map is simply done again). With `twin` (the observable-truth results of the same maps,
/// SweepConfig::observable_out), only lines carrying the twin's counts count, which go into `*twin`.
[[nodiscard]] std::map<std::uint64_t, MapResult> loadPartial(const std::filesystem::path& partial,
                                                             const ResultsHeader& header, bool force,
                                                             std::map<std::uint64_t, std::string>& engine_of,
                                                             std::map<std::uint64_t, MapResult>* twin);

/// A partial-log line's field holding the twin's thresholds and AUC.
inline constexpr const char* kTwinField = "observable";

/// True when `file` holds complete results of the same work as `header` (the twin of a finished sweep); false
/// when it is missing or other work. Throws for a file that is not occsweep's results (never replaced).
[[nodiscard]] bool completeResultsOf(const std::filesystem::path& file, const ResultsHeader& header);

}  // namespace occsweep::sweep_detail
