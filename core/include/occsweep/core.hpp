// occsweep's header-only mapping core, all of it.
#pragma once

#include "core/knn_average_distance.hpp"
#include "core/knn_inverse_sensor_model.hpp"
#include "core/knn_set_distances.hpp"
#include "core/log_odds.hpp"
#include "core/map_voxels.hpp"
#include "core/mapping_params.hpp"
#include "core/normal_cdf.hpp"
#include "core/octomap_baseline.hpp"
#include "core/point_cloud_set.hpp"
#include "core/welford.hpp"
#include "core/splitmix64.hpp"
#include "core/scan_events.hpp"
#include "core/flat_key_index.hpp"
#include "core/ray_traversal.hpp"
