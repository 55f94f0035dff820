#include "occsweep/methods/builtin_methods.hpp"

#include <memory>
#include <mutex>

#include "occsweep/core/method_registry.hpp"
#include "occsweep/methods/knn/knn_method.hpp"
#include "occsweep/methods/octomap/octomap_method.hpp"
#include "occsweep/methods/outlier_filters/outlier_filter_methods.hpp"
#include "occsweep/methods/range_octomap/range_octomap_method.hpp"

namespace occsweep {

void registerBuiltinMethods() {
  static std::once_flag once;
  std::call_once(once, [] {
    registerMethod(std::make_shared<OctoMapMethod>());
    registerMethod(std::make_shared<KnnMethod>());
    registerMethod(std::make_shared<SorOctoMapMethod>());
    registerMethod(std::make_shared<RorOctoMapMethod>());
    registerMethod(std::make_shared<RangeOctoMapMethod>());
  });
}

}  // namespace occsweep
