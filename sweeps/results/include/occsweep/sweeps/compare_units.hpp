// The independent units of compare's tests (docs/statistics.md, "Verdicts"): data sets that share a recording or a
// scene, found from the provenance their manifests record, or the units a user declares.
#pragma once

#include <string>
#include <vector>

#include "occsweep/sweeps/compare.hpp"

namespace occsweep {

enum class UnitRule {
  Provenance,  ///< the default: data sets sharing a recorded input, the truth (with the poses or in one region),
               ///< or a generated scene
  Names,       ///< `compare --units names`: each data set name is a unit (DATASET/pcs-NNNN share DATASET)
};

/// The data set a set's name belongs to: generated sets are named DATASET/pcs-NNNN and share DATASET; any other
/// name is the data set.
[[nodiscard]] std::string datasetOf(const std::string& name);

struct SampleUnits {
  std::vector<std::string> of_row;  ///< each row's unit, labelled by its data sets' names
  std::string noun = "data sets";   ///< "scenes" where provenance grouped the data sets
  std::string declaration;          ///< how the units were found: every verdict names it
  /// Data sets whose unit their name decided under UnitRule::Provenance: made by an older occsweep, they record no
  /// provenance.
  std::vector<std::string> without_provenance;
};

/// The rows' units: under UnitRule::Provenance the connected groups of rows that share a recorded input file, the
/// points read, the truth, or a generated scene (docs/dataset-format.md, "Provenance"), a row without provenance by
/// its name; under UnitRule::Names by name.
[[nodiscard]] SampleUnits sampleUnits(const std::vector<ComparisonRow>& rows, UnitRule rule);

/// "20 data sets over 10 scenes", or "8 data sets" where the units are the data sets, then the declaration: the
/// sample a verdict rests on.
[[nodiscard]] std::string sampleText(const SampleUnits& units, std::size_t datasets, std::size_t scenes);

}  // namespace occsweep
