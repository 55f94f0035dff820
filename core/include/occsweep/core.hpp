// occsweep's header-only mapping core, all of it: the contract every method implements and what every map
// shares (the methods occsweep ships are in methods/).
#pragma once

#include "core/flat_key_index.hpp"
#include "core/log_odds.hpp"
#include "core/map_settings.hpp"
#include "core/map_voxels.hpp"
#include "core/mapping_method.hpp"
#include "core/method_parameter.hpp"
#include "core/method_registry.hpp"
#include "core/occupancy_tree.hpp"
#include "core/point_cloud_set.hpp"
#include "core/point_feature.hpp"
#include "core/ray_traversal.hpp"
#include "core/scan_events.hpp"
#include "core/splitmix64.hpp"
#include "core/welford.hpp"
