// Parameters of both mappers as plain structs with documented defaults, checked against Eq. 12.
#pragma once

#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>

#include "enum_names.hpp"

namespace occsweep {

/// Parameters of the OctoMap baseline (Eq. 4-5). Defaults are liboctomap's own (OcTree constructor),
/// with OctoMap's clamping thresholds rounded to the paper's two decimals.
struct OctoMapParams {
  double p_h = 0.7;          ///< probability of a hit (setProbHit)
  double p_m = 0.4;          ///< probability of a miss (setProbMiss)
  double p_max = 0.97;       ///< upper clamping threshold (setClampingThresMax)
  double p_min = 0.12;       ///< lower clamping threshold (setClampingThresMin)
  double p_t = 0.5;          ///< occupancy threshold: occupied when l >= l(p_t)
  double resolution = 0.1;   ///< voxel edge in metres (paper Section 4.2)
  double s_c = 4.0;          ///< maximum range in metres: longer rays are cut and only free space
};

/// Algorithm 1 word for word (Literal) or with OctoMap's "occupied wins" (Default); see voxel_update_rule.hpp.
enum class UpdateVariant { Default, Literal };

/// Where mu and sigma of Eq. 8 come from: the whole point cloud set in a first pass (Batch, the paper's),
/// or the running Welford values after the current scan (Online, for a robot mapping as it goes).
enum class StatsMode { Batch, Online };

/// The names of both enums in results files (map.variant, map.stats: docs/results-format.md), in the .ot.json of
/// `occsweep map` and on the command line (--variant, --stats; .list() for CLI11's IsMember).
inline constexpr EnumNames<UpdateVariant, 2> kUpdateVariantNames{
    "variant", {{{UpdateVariant::Default, "default"}, {UpdateVariant::Literal, "literal"}}}};
inline constexpr EnumNames<StatsMode, 2> kStatsModeNames{
    "stats", {{{StatsMode::Batch, "batch"}, {StatsMode::Online, "online"}}}};

/// "default" or "literal".
[[nodiscard]] inline const char* toText(UpdateVariant variant) { return kUpdateVariantNames.text(variant); }
/// "batch" or "online".
[[nodiscard]] inline const char* toText(StatsMode stats) { return kStatsModeNames.text(stats); }

/// The variant of that name; throws std::invalid_argument naming it and the accepted names.
[[nodiscard]] inline UpdateVariant parseUpdateVariant(std::string_view name) { return kUpdateVariantNames.parse(name); }
/// The statistics mode of that name; throws std::invalid_argument naming it and the accepted names.
[[nodiscard]] inline StatsMode parseStatsMode(std::string_view name) { return kStatsModeNames.parse(name); }

/// Parameters of the k-NN inverse sensor model (Eq. 6-10, Algorithm 1).
struct KnnParams {
  double p_u = 0.86;         ///< upper bound of p(s) (Eq. 6): a point with tight neighbours
  double p_l = 0.26;         ///< lower bound of p(s) (Eq. 6): an isolated point
  double p_m = 0.4;          ///< miss for voxels crossed by rays to in-range points (l_in)
  double p_m_out = 0.45;     ///< p'_m: miss for voxels crossed only by rays to points beyond s_c (l_out)
  double p_max = 0.97;       ///< upper clamping threshold
  double p_min = 0.12;       ///< lower clamping threshold
  double p_t = 0.5;          ///< occupancy threshold
  int k = 3;                 ///< number of nearest neighbours averaged (Section 3.1)
  double resolution = 0.1;   ///< voxel edge in metres
  double s_c = 4.0;          ///< maximum range in metres: splits z_in from z_out
  UpdateVariant variant = UpdateVariant::Default;
  StatsMode stats = StatsMode::Batch;
};

/// The first relation of Eq. 12 (or a range rule of ours) that the parameters break, as a sentence; none if valid.
[[nodiscard]] std::optional<std::string> brokenRelation(const OctoMapParams& p);
[[nodiscard]] std::optional<std::string> brokenRelation(const KnnParams& p);

/// Throws std::invalid_argument naming the broken relation.
template <class Params>
void validate(const Params& p) {
  if (auto why = brokenRelation(p)) throw std::invalid_argument(*why);
}

// ---------------------------------------------------------------------------------------------------------
namespace detail {

inline std::string fmt(double v) {
  std::string s = std::to_string(v);
  while (s.size() > 1 && s.back() == '0') s.pop_back();
  if (!s.empty() && s.back() == '.') s.pop_back();
  return s;
}

// One relation a OP b; a message when it fails.
inline std::optional<std::string> need(bool holds, const std::string& relation, const std::string& values) {
  if (holds) return std::nullopt;
  return "parameters break Eq. 12: " + relation + " does not hold (" + values + ")";
}

inline std::optional<std::string> commonRelations(double p_max, double p_min, double p_t, double resolution,
                                                  double s_c) {
  using detail::fmt;
  if (auto e = need(1.0 > p_max, "1 > p_max", "p_max = " + fmt(p_max))) return e;
  if (auto e = need(p_max >= 0.5, "p_max >= 0.5", "p_max = " + fmt(p_max))) return e;
  if (auto e = need(p_min > 0.0, "p_min > 0", "p_min = " + fmt(p_min))) return e;
  if (auto e = need(p_max >= p_t, "p_max >= p_t", "p_max = " + fmt(p_max) + ", p_t = " + fmt(p_t))) return e;
  if (auto e = need(p_t >= p_min, "p_t >= p_min", "p_t = " + fmt(p_t) + ", p_min = " + fmt(p_min))) return e;
  if (!(resolution > 0.0)) return "resolution must be > 0 (resolution = " + fmt(resolution) + ")";
  if (!(s_c > 0.0)) return "s_c must be > 0 (s_c = " + fmt(s_c) + ")";
  return std::nullopt;
}

}  // namespace detail

inline std::optional<std::string> brokenRelation(const OctoMapParams& p) {
  using detail::fmt;
  using detail::need;
  if (auto e = detail::commonRelations(p.p_max, p.p_min, p.p_t, p.resolution, p.s_c)) return e;
  if (auto e = need(0.5 > p.p_m, "0.5 > p_m", "p_m = " + fmt(p.p_m))) return e;
  if (auto e = need(p.p_m >= p.p_min, "p_m >= p_min", "p_m = " + fmt(p.p_m) + ", p_min = " + fmt(p.p_min)))
    return e;
  if (auto e = need(p.p_max >= p.p_h, "p_max >= p_h", "p_max = " + fmt(p.p_max) + ", p_h = " + fmt(p.p_h)))
    return e;
  if (auto e = need(p.p_h >= 0.5, "p_h >= 0.5", "p_h = " + fmt(p.p_h))) return e;
  return std::nullopt;
}

inline std::optional<std::string> brokenRelation(const KnnParams& p) {
  using detail::fmt;
  using detail::need;
  if (auto e = detail::commonRelations(p.p_max, p.p_min, p.p_t, p.resolution, p.s_c)) return e;
  if (auto e = need(0.5 > p.p_m_out, "0.5 > p'_m", "p'_m = " + fmt(p.p_m_out))) return e;
  if (auto e = need(p.p_m_out >= p.p_m, "p'_m >= p_m", "p'_m = " + fmt(p.p_m_out) + ", p_m = " + fmt(p.p_m)))
    return e;
  if (auto e = need(p.p_m >= p.p_min, "p_m >= p_min", "p_m = " + fmt(p.p_m) + ", p_min = " + fmt(p.p_min)))
    return e;
  if (auto e = need(p.p_u >= p.p_l, "p_u >= p_l", "p_u = " + fmt(p.p_u) + ", p_l = " + fmt(p.p_l))) return e;
  // Ours, not Eq. 12: l(p(s)) must be finite, so p(s) stays inside (0, 1).
  if (!(p.p_l > 0.0 && p.p_u < 1.0))
    return "p_u and p_l must lie in (0, 1) so that l(p(s)) is finite (p_u = " + fmt(p.p_u) +
           ", p_l = " + fmt(p.p_l) + ")";
  if (p.k < 1) return "k must be >= 1 (k = " + std::to_string(p.k) + ")";
  return std::nullopt;
}

}  // namespace occsweep
