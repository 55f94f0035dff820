#include "occsweep/data/dataset_truth.hpp"

#include <string>

#include "occsweep/data/data_error.hpp"

namespace occsweep {

GroundTruth datasetGroundTruth(const Dataset& d, const std::filesystem::path& dir, double resolution) {
  try {
    return makeGroundTruth(d.truth, d.region, resolution);
  } catch (const std::invalid_argument& e) {
    std::string why = e.what();
    if (why.rfind("ground truth: ", 0) == 0) why.erase(0, 14);
    const auto& r = d.region;
    throw DataError(dir / "manifest.json", "region",
                    why + " (min " + std::to_string(r.min[0]) + " " + std::to_string(r.min[1]) + " " +
                        std::to_string(r.min[2]) + ", max " + std::to_string(r.max[0]) + " " +
                        std::to_string(r.max[1]) + " " + std::to_string(r.max[2]) + ", resolution " +
                        std::to_string(resolution) + "): widen the region (import truth --region) or use a finer "
                        "--resolution");
  }
}

}  // namespace occsweep
