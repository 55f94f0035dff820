// Reads an occsweep data set, builds one k-NN map with the paper's defaults (Table 1) and counts TP, FP, FN and
// TN against the data set's ground truth at p_t = 0.5: the smallest program that uses occsweep as a library.
#include <cstdio>
#include <exception>

#include "occsweep/methods/knn/knn_inverse_sensor_model.hpp"
#include "occsweep/eval/confusion.hpp"
#include "occsweep/eval/dataset.hpp"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s DATASET_DIR\n", argv[0]);
    return 2;
  }
  try {
    const occsweep::Dataset data = occsweep::readDataset(argv[1]);
        // The paper's defaults: k = 3, ... (knn_parameters.hpp), 0.1 m voxels and s_c 4 m (map_settings.hpp).
    occsweep::KnnParams params;
    occsweep::validate(params);  // throws naming the broken relation of Eq. 12
    const auto map = occsweep::KnnInverseSensorModel(params).buildMap(data.scans);
    const occsweep::GroundTruth truth = occsweep::groundTruthOf(data, argv[1], params.map.resolution);
    const occsweep::ConfusionCounts c = occsweep::classify(occsweep::sampleRegion(*map, truth), params.p_t);
    std::printf("%s: %zu scans, k-NN map of %zu voxels; at p_t %.2f: TP %llu FP %llu FN %llu TN %llu (TPR %.4f)\n",
                data.name.c_str(), data.scans.size(), map->size(), params.p_t, (unsigned long long)c.tp,
                (unsigned long long)c.fp, (unsigned long long)c.fn, (unsigned long long)c.tn, c.tpr());
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: %s\n", argv[1], e.what());
    return 2;
  }
}
