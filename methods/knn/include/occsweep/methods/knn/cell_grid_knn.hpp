// An exact k-nearest-neighbour search over a uniform grid of cubic cells, for the dense clouds of a range scan
// (docs/performance.md, "The k-NN search over a grid of cells"): cells a few k-th neighbour distances wide in a
// hash table; a query reads its own cell, then the cells around it nearer than its k-th nearest so far, ring by
// ring, and stops as soon as no unread cell can hold a nearer point. For k = 1 the nearest is kept as a minimum.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <type_traits>
#include <vector>

#include <octomap/octomap_types.h>

namespace occsweep {

/// Squared Euclidean distance in double from float coordinates; (dx^2 + dy^2) + dz^2, in this order, is the
/// one formula every k-NN search here ranks and sums by (so their results can be equal bit for bit).
[[nodiscard]] double squaredDistance(const octomap::point3d& a, const octomap::point3d& b);

/// Exact k-NN over one cloud: the points sorted into a hash table of cells. The points are kept by
/// reference and must outlive the search.
class CellGridKnn {
 public:
  /// Indexes `points` with cells sized for about k neighbours (any k >= 1 can be asked later; only speed
  /// depends on this one).
  CellGridKnn(const std::vector<octomap::point3d>& points, int k);

  /// The squared distances from point i to its min(k, n - 1) nearest *other* points (itself excluded by
  /// index, so a duplicate counts at 0), ascending, into `out` (resized; reused across calls, no allocation).
  /// Exact: which of several equally distant points is taken is unspecified, but the distances are equal,
  /// so `out` is the same sequence of values as sorting all n - 1 squared distances and keeping the first k.
  void nearestOtherSquaredDistances(std::size_t i, int k, std::vector<double>& out) const;

  /// The same for every point, cell by cell: visit(i, ascending squared distances) once per point i. The
  /// points of one cell share one read of the 27 cells around it, which holds most of their neighbours.
  template <class Visit>
  void forEachPointNearestOthers(int k, Visit&& visit) const;

  [[nodiscard]] double cellSize() const { return cell_; }

 private:
  struct Cell {
    std::uint32_t start = 0;  ///< first point of the cell in sorted_
    std::uint32_t count = 0;
  };
  /// The points cell by cell, one array per coordinate, in double (each float converted once, exactly, instead of
  /// in every distance): the distance loops read two points a step.
  struct SortedPoints {
    std::vector<double> x, y, z;
    std::vector<std::uint32_t> index;  ///< into points_
  };
  /// A query: one sorted point, or any point of points_.
  struct Query {
    double x, y, z;  ///< a point's float coordinates
    std::uint32_t index;  ///< into points_
  };
  struct CellCoords {
    std::int64_t c[3];
  };
  /// A non-empty cell among the 26 around a query's: where it lies per axis (0 below the query's cell, 1 level
  /// with it, 2 above) and its points [start, end) in sorted_.
  struct NeighbourCell {
    std::uint8_t side[3];
    std::uint32_t start, end;
  };
  /// Per axis, the squared distance from a query to the cells below, level with and above its own, each face's
  /// distance made smaller by the margin (+inf beyond the grid's edge, where no cell is). A neighbour cell's gap
  /// is the sum over its axes: a lower bound on the squared distance to any point in it.
  struct FaceGaps {
    double gap2[3][3];
    double nearest;  ///< the smallest: no point outside the query's cell is nearer
    [[nodiscard]] double of(const NeighbourCell& b) const {
      return gap2[0][b.side[0]] + gap2[1][b.side[1]] + gap2[2][b.side[2]];
    }
  };
  static constexpr std::uint64_t kEmpty = ~std::uint64_t(0);
  static constexpr int kAxisBits = 21;  ///< cells per axis at most 2^21: three fit in one 64-bit key
  static constexpr std::int64_t kMaxCellsPerAxis = std::int64_t(1) << kAxisBits;

  [[nodiscard]] double sampledKthNeighbourDistance(int k) const;
  void chooseCellSize(int k);
  [[nodiscard]] CellCoords cellOf(double x, double y, double z) const;
  [[nodiscard]] static std::uint64_t keyOf(const CellCoords& c);
  [[nodiscard]] std::size_t slotOf(std::uint64_t key) const;  ///< the key's slot, or the free slot it would take
  void sortIntoCells();
  /// The distance from q to the nearest face of the block of cells within `ring` of its cell, made smaller by
  /// a margin far above the rounding of cellOf and of the squared distances: no unread point is nearer.
  [[nodiscard]] double unreadLowerBound(const Query& q, const CellCoords& c, std::int64_t ring) const;
  [[nodiscard]] bool blockCoversGrid(const CellCoords& c, std::int64_t ring) const;
  [[nodiscard]] const Cell* find(const CellCoords& c) const;  ///< nullptr: an empty cell
  /// The non-empty cells among the 26 around c, into `out`.
  void neighboursOf(const CellCoords& c, std::vector<NeighbourCell>& out) const;
  [[nodiscard]] FaceGaps faceGaps(const Query& q, const CellCoords& c, double margin) const;
  /// Whether `nearest` (for q, from every cell within `ring` of c) already holds q's nearest points.
  template <class Nearest>
  [[nodiscard]] bool certain(const Query& q, const CellCoords& c, std::int64_t ring, const Nearest& nearest) const;
  /// Reads the cells at Chebyshev distance first_ring, first_ring + 1, ... from q's cell c until certain.
  template <class Nearest>
  void searchRings(const Query& q, const CellCoords& c, std::int64_t first_ring, Nearest& nearest) const;
  /// Offers the squared distances from q to the sorted points [begin, end) (q itself excluded by index).
  template <class Nearest>
  void offerCell(const Query& q, std::uint32_t begin, std::uint32_t end, Nearest& nearest) const;
  /// forEachPointNearestOthers for k = 1: a minimum instead of a list.
  template <class Visit>
  void forEachPointNearestOther(Visit&& visit) const;
  /// The smallest squared distance from q to the sorted points [begin, end), +inf for none.
  [[nodiscard]] double nearestIn(const Query& q, std::uint32_t begin, std::uint32_t end) const;
  /// Per sorted point j of [begin, end), the smallest squared distance to another point of the range, into
  /// nearest[j - begin] (+inf for none): each pair's distance computed once and taken by both points.
  void nearestWithin(std::uint32_t begin, std::uint32_t end, std::vector<double>& nearest) const;
  /// Cell number `id`: its points [begin, end) in sorted_, and its coordinates.
  struct NumberedCell {
    std::uint32_t begin, end;
    CellCoords c;
  };
  [[nodiscard]] NumberedCell numberedCell(std::uint32_t id) const {
    const std::uint32_t begin = cells_[id].start;
    const Query first = query(begin);
    return {begin, begin + cells_[id].count, cellOf(first.x, first.y, first.z)};
  }
  /// The number of the cell with this key, a new one (cells_.size()) if it has none yet.
  std::uint32_t numberOf(std::uint64_t key);
  void growTable();
  /// What a cell's gap is made smaller by: far above the rounding of cellOf and of the squared distances.
  [[nodiscard]] double gapMargin() const { return 1e-9 * (span_ + cell_); }
  [[nodiscard]] Query query(std::uint32_t j) const {
    return {sorted_.x[j], sorted_.y[j], sorted_.z[j], sorted_.index[j]};
  }
  [[nodiscard]] std::size_t nearestCount(int k) const {
    return std::min<std::size_t>(std::size_t(std::max(k, 0)), points_.empty() ? 0 : points_.size() - 1);
  }

  const std::vector<octomap::point3d>& points_;
  double origin_[3] = {0, 0, 0};
  std::int64_t last_cell_[3] = {0, 0, 0};  ///< the largest cell coordinate per axis
  double cell_ = 1.0, inverse_cell_ = 1.0, span_ = 0.0;
  // The non-empty cells, numbered in the order of their first point (for a range scan's points, in image order,
  // the next cell is a neighbour of the last: the 27 around it are mostly in cache already), and their points in
  // sorted_ in that order. A hash table, open addressing with linear probing, power-of-two size, at most an
  // eighth full, maps a cell's key to its number: sized by the cells, not the points (a cell holds about ten), it
  // stays in cache; the keys apart from the numbers, so that probing (mostly for empty cells) reads 8 bytes a slot.
  std::vector<Cell> cells_;             ///< by number
  std::vector<std::uint64_t> keys_;     ///< kEmpty for a free slot
  std::vector<std::uint32_t> numbers_;  ///< same slots
  std::uint64_t mask_ = 0;
  int shift_ = 64;  ///< 64 - log2(table size)
  SortedPoints sorted_;
};

// ---------------------------------------------------------------------------------------------------------
namespace detail {

/// Two doubles in one SSE register: the distance loops take two points a step.
using Double2 = double __attribute__((vector_size(16)));
/// The two doubles at `from` (any alignment).
inline Double2 loadTwo(const double* from) {
  Double2 d;
  std::memcpy(&d, from, sizeof d);
  return d;
}

/// The smallest squared distance offered so far (k = 1): NearestSoFar's interface, kept in a register.
struct NearestOne {
  double d2 = std::numeric_limits<double>::infinity();
  [[nodiscard]] bool full() const { return d2 < std::numeric_limits<double>::infinity(); }
  [[nodiscard]] double worst() const { return d2; }
  void clear() { d2 = std::numeric_limits<double>::infinity(); }
  void offer(double d) { d2 = std::min(d2, d); }
};

/// The k smallest squared distances offered so far. Up to kSortedUpTo of them in an array kept sorted: an offer
/// shifts the larger ones, fastest for the grids' small k. More are gathered unsorted and cut back to the k smallest
/// (nth_element) whenever twice k have come: O(1) an offer, where the sorted array's O(k) made a k near the cloud's
/// size cubic in it (docs/methods.md, "Neighbour searches"). worst() is then the k-th smallest at the last cut, at
/// or above the k-th so far: a search that prunes by it is still exact (it may read a little more), and fewer than
/// 2k points lie below it once every point has been offered.
template <class Distance>
class NearestSoFar {
 public:
  static constexpr std::size_t kSortedUpTo = 128;
  NearestSoFar(std::vector<Distance>& d2, std::size_t capacity)
      : d2_(d2), capacity_(capacity), gathered_(capacity > kSortedUpTo) {
    clear();
  }
  [[nodiscard]] bool full() const { return gathered_ ? cut_ < kNone : d2_.size() == capacity_; }
  [[nodiscard]] Distance worst() const { return gathered_ ? cut_ : full() ? d2_.back() : kNone; }
  void clear() { d2_.clear(), cut_ = kNone; }
  void offer(Distance d2) {
    if (full() && !(d2 < worst())) return;
    if (gathered_) return gather(d2);
    if (!full()) d2_.push_back(d2);  // room for one more; capacity_ is reached once and kept
    std::size_t at = d2_.size() - 1;  // the last place is free (new) or the worst (dropped)
    for (; at > 0 && d2_[at - 1] > d2; --at) d2_[at] = d2_[at - 1];
    d2_[at] = d2;
  }
  /// The k smallest ascending, in the vector given (after the last offer).
  void sortAscending() {
    if (!gathered_) return;
    if (d2_.size() > capacity_) cutToCapacity();
    std::sort(d2_.begin(), d2_.end());
  }

 private:
  static constexpr Distance kNone = std::numeric_limits<Distance>::infinity();
  void gather(Distance d2) {
    d2_.push_back(d2);
    if (d2_.size() == (full() ? 2 * capacity_ : capacity_)) cutToCapacity();
  }
  void cutToCapacity() {
    std::nth_element(d2_.begin(), d2_.begin() + std::ptrdiff_t(capacity_ - 1), d2_.end());
    d2_.resize(capacity_);
    cut_ = d2_.back();  // the k-th smallest: those before it are no larger
  }

  std::vector<Distance>& d2_;
  std::size_t capacity_;
  bool gathered_;
  Distance cut_ = kNone;
};

}  // namespace detail

inline double squaredDistance(const octomap::point3d& a, const octomap::point3d& b) {
  const double dx = double(a.x()) - double(b.x());
  const double dy = double(a.y()) - double(b.y());
  const double dz = double(a.z()) - double(b.z());
  return dx * dx + dy * dy + dz * dz;
}

inline CellGridKnn::CellGridKnn(const std::vector<octomap::point3d>& points, int k) : points_(points) {
  if (points_.empty()) return;
  chooseCellSize(std::max(k, 1));
  sortIntoCells();
}

// About the k-th neighbour distance at the median of 8 points spread over the cloud, by brute force in float
// (8 n distances in a loop the compiler vectorises; only the cells' size depends on it, so its rounding cannot
// change a result): the cells then hold a few points each and the 27 around a query usually hold its k neighbours.
inline double CellGridKnn::sampledKthNeighbourDistance(int k) const {
  const std::size_t n = points_.size();
  const std::size_t samples = std::min<std::size_t>(n, 8);
  const std::size_t kk = std::min<std::size_t>(std::size_t(k), n - 1);
  if (kk == 0) return 0.0;
  constexpr std::size_t kChunk = 64;
  std::vector<double> kth, nearest_d2;
  float d2[kChunk];
  for (std::size_t s = 0; s < samples; ++s) {
    const std::size_t i = (2 * s + 1) * n / (2 * samples);
    const float qx = points_[i].x(), qy = points_[i].y(), qz = points_[i].z();
    detail::NearestSoFar nearest(nearest_d2, kk);
    for (std::size_t chunk = 0; chunk < n; chunk += kChunk) {
      const std::size_t m = std::min(kChunk, n - chunk);
      float chunk_nearest = std::numeric_limits<float>::infinity();
      for (std::size_t j = 0; j < m; ++j) {
        const auto& p = points_[chunk + j];
        const float dx = qx - p.x(), dy = qy - p.y(), dz = qz - p.z();
        d2[j] = dx * dx + dy * dy + dz * dz;
        chunk_nearest = std::min(chunk_nearest, chunk + j == i ? std::numeric_limits<float>::infinity() : d2[j]);
      }
      if (!(chunk_nearest < nearest.worst())) continue;  // most chunks: nothing to offer
      for (std::size_t j = 0; j < m; ++j)
        if (d2[j] < nearest.worst() && chunk + j != i) nearest.offer(d2[j]);
    }
    kth.push_back(nearest.worst());
  }
  std::nth_element(kth.begin(), kth.begin() + long(kth.size() / 2), kth.end());
  return std::sqrt(kth[kth.size() / 2]);
}

inline void CellGridKnn::chooseCellSize(int k) {
  double lo[3], hi[3];
  for (int a = 0; a < 3; ++a) lo[a] = hi[a] = double(points_[0](a));
  for (const auto& p : points_)
    for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], double(p(a))), hi[a] = std::max(hi[a], double(p(a)));
  span_ = 0.0;
  for (int a = 0; a < 3; ++a) origin_[a] = lo[a], span_ = std::max(span_, hi[a] - lo[a]);
  // Cells 5 / sqrt(k) (at least 2) k-th neighbour distances wide, about 8 + k points a cell on a surface (the
  // fastest of 1.5 to 8 on the dense built-in scene for k = 1, 5, 10; docs/performance.md): a query reads its
  // own cell, and of the 26 around it only those nearer than its k-th nearest so far; sparse points need few
  // rings of cells.
  double cell = std::max(2.0, 5.0 / std::sqrt(double(k))) * sampledKthNeighbourDistance(k);
  if (!(cell > 0.0)) cell = span_ / std::cbrt(double(points_.size()));  // the samples sat on duplicates
  cell = std::max(cell, span_ / double(kMaxCellsPerAxis - 2));         // the keys' 21 bits per axis
  if (!(cell > 0.0)) cell = 1.0;                                        // every point the same: one cell
  cell_ = cell;
  inverse_cell_ = 1.0 / cell;
  for (int a = 0; a < 3; ++a) last_cell_[a] = std::int64_t(std::floor((hi[a] - lo[a]) * inverse_cell_));
}

inline CellGridKnn::CellCoords CellGridKnn::cellOf(double x, double y, double z) const {
  const double p[3] = {x, y, z};
  CellCoords c{};
  for (int a = 0; a < 3; ++a)
    c.c[a] = std::clamp(std::int64_t(std::floor((p[a] - origin_[a]) * inverse_cell_)), std::int64_t(0),
                        last_cell_[a]);
  return c;
}

inline std::uint64_t CellGridKnn::keyOf(const CellCoords& c) {
  return std::uint64_t(c.c[0]) | (std::uint64_t(c.c[1]) << kAxisBits) | (std::uint64_t(c.c[2]) << (2 * kAxisBits));
}

inline std::size_t CellGridKnn::slotOf(std::uint64_t key) const {
  // Fibonacci hashing: the product's top bits depend on every bit of the key (x, y and z alike)
  std::size_t s = std::size_t((key * 0x9E3779B97F4A7C15ull) >> shift_);
  while (keys_[s] != key && keys_[s] != kEmpty) s = (s + 1) & mask_;
  return s;
}

inline const CellGridKnn::Cell* CellGridKnn::find(const CellCoords& c) const {
  const std::size_t s = slotOf(keyOf(c));
  return keys_[s] == kEmpty ? nullptr : &cells_[numbers_[s]];
}

inline std::uint32_t CellGridKnn::numberOf(std::uint64_t key) {
  const std::size_t s = slotOf(key);
  if (keys_[s] != kEmpty) return numbers_[s];
  const auto number = std::uint32_t(cells_.size());
  keys_[s] = key, numbers_[s] = number;
  cells_.push_back(Cell{});
  if (8 * cells_.size() > keys_.size()) growTable();  // at most an eighth full: few probes for an empty cell
  return number;
}

inline void CellGridKnn::growTable() {
  std::vector<std::uint64_t> keys(keys_.size() * 2, kEmpty);
  std::vector<std::uint32_t> numbers(keys.size());
  keys.swap(keys_), numbers.swap(numbers_);
  mask_ = keys_.size() - 1, --shift_;
  for (std::size_t old = 0; old < keys.size(); ++old)
    if (keys[old] != kEmpty) {
      const std::size_t s = slotOf(keys[old]);
      keys_[s] = keys[old], numbers_[s] = numbers[old];
    }
}

// A counting sort by cell: count per cell, each cell's end, then place every point by counting down. The table
// starts at 64 slots and doubles as cells come (numberOf).
inline void CellGridKnn::sortIntoCells() {
  const std::size_t n = points_.size();
  keys_.assign(64, kEmpty), numbers_.assign(64, 0);
  mask_ = 63, shift_ = 64 - 6;
  std::vector<std::uint32_t> cell_of(n);
  for (std::size_t i = 0; i < n; ++i) {
    const auto& p = points_[i];
    cell_of[i] = numberOf(keyOf(cellOf(p.x(), p.y(), p.z())));
    ++cells_[cell_of[i]].count;
  }
  std::uint32_t end = 0;
  for (Cell& cell : cells_) end += cell.count, cell.start = end;
  sorted_.x.resize(n), sorted_.y.resize(n), sorted_.z.resize(n), sorted_.index.resize(n);
  for (std::size_t i = n; i-- > 0;) {
    const auto& p = points_[i];
    const std::uint32_t j = --cells_[cell_of[i]].start;
    sorted_.x[j] = p.x(), sorted_.y[j] = p.y(), sorted_.z[j] = p.z(), sorted_.index[j] = std::uint32_t(i);
  }
}

inline double CellGridKnn::unreadLowerBound(const Query& q, const CellCoords& c, std::int64_t ring) const {
  const double p[3] = {q.x, q.y, q.z};
  double bound = std::numeric_limits<double>::infinity();
  for (int a = 0; a < 3; ++a) {
    // a side at the grid's edge has no unread cells beyond it
    if (c.c[a] - ring > 0) bound = std::min(bound, p[a] - (origin_[a] + double(c.c[a] - ring) * cell_));
    if (c.c[a] + ring < last_cell_[a]) bound = std::min(bound, origin_[a] + double(c.c[a] + ring + 1) * cell_ - p[a]);
  }
  return bound - 1e-9 * (span_ + cell_ * double(ring + 1));
}

inline bool CellGridKnn::blockCoversGrid(const CellCoords& c, std::int64_t ring) const {
  for (int a = 0; a < 3; ++a)
    if (c.c[a] - ring > 0 || c.c[a] + ring < last_cell_[a]) return false;
  return true;
}

template <class Nearest>
bool CellGridKnn::certain(const Query& q, const CellCoords& c, std::int64_t ring, const Nearest& nearest) const {
  if (blockCoversGrid(c, ring)) return true;  // every point read
  if (!nearest.full()) return false;
  const double bound = unreadLowerBound(q, c, ring);
  // An unread point at exactly the bound would tie with the worst: the same distances either way.
  return bound > 0 && nearest.worst() <= bound * bound;
}

// In chunks: the squared distances first (a loop the compiler vectorises), then the few that beat the k-th.
template <class Nearest>
void CellGridKnn::offerCell(const Query& q, std::uint32_t begin, std::uint32_t end, Nearest& nearest) const {
  constexpr std::uint32_t kChunk = 32;
  const double qx = q.x, qy = q.y, qz = q.z;
  const double *x = sorted_.x.data(), *y = sorted_.y.data(), *z = sorted_.z.data();
  double d2[kChunk];
  for (std::uint32_t chunk = begin; chunk < end; chunk += kChunk) {
    const std::uint32_t m = std::min(kChunk, end - chunk);
    for (std::uint32_t j = 0; j < m; ++j) {
      const double dx = qx - x[chunk + j], dy = qy - y[chunk + j], dz = qz - z[chunk + j];
      d2[j] = dx * dx + dy * dy + dz * dz;  // squaredDistance(q, p), the same operations in the same order
    }
    double worst = nearest.worst();  // a local: the loop reads no vector between offers
    for (std::uint32_t j = 0; j < m; ++j)
      if (d2[j] < worst && sorted_.index[chunk + j] != q.index) nearest.offer(d2[j]), worst = nearest.worst();
  }
}

template <class Nearest>
void CellGridKnn::searchRings(const Query& q, const CellCoords& c, std::int64_t first_ring,
                              Nearest& nearest) const {
  std::size_t cells_read = 0;
  const double margin = gapMargin();
  const double p[3] = {q.x, q.y, q.z};
  // A cell's gap, a lower bound on the squared distance from q to any of its points, is the sum over the axes of
  // axisGap2 (the distance to its box along that axis, less the margin). A cell is not even looked up when its gap
  // reaches the k-th nearest so far (a tie at most); nor is a plane or a row of cells whose partial sum does (the
  // sum only grows).
  const auto axisGap2 = [&](int a, std::int64_t v) {
    const double low = origin_[a] + double(v) * cell_;
    const double gap = std::max(std::max(low - p[a], p[a] - (low + cell_)) - margin, 0.0);
    return gap * gap;
  };
  const auto farther = [&](double gap2) { return nearest.full() && !(gap2 < nearest.worst()); };
  const auto read = [&](std::int64_t x, std::int64_t y, std::int64_t z, double gap2_yz) {
    if (farther(gap2_yz + axisGap2(0, x))) return;
    ++cells_read;
    const CellCoords near{{x, y, z}};
    const Cell* cell = find(near);
    if (!cell) return;
    // k = 1 beyond the query's own cell (ring > 0): no point to exclude, the minimum of the vector loop
    if constexpr (std::is_same_v<Nearest, detail::NearestOne>)
      if (near.c[0] != c.c[0] || near.c[1] != c.c[1] || near.c[2] != c.c[2])
        return nearest.offer(nearestIn(q, cell->start, cell->start + cell->count));
    offerCell(q, cell->start, cell->start + cell->count, nearest);
  };
  for (std::int64_t ring = first_ring;; ++ring) {
    if (cells_read > points_.size()) {
      // Far from every other point (an outlier beside dense cells): reading all n points is cheaper than
      // the empty cells around it. Points read twice offer the same distance twice: start again.
      nearest.clear();
      offerCell(q, 0, std::uint32_t(points_.size()), nearest);
      return;
    }
    // the shell of cells at Chebyshev distance `ring`, clipped to the grid
    const std::int64_t z0 = std::max(c.c[2] - ring, std::int64_t(0)), z1 = std::min(c.c[2] + ring, last_cell_[2]);
    const std::int64_t y0 = std::max(c.c[1] - ring, std::int64_t(0)), y1 = std::min(c.c[1] + ring, last_cell_[1]);
    const std::int64_t x0 = std::max(c.c[0] - ring, std::int64_t(0)), x1 = std::min(c.c[0] + ring, last_cell_[0]);
    for (std::int64_t z = z0; z <= z1; ++z) {
      const double gap2_z = axisGap2(2, z);
      if (farther(gap2_z)) continue;
      for (std::int64_t y = y0; y <= y1; ++y) {
        const double gap2_yz = gap2_z + axisGap2(1, y);
        if (farther(gap2_yz)) continue;
        if (std::abs(z - c.c[2]) == ring || std::abs(y - c.c[1]) == ring) {
          for (std::int64_t x = x0; x <= x1; ++x) read(x, y, z, gap2_yz);
        } else {
          if (c.c[0] - ring >= 0) read(c.c[0] - ring, y, z, gap2_yz);
          if (ring > 0 && c.c[0] + ring <= last_cell_[0]) read(c.c[0] + ring, y, z, gap2_yz);
        }
      }
    }
    if (certain(q, c, ring, nearest)) return;
  }
}

inline void CellGridKnn::nearestOtherSquaredDistances(std::size_t i, int k, std::vector<double>& out) const {
  detail::NearestSoFar nearest(out, nearestCount(k));
  if (nearest.full()) return;  // nothing to find
  const auto& p = points_[i];
  const Query q{p.x(), p.y(), p.z(), std::uint32_t(i)};
  searchRings(q, cellOf(q.x, q.y, q.z), 0, nearest);
  nearest.sortAscending();
}

// Cells in the order of their first point: for a range scan's points (in image order) the next cell is a
// neighbour of the last, and the slots its 27 cells probe are mostly in cache already. A query reads its own cell,
// then each cell around it whose gap is below its k-th nearest so far (a point there at exactly that distance would
// tie: the same distances either way).
template <class Visit>
void CellGridKnn::forEachPointNearestOthers(int k, Visit&& visit) const {
  const std::size_t count = nearestCount(k);
  if (count == 1) return forEachPointNearestOther(visit);
  std::vector<double> d2;
  std::vector<NeighbourCell> neighbours;
  const double margin = gapMargin();
  for (std::uint32_t id = 0; id < cells_.size(); ++id) {
    const auto [begin, end, c] = numberedCell(id);
    neighboursOf(c, neighbours);
    for (std::uint32_t j = begin; j < end; ++j) {
      const Query q = query(j);
      detail::NearestSoFar nearest(d2, count);
      if (!nearest.full()) {
        offerCell(q, begin, end, nearest);
        const FaceGaps gaps = faceGaps(q, c, margin);
        for (const NeighbourCell& b : neighbours)
          if (!nearest.full() || gaps.of(b) < nearest.worst()) offerCell(q, b.start, b.end, nearest);
        if (!certain(q, c, 1, nearest)) searchRings(q, c, 2, nearest);
      }
      nearest.sortAscending();
      visit(std::size_t(q.index), static_cast<const std::vector<double>&>(d2));
    }
  }
}

// k = 1, the optimisation grids' k and the direct build's default: the nearest other point is a minimum, kept in
// a register instead of a sorted list. A query whose nearest point in its own cell is nearer than the cell's
// faces is settled by that cell; the others (about two in three on the dense built-in scene) read the cells
// around it whose gap is below the nearest so far, and the cells' 26 neighbours are looked up once, when the
// first point of the cell needs them (docs/performance.md, "k = 1 as a minimum").
template <class Visit>
void CellGridKnn::forEachPointNearestOther(Visit&& visit) const {
  std::vector<NeighbourCell> neighbours;
  std::vector<double> d2, own;
  const double margin = gapMargin();
  for (std::uint32_t id = 0; id < cells_.size(); ++id) {
    const auto [begin, end, c] = numberedCell(id);
    nearestWithin(begin, end, own);
    bool neighbours_found = false;
    for (std::uint32_t j = begin; j < end; ++j) {
      const Query q = query(j);
      double best = own[j - begin];
      const FaceGaps gaps = faceGaps(q, c, margin);
      // No point outside the cell is nearer than its nearest face (one at exactly that distance would tie).
      if (!(best <= gaps.nearest)) {
        if (!neighbours_found) neighboursOf(c, neighbours), neighbours_found = true;
        for (const NeighbourCell& b : neighbours)
          if (gaps.of(b) < best) best = std::min(best, nearestIn(q, b.start, b.end));
        detail::NearestOne nearest{best};
        if (!certain(q, c, 1, nearest)) searchRings(q, c, 2, nearest);
        best = nearest.d2;
      }
      d2.assign(1, best);
      visit(std::size_t(q.index), static_cast<const std::vector<double>&>(d2));
    }
  }
}

// Two points a step in vectors of two doubles, two minima side by side; each distance as squaredDistance.
inline double CellGridKnn::nearestIn(const Query& q, std::uint32_t begin, std::uint32_t end) const {
  using detail::Double2, detail::loadTwo;
  const Double2 qx = {q.x, q.x}, qy = {q.y, q.y}, qz = {q.z, q.z};
  const double *x = sorted_.x.data(), *y = sorted_.y.data(), *z = sorted_.z.data();
  constexpr double kInf = std::numeric_limits<double>::infinity();
  Double2 nearest = {kInf, kInf};
  std::uint32_t j = begin;
  for (; j + 1 < end; j += 2) {
    const Double2 dx = qx - loadTwo(x + j), dy = qy - loadTwo(y + j), dz = qz - loadTwo(z + j);
    const Double2 d2 = dx * dx + dy * dy + dz * dz;
    nearest = d2 < nearest ? d2 : nearest;
  }
  double m = std::min(nearest[0], nearest[1]);
  if (j < end) {
    const double dx = q.x - x[j], dy = q.y - y[j], dz = q.z - z[j];
    m = std::min(m, dx * dx + dy * dy + dz * dz);
  }
  return m;
}

// The pairs (i, j > i), j two at a time: the distance from i to j is the one from j to i (the differences only
// change sign), so the minima are those of nearestIn over the range without i. The pairs start at an even j, so a
// row reads its minima from where the rows before stored them whole (a load across two stores waits for both);
// a lane that is i itself, or past the range, counts as +inf.
inline void CellGridKnn::nearestWithin(std::uint32_t begin, std::uint32_t end, std::vector<double>& nearest) const {
  using detail::Double2, detail::loadTwo;
  using Mask2 = long long __attribute__((vector_size(16)));
  constexpr double kInf = std::numeric_limits<double>::infinity();
  const std::uint32_t m = end - begin;
  nearest.assign(m + 1, kInf);  // one more: the last pair of an odd range
  const double *x = sorted_.x.data() + begin, *y = sorted_.y.data() + begin, *z = sorted_.z.data() + begin;
  double* out = nearest.data();
  const auto load = [&](const double* from, std::uint32_t j) {  // past the range: the pair's own first point
    const Double2 d = {from[j], from[j + 1 < m ? j + 1 : j]};
    return d;
  };
  const Double2 inf2 = {kInf, kInf};
  for (std::uint32_t i = 0; i < m; ++i) {
    const Double2 qx = {x[i], x[i]}, qy = {y[i], y[i]}, qz = {z[i], z[i]};
    Double2 mine = inf2;
    for (std::uint32_t j = (i + 1) & ~1u; j < m; j += 2) {
      const Double2 dx = qx - load(x, j), dy = qy - load(y, j), dz = qz - load(z, j);
      Double2 d2 = dx * dx + dy * dy + dz * dz;
      const Mask2 lane = {j, j + 1};
      const Mask2 valid = (lane > (long long)i) & (lane < (long long)m);
      d2 = valid ? d2 : inf2;
      mine = d2 < mine ? d2 : mine;
      Double2 theirs = loadTwo(out + j);
      theirs = d2 < theirs ? d2 : theirs;
      std::memcpy(out + j, &theirs, sizeof theirs);
    }
    out[i] = std::min({out[i], mine[0], mine[1]});
  }
  nearest.pop_back();
}

inline void CellGridKnn::neighboursOf(const CellCoords& c, std::vector<NeighbourCell>& out) const {
  out.clear();
  for (std::int64_t z = std::max(c.c[2] - 1, std::int64_t(0)); z <= std::min(c.c[2] + 1, last_cell_[2]); ++z)
    for (std::int64_t y = std::max(c.c[1] - 1, std::int64_t(0)); y <= std::min(c.c[1] + 1, last_cell_[1]); ++y)
      for (std::int64_t x = std::max(c.c[0] - 1, std::int64_t(0)); x <= std::min(c.c[0] + 1, last_cell_[0]); ++x) {
        if (x == c.c[0] && y == c.c[1] && z == c.c[2]) continue;
        if (const Cell* cell = find(CellCoords{{x, y, z}}))
          out.push_back({{std::uint8_t(x - c.c[0] + 1), std::uint8_t(y - c.c[1] + 1), std::uint8_t(z - c.c[2] + 1)},
                         cell->start, cell->start + cell->count});
      }
}

inline CellGridKnn::FaceGaps CellGridKnn::faceGaps(const Query& q, const CellCoords& c, double margin) const {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  const double p[3] = {q.x, q.y, q.z};
  FaceGaps g{};
  g.nearest = kInf;
  for (int a = 0; a < 3; ++a) {
    const double low = origin_[a] + double(c.c[a]) * cell_;
    const double below = std::max(p[a] - low - margin, 0.0), above = std::max(low + cell_ - p[a] - margin, 0.0);
    g.gap2[a][0] = c.c[a] > 0 ? below * below : kInf;
    g.gap2[a][1] = 0.0;
    g.gap2[a][2] = c.c[a] < last_cell_[a] ? above * above : kInf;
    g.nearest = std::min({g.nearest, g.gap2[a][0], g.gap2[a][2]});
  }
  return g;
}

}  // namespace occsweep
