#include "occsweep/eval/truth_offset.hpp"

#include <algorithm>
#include <cstdlib>

#include <octomap/OcTree.h>

namespace occsweep {
namespace {

using Offset = std::array<int, 3>;
constexpr int kSide = 2 * kOffsetSearchVoxels + 1;

// The key `k` moved by `d`, false when that leaves OctoMap's key range.
bool moved(const octomap::OcTreeKey& k, const Offset& d, octomap::OcTreeKey& out) {
  for (int a = 0; a < 3; ++a) {
    const int v = k[a] + d[a];
    if (v < 0 || v > 65535) return false;
    out[a] = octomap::key_type(v);
  }
  return true;
}

bool onSurface(const TruthMask& mask, const octomap::OcTreeKey& k) {
  if (!mask.has(k)) return false;
  for (int a = 0; a < 3; ++a)
    for (int step : {-1, 1}) {
      Offset d{0, 0, 0};
      d[a] = step;
      octomap::OcTreeKey n;
      if (!moved(k, d, n) || !mask.has(n)) return true;
    }
  return false;
}

// Some surface voxel within a voxel (the 27 keys around) of `k` moved by `d`.
bool nearSurface(const TruthMask& mask, const octomap::OcTreeKey& k, const Offset& d) {
  for (int x = -1; x <= 1; ++x)
    for (int y = -1; y <= 1; ++y)
      for (int z = -1; z <= 1; ++z) {
        octomap::OcTreeKey n;
        if (moved(k, {d[0] + x, d[1] + y, d[2] + z}, n) && onSurface(mask, n)) return true;
      }
  return false;
}

double shareNearSurface(const TruthMask& mask, const std::vector<octomap::OcTreeKey>& keys, const Offset& d) {
  const auto near = std::count_if(keys.begin(), keys.end(), [&](const auto& k) { return nearSurface(mask, k, d); });
  return double(near) / double(keys.size());
}

std::size_t cell(const Offset& d) {
  return (std::size_t(d[0] + kOffsetSearchVoxels) * kSide + std::size_t(d[1] + kOffsetSearchVoxels)) * kSide +
         std::size_t(d[2] + kOffsetSearchVoxels);
}

// votes[cell(d)]: of the voting points, those with a surface voxel at their key moved by d.
std::vector<unsigned> offsetVotes(const TruthMask& mask, const std::vector<octomap::OcTreeKey>& keys) {
  std::vector<unsigned> votes(std::size_t(kSide) * kSide * kSide, 0);
  for (std::size_t i : evenlySpaced(keys.size(), kOffsetVotingPoints))
    for (int x = -kOffsetSearchVoxels; x <= kOffsetSearchVoxels; ++x)
      for (int y = -kOffsetSearchVoxels; y <= kOffsetSearchVoxels; ++y)
        for (int z = -kOffsetSearchVoxels; z <= kOffsetSearchVoxels; ++z) {
          octomap::OcTreeKey n;
          if (moved(keys[i], {x, y, z}, n) && onSurface(mask, n)) ++votes[cell({x, y, z})];
        }
  return votes;
}

// The offset farther than kOffsetNearVoxels whose 27 cells hold the most votes (a point within a voxel of the
// surface votes for one of them); the first in x, y, z order on a tie.
Offset mostVoted(const std::vector<unsigned>& votes) {
  Offset best{0, 0, 0};
  unsigned most = 0;
  const int reach = kOffsetSearchVoxels - 1;
  for (int x = -reach; x <= reach; ++x)
    for (int y = -reach; y <= reach; ++y)
      for (int z = -reach; z <= reach; ++z) {
        if (std::max({std::abs(x), std::abs(y), std::abs(z)}) <= kOffsetNearVoxels) continue;
        unsigned sum = 0;
        for (int i = -1; i <= 1; ++i)
          for (int j = -1; j <= 1; ++j)
            for (int k = -1; k <= 1; ++k) sum += votes[cell({x + i, y + j, z + k})];
        if (sum > most) most = sum, best = {x, y, z};
      }
  return best;
}

}  // namespace

OffsetFit bestOffset(const TruthMask& mask, double resolution, const std::vector<octomap::point3d>& points) {
  const octomap::OcTree grid(resolution);
  std::vector<octomap::OcTreeKey> keys;
  for (const auto& p : points) keys.push_back(grid.coordToKey(p));
  const Offset best = mostVoted(offsetVotes(mask, keys));
  OffsetFit fit;
  fit.share_on_surface = shareNearSurface(mask, keys, {0, 0, 0});
  fit.offset_share_on_surface = shareNearSurface(mask, keys, best);
  for (int a = 0; a < 3; ++a) fit.offset[std::size_t(a)] = best[std::size_t(a)] * resolution;
  return fit;
}

}  // namespace occsweep
