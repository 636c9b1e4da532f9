// SPDX-License-Identifier: GPL-3.0-or-later
// Mesh quality measures shared by the CLI, the plugin log and the tests:
// angles, enclosed volume, Hausdorff distance, faces turned against a reference.
#pragma once

#include <sodt/guards/facing.h>
#include <sodt/guards/input_grid.h>
#include <sodt/maths/box_tree.h>
#include <sodt/maths/geometry.h>
#include <sodt/maths/lanes.h>
#include "mesh.h"

#include <Eigen/Eigenvalues>
#include <vcg/complex/algorithms/point_sampling.h>
#include <vcg/complex/algorithms/update/bounding.h>
#include <vcg/complex/algorithms/update/normal.h>
#include <vcg/complex/complex.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <utility>
#include <vector>

namespace sodt {

/// Angle distribution over every corner of every live triangle, in degrees.
struct AngleStats {
  double minDeg = 0;       ///< smallest corner angle (0 for a mesh without faces)
  double maxDeg = 0;       ///< largest corner angle
  std::vector<long long> histogram = std::vector<long long>(180, 0);  ///< bin b counts angles in [b, b+1)
  double fracBelow30 = 0;  ///< fraction of corner angles below 30 degrees
  double fracAbove90 = 0;  ///< fraction of corner angles above 90 degrees
  double p1TriMinDeg = 0;  ///< 1st percentile of the per-triangle smallest angle
  long long faces = 0;     ///< live faces measured
};

/// Enclosed volume of a closed mesh.
struct VolumeResult {
  bool closed = false;  ///< every edge has exactly two faces, oriented consistently
  double volume = 0;    ///< signed volume (positive for outward normals); 0 when !closed
};

/// Two-sided surface distance, relative to the bounding-box diagonal of the reference.
struct DistanceStats {
  double maxRel = 0;   ///< symmetric Hausdorff distance / diagonal
  double meanRel = 0;  ///< mean of the two one-sided mean distances / diagonal
  /// The largest distance over those samples and points along every edge of
  /// both meshes (edgeSamples), / diagonal; at least maxRel. Where a surface
  /// bends, the farthest point between two meshes is often on an edge, at a
  /// few random surface points from the nearest sample.
  double maxEdgeRel = 0;
};

/// Sampling caps of surfaceDistance (per direction).
constexpr int kMaxVertexSamples = 250000;
constexpr int kMaxFaceSamples = 500000;
/// Points per edge of edgeSamples (at most), and their cap per direction.
constexpr int kEdgePoints = 7;
constexpr int kMaxEdgeSamples = 500000;

/// How surfaceDistance indexes the faces it measures against: vcglib's grid
/// or a tree of oriented boxes (see DistanceSampler), or the grid unless it
/// would grow too large (Auto). The distances are the same.
enum class FaceIndex { Auto, Grid, Tree };

/// Auto takes the tree when the grid would hold more links than this many
/// per face, plus a million.
constexpr double kGridLinksPerFace = 16;

/// Beyond this many reference diagonals, surfaceDistance reports a bound.
constexpr double kFarDiagonals = 10.0;

/// Positions and triangles in double and nothing else (no vertex normal,
/// quality, colour or adjacency): the meshes surfaceDistance samples, less
/// than half the memory of a MeshD. The face normals are there for vcglib's
/// point-face distance.
struct SampleMeshTypes {
  class Vertex;
  class Face;
  struct UsedTypes : public vcg::UsedTypes<vcg::Use<Vertex>::AsVertexType, vcg::Use<Face>::AsFaceType> {};
  class Vertex : public vcg::Vertex<UsedTypes, vcg::vertex::Coord3d, vcg::vertex::BitFlags> {};
  class Face : public vcg::Face<UsedTypes, vcg::face::VertexRef, vcg::face::Normal3d, vcg::face::BitFlags> {};
  class Mesh : public vcg::tri::TriMesh<std::vector<Vertex>, std::vector<Face>> {};
};
using SampleMesh = SampleMeshTypes::Mesh;

namespace detail {

template <class MeshType>
Vec3 toVec3(const typename MeshType::CoordType& c) {
  return Vec3(c[0], c[1], c[2]);
}

/// Copies the live vertices and faces of any vcg mesh into a double mesh
/// (MeshD or SampleMesh) and computes its bounding box.
template <class MeshType, class DstMesh>
void copyLive(const MeshType& src, DstMesh& dst) {
  dst.Clear();
  // Only vertices of live faces are surface points (when there are faces):
  // an unreferenced vertex far from a tiny surface would also wreck the
  // sampling grids.
  std::vector<char> used(src.vert.size(), 0);
  bool anyFace = false;
  for (const auto& f : src.face)
    if (!f.IsD()) {
      anyFace = true;
      for (int j = 0; j < 3; ++j) used[f.cV(j) - &src.vert[0]] = 1;
    }
  std::vector<int> remap(src.vert.size(), -1);
  int nv = 0;
  for (std::size_t i = 0; i < src.vert.size(); ++i)
    if (!src.vert[i].IsD() && (used[i] || !anyFace)) remap[i] = nv++;
  vcg::tri::Allocator<DstMesh>::AddVertices(dst, nv);
  for (std::size_t i = 0; i < src.vert.size(); ++i)
    if (remap[i] >= 0) dst.vert[remap[i]].P() = toVec3<MeshType>(src.vert[i].cP());
  int nf = 0;
  for (const auto& f : src.face)
    if (!f.IsD()) ++nf;
  vcg::tri::Allocator<DstMesh>::AddFaces(dst, nf);
  int k = 0;
  for (const auto& f : src.face) {
    if (f.IsD()) continue;
    for (int j = 0; j < 3; ++j)
      dst.face[k].V(j) = &dst.vert[remap[f.cV(j) - &src.vert[0]]];
    ++k;
  }
  vcg::tri::UpdateBounding<DstMesh>::Box(dst);
}

/// Copies the live vertices and faces of any vcg mesh into a double mesh,
/// with its bounding box and normals.
template <class MeshType>
void copyToDouble(const MeshType& src, MeshD& dst) {
  copyLive(src, dst);
  vcg::tri::UpdateNormal<MeshD>::PerVertexNormalizedPerFace(dst);
}

/// True when copyLive would copy m as it is: no deleted face (vcglib's face
/// grid would index them) and, when there are faces, no live vertex outside
/// them. surfaceDistanceInPlace samples such a mesh without copying it.
template <class MeshType>
bool samplesAsIs(const MeshType& m) {
  if (m.fn != static_cast<int>(m.face.size())) return false;
  if (m.face.empty()) return true;
  std::vector<char> used(m.vert.size(), 0);
  for (const auto& f : m.face)
    for (int j = 0; j < 3; ++j) used[f.cV(j) - &m.vert[0]] = 1;
  for (std::size_t i = 0; i < m.vert.size(); ++i)
    if (!m.vert[i].IsD() && !used[i]) return false;
  return true;
}

/// Sum of the face areas.
template <class MeshType>
double totalArea(const MeshType& m) {
  double a = 0;
  for (const auto& f : m.face)
    if (!f.IsD()) a += 0.5 * doubleAreaVector(toVec3<MeshType>(f.cP(0)), toVec3<MeshType>(f.cP(1)),
                                              toVec3<MeshType>(f.cP(2))).Norm();
  return a;
}

/// A copy of m's vertices without faces: the sampler then measures
/// distances to the points, which is all a surface without area has.
template <class MeshType>
void pointsOnly(const MeshType& m, SampleMesh& out) {
  out.Clear();
  vcg::tri::Allocator<SampleMesh>::AddVertices(out, m.vn);
  int k = 0;
  for (const auto& v : m.vert)
    if (!v.IsD()) out.vert[k++].P() = toVec3<MeshType>(v.cP());
  vcg::tri::UpdateBounding<SampleMesh>::Box(out);
}

/// The box, cells and cell sizes vcglib's GridStaticPtr::Set gives a face
/// grid over [begin, end) (see setFaceGrid), without filling the cells.
template <class FaceGrid, class Iter>
void layFaceGrid(FaceGrid& grid, Iter begin, Iter end, const typename FaceGrid::Box3x& cover) {
  using Box = typename FaceGrid::Box3x;
  using Coord = typename FaceGrid::CoordType;
  using Scalar = typename FaceGrid::ScalarType;
  Box own, b;
  long long count = 0;
  for (Iter i = begin; i != end; ++i, ++count) {
    i->GetBBox(b);
    own.Add(b);
  }
  Box all = own;
  all.Add(cover);
  // What Set(begin, end) and Set(begin, end, box, size) compute before the
  // cells are filled.
  const int size = std::max<long long>(1, count) > std::numeric_limits<int>::max()
                       ? std::numeric_limits<int>::max()
                       : static_cast<int>(std::max<long long>(1, count));
  if (cover.IsNull() || all == own) all = own;
  const Scalar infl = all.Diag() / size;
  all.min -= Coord(infl, infl, infl);
  all.max += Coord(infl, infl, infl);
  vcg::Point3i siz;
  vcg::BestDim(static_cast<long long>(size), Coord(all.max - all.min), siz);
  grid.bbox = all;
  grid.siz = siz;
  grid.dim = all.max - all.min;
  for (int j = 0; j < 3; ++j) grid.voxel[j] = grid.dim[j] / grid.siz[j];
}

/// The cells of face f in grid (those its box meets, clipped to the grid)
/// in ib; false when there are none.
template <class FaceGrid, class Face>
bool faceCells(const FaceGrid& grid, const Face& f, vcg::Box3i& ib) {
  typename FaceGrid::Box3x fb;
  f.GetBBox(fb);
  fb.Intersect(grid.bbox);
  if (fb.IsNull()) return false;
  grid.BoxToIBox(fb, ib);
  return true;
}

/// How many links setFaceGrid would make over a grid laid by layFaceGrid,
/// counted without making them (in time linear in the faces).
template <class FaceGrid, class Iter>
double faceGridLinks(const FaceGrid& grid, Iter begin, Iter end) {
  double links = 0;
  vcg::Box3i ib;
  for (Iter i = begin; i != end; ++i)
    if (faceCells(grid, *i, ib))
      links += double(ib.max[0] - ib.min[0] + 1) * double(ib.max[1] - ib.min[1] + 1) * double(ib.max[2] - ib.min[2] + 1);
  return links;
}

/// vcglib's GridStaticPtr::Set for faces, with the same grid (box, cells,
/// and the faces of each cell) but built by counting: two passes over the
/// faces instead of a link appended per face and cell and a sort of them all
/// (on a multi-million face mesh the sort and the vector's regrowth took
/// seconds, and the regrowth held up to twice the links). Within a cell the
/// faces are in the order of [begin, end), where vcglib's unstable sort
/// leaves them in no particular order. The faces must all be live. The grid
/// covers the faces' box, inflated as vcglib inflates it, or that box joined
/// with cover when cover sticks out of it (see DistanceSampler).
template <class FaceGrid, class Iter>
void setFaceGrid(FaceGrid& grid, Iter begin, Iter end, const typename FaceGrid::Box3x& cover) {
  using Link = typename FaceGrid::Link;
  layFaceGrid(grid, begin, end, cover);
  const vcg::Point3i siz = grid.siz;
  const std::size_t cells = static_cast<std::size_t>(siz[0]) * siz[1] * siz[2];
  const auto cellsOf = [&](const typename FaceGrid::ObjType& f, vcg::Box3i& ib) { return faceCells(grid, f, ib); };
  std::vector<std::size_t> start(cells + 1, 0);
  vcg::Box3i ib;
  for (Iter i = begin; i != end; ++i)
    if (cellsOf(*i, ib))
      for (int z = ib.min[2]; z <= ib.max[2]; ++z)
        for (int y = ib.min[1]; y <= ib.max[1]; ++y)
          for (int x = ib.min[0]; x <= ib.max[0]; ++x) ++start[x + siz[0] * (y + siz[1] * std::size_t(z)) + 1];
  for (std::size_t c = 0; c < cells; ++c) start[c + 1] += start[c];
  grid.links.assign(start[cells] + 1, Link(nullptr, static_cast<int>(cells)));  // the last: the end marker
  {
    std::vector<std::size_t> next(start.begin(), start.end() - 1);
    for (Iter i = begin; i != end; ++i)
      if (cellsOf(*i, ib))
        for (int z = ib.min[2]; z <= ib.max[2]; ++z)
          for (int y = ib.min[1]; y <= ib.max[1]; ++y)
            for (int x = ib.min[0]; x <= ib.max[0]; ++x) {
              const std::size_t c = x + siz[0] * (y + siz[1] * std::size_t(z));
              grid.links[next[c]++] = Link(&*i, static_cast<int>(c));
            }
  }
  grid.grid.resize(cells + 1);
  for (std::size_t c = 0; c <= cells; ++c) grid.grid[c] = grid.links.data() + start[c];
}

/// The faces [begin, end) in a BoxTree (sodt/box_tree.h), for the
/// closest-face search where vcglib's grid does not work (long needles).
template <class FaceType>
class FaceBoxTree {
 public:
  using CoordType = typename FaceType::CoordType;

  /// Indexes the faces [begin, end). slack: an absolute margin added to
  /// every box, to cover rounding in the projections.
  template <class Iter>
  void build(Iter begin, Iter end, double slack) {
    faces_.clear();
    for (Iter i = begin; i != end; ++i) faces_.push_back(&*i);
    tree_.build(static_cast<int>(faces_.size()),
                [this](int k, int j) {
                  const CoordType& c = faces_[k]->cP(j);
                  return Vec3(double(c[0]), double(c[1]), double(c[2]));
                },
                slack);
  }

  bool empty() const { return tree_.empty(); }

  /// Calls visit(face) for every face whose leaf's box is within
  /// sqrt(reach2()) of p, nearer subtrees first (BoxTree::search).
  template <class Reach2, class Visit>
  void search(const CoordType& p, Reach2&& reach2, Visit&& visit) const {
    tree_.search(Vec3(double(p[0]), double(p[1]), double(p[2])), reach2, [&](int k) {
      visit(*faces_[k]);
      return false;
    });
  }

 private:
  BoxTree tree_;
  std::vector<const FaceType*> faces_;
};

/// Distances from sample points to the surface of `to` (to its vertices when
/// it has no faces): vcglib's HausdorffSampler reduced to what
/// surfaceDistance reports, with the same results bit for bit. Each sample's
/// distance is the smallest of vcglib's point-face distances over the faces
/// within the bound, found by vcglib's closest-face search over vcglib's face
/// grid, cell for cell. Unlike HausdorffSampler it takes samples of any mesh
/// type, needs no normals and leaves the sampled vertices' quality alone
/// (HausdorffSampler stores each vertex's distance there).
///
/// Three things make it faster than HausdorffSampler without changing a
/// distance:
/// - the samples are looked up in the order of a space-filling curve, from a
///   copy in that order (random surface points in sampling order touch a new
///   part of the mesh each time; in curve order, consecutive lookups share
///   their cells and faces in the cache);
/// - a face whose bounding box is farther than the closest distance found so
///   far is passed over without vcglib's point-face distance, which could not
///   come out smaller;
/// - those boxes are kept beside the grid, cell by cell, in float rounded
///   outwards, and tested four at a time (AVX2, where the processor has it).
///   A sample's search reads one short run of them per cell instead of
///   each face's three corners.
/// The search does not mark the faces it has measured: a face in several of
/// the cells searched is measured once per cell, with the same distance.
template <class To>
class DistanceSampler {
 public:
  using CoordType = typename To::CoordType;
  using ScalarType = typename To::ScalarType;

  /// Normalizes to's face normals (the point-face distance needs them) and
  /// indexes its faces, or its vertices when it has none. The faces go in
  /// vcglib's grid unless that would hold more than kGridLinksPerFace links
  /// per face (plus a million): long thin faces, each in many cells; then in
  /// a FaceBoxTree (index forces one or the other; the distances are the
  /// same either way). The samples are
  /// expected inside `cover`: vcglib's closest-point search widens its radius
  /// one cell at a time, so a sample far outside the grid would take as many
  /// rounds as there are cell widths between them (a mesh whose spike the
  /// smoothing removed: ten million rounds per sample). The grid is laid over
  /// cover as well when cover reaches beyond to's own box. simd: test the
  /// boxes four at a time where the processor can (the results are the same
  /// either way); threads: for the boxes.
  DistanceSampler(To& to, ScalarType upperBound, const vcg::Box3<ScalarType>& cover, bool simd = true,
                  int threads = 1, FaceIndex index = FaceIndex::Auto)
      : to_(to), upperBound_(upperBound), simd_(simd && lanes::available()) {
    vcg::tri::UpdateNormal<To>::PerFaceNormalized(to);
    if (to.fn == 0) {
      setGrid(vertexGrid_, to.vert.begin(), to.vert.end(), to.vn, cover);
    } else {
      layFaceGrid(faceGrid_, to.face.begin(), to.face.end(), cover);
      useTree_ = index == FaceIndex::Tree ||
                 (index == FaceIndex::Auto &&
                  faceGridLinks(faceGrid_, to.face.begin(), to.face.end()) > kGridLinksPerFace * double(to.fn) + 1e6);
      if (!useTree_) {
        setFaceGrid(faceGrid_, to.face.begin(), to.face.end(), cover);
        setBoxes(std::max(1, std::min(threads, 1024)));
      }
    }
    // vcglib's point-face distance rounds at the scale of the coordinates,
    // not of the distance: the bounding-box test leaves that much room.
    ScalarType largest = 0;
    for (const auto& v : to.vert)
      if (!v.IsD())
        for (int j = 0; j < 3; ++j) largest = std::max(largest, std::abs(v.cP()[j]));
    if (!cover.IsNull())
      for (int j = 0; j < 3; ++j) largest = std::max({largest, std::abs(cover.min[j]), std::abs(cover.max[j])});
    slack_ = ScalarType(1e-12) * largest;
    if (useTree_) tree_.build(to.face.begin(), to.face.end(), double(slack_));
  }

  /// True when the faces are indexed by a FaceBoxTree instead of the grid.
  bool usesTree() const { return useTree_; }

  /// HausdorffSampler::AddVert without the normal and the quality.
  template <class VertexType>
  void AddVert(const VertexType& v) {
    addSample(v.cP());
  }
  /// HausdorffSampler::AddFace without the normal.
  template <class FaceType>
  void AddFace(const FaceType& f, const CoordType& interp) {
    addSample(f.cP(0) * interp[0] + f.cP(1) * interp[1] + f.cP(2) * interp[2]);
  }

  /// Looks up the samples taken so far, on threads threads, and adds their
  /// distances in the order they were taken, as HausdorffSampler adds them
  /// one by one: the result does not depend on the number of threads.
  void measure(int threads) {
    const long long n = static_cast<long long>(points_.size());
    std::vector<ScalarType> dist(points_.size());
    {
      const std::vector<int> order = curveOrder();
      std::vector<CoordType> sorted(points_.size());
      for (long long j = 0; j < n; ++j) sorted[j] = points_[order[j]];
      threads = std::max(1, std::min(threads, 1024));
      if (to_.fn == 0) {
        for (long long j = 0; j < n; ++j) dist[order[j]] = closestVertex(sorted[j]);
      } else {
#ifdef _OPENMP
#pragma omp parallel for num_threads(threads) schedule(dynamic, 1024) if (threads > 1 && n >= 4096)
#endif
        for (long long j = 0; j < n; ++j) dist[order[j]] = closestFace(sorted[j]);
      }
    }
    for (const ScalarType d : dist) {
      if (d == upperBound_) continue;  // nothing closer than the bound: not counted
      if (d > maxDist_) maxDist_ = d;
      sumDist_ += d;
      ++samples_;
    }
    points_.clear();
  }

  int samples() const { return samples_; }
  /// Largest distance, rounded to float like HausdorffSampler::getMaxDist.
  float maxDist() const { return float(maxDist_); }
  /// Mean distance, rounded to float like HausdorffSampler::getMeanDist.
  float meanDist() const { return float(sumDist_ / samples_); }

 private:
  using FaceGrid = vcg::GridStaticPtr<typename To::FaceType, ScalarType>;
  using VertexGrid = vcg::GridStaticPtr<typename To::VertexType, ScalarType>;
  using Link = typename FaceGrid::Link;

  /// Samples are looked up by measure().
  void addSample(const CoordType& p) { points_.push_back(p); }

  /// The distance HausdorffSampler::AddSample finds for p when to has no
  /// faces: the upper bound when no vertex is closer.
  ScalarType closestVertex(const CoordType& p) {
    ScalarType dist = upperBound_;
    vcg::tri::GetClosestVertex<To, VertexGrid>(to_, vertexGrid_, p, upperBound_, dist);
    return dist;
  }

  /// The bounding box of the face of every link of the face grid, in the
  /// links' order (a cell's faces are a run), one array per bound and axis:
  /// box_[a * stride_ + k] for link k, a = 0..2 the lower and 3..5 the upper
  /// bounds, rounded outwards to float. stride_ leaves room for a group of
  /// four that reads past the last link. Filled on threads threads (the
  /// array is written where it is first touched, not zeroed before).
  void setBoxes(int threads) {
    const long long nl = static_cast<long long>(faceGrid_.links.size());
    stride_ = static_cast<std::size_t>(nl) + lanes::kWidth;
    box_.reset(new float[6 * stride_]);
    float* const box = box_.get();
    const std::size_t stride = stride_;
    auto& links = faceGrid_.links;  // (Link::Elem is not const)
#ifdef _OPENMP
#pragma omp parallel for num_threads(threads) schedule(static) if (threads > 1 && nl >= 65536)
#endif
    for (long long k = 0; k < nl + lanes::kWidth; ++k) {
      const auto* f = k < nl ? links[static_cast<std::size_t>(k)].Elem() : nullptr;
      for (int j = 0; j < 3; ++j) {
        float flo = 0, fhi = 0;  // the grid's end marker and the room after it
        if (f) {
          const ScalarType a = f->cP(0)[j], b = f->cP(1)[j], c = f->cP(2)[j];
          const ScalarType lo = std::min(a, std::min(b, c)), hi = std::max(a, std::max(b, c));
          flo = static_cast<float>(lo);
          fhi = static_cast<float>(hi);
          if (ScalarType(flo) > lo) flo = std::nextafter(flo, -std::numeric_limits<float>::infinity());
          if (ScalarType(fhi) < hi) fhi = std::nextafter(fhi, std::numeric_limits<float>::infinity());
        }
        box[j * stride + k] = flo;
        box[(3 + j) * stride + k] = fhi;
      }
    }
  }

  /// The squared distance from p to the box of link k, in double; nothing
  /// of the face itself is read. (The float box holds the face's box, so
  /// this is at most the squared distance to the face.)
  ScalarType boxDistance2(const CoordType& p, std::size_t k) const {
    ScalarType d2 = 0;
    for (int j = 0; j < 3; ++j) {
      const ScalarType lo = box_[j * stride_ + k], hi = box_[(3 + j) * stride_ + k];
      const ScalarType e = std::max(std::max(lo - p[j], p[j] - hi), ScalarType(0));
      d2 = j == 0 ? e * e : d2 + e * e;
    }
    return d2;
  }

  /// Bit l set: link k + l has a box within sqrt(reach2) of p (or a distance
  /// that is NaN), the lanes of boxDistance2 compared as the scalar test
  /// compares them; d2[l] gets that squared distance.
  int nearBoxes(const CoordType& p, std::size_t k, ScalarType reach2, double* d2) const {
#ifdef SODT_HAVE_LANES
    if (simd_) return nearBoxes4(p, k, reach2, d2);
#endif
    int m = 0;
    for (int l = 0; l < lanes::kWidth; ++l) {
      d2[l] = boxDistance2(p, k + l);
      m |= !(d2[l] > reach2) << l;
    }
    return m;
  }

#ifdef SODT_HAVE_LANES
  __attribute__((target("avx2"))) int nearBoxes4(const CoordType& p, std::size_t k, ScalarType reach2,
                                                 double* out) const {
    __m256d d2 = _mm256_setzero_pd();
    for (int j = 0; j < 3; ++j) {
      const __m256d lo = _mm256_cvtps_pd(_mm_loadu_ps(&box_[j * stride_ + k]));
      const __m256d hi = _mm256_cvtps_pd(_mm_loadu_ps(&box_[(3 + j) * stride_ + k]));
      const __m256d q = _mm256_set1_pd(double(p[j]));
      const __m256d e =
          _mm256_max_pd(_mm256_max_pd(_mm256_sub_pd(lo, q), _mm256_sub_pd(q, hi)), _mm256_setzero_pd());
      d2 = j == 0 ? _mm256_mul_pd(e, e) : _mm256_add_pd(d2, _mm256_mul_pd(e, e));
    }
    _mm256_storeu_pd(out, d2);
    return _mm256_movemask_pd(_mm256_cmp_pd(d2, _mm256_set1_pd(double(reach2)), _CMP_NGT_UQ));
  }
#endif

  /// The distance HausdorffSampler::AddSample finds for p: the upper bound
  /// when no surface point is closer. vcglib's GridClosest, cell for cell:
  /// first the cell that holds p, then the cells within the closest distance
  /// found (or one more cell diagonal while there is none) until that
  /// distance is within the radius searched. A face is measured with
  /// vcglib's PointDistanceBaseFunctor unless its box is farther than the
  /// closest distance so far by more than the distance's rounding (slack_):
  /// its distance could not beat it then.
  ScalarType closestFace(const CoordType& p) {
    if (useTree_) return closestFaceInTree(p);
    FaceGrid& G = faceGrid_;
    Link* const links = G.links.data();
    ScalarType minDist = upperBound_;
    bool found = false;
    vcg::face::PointDistanceBaseFunctor<ScalarType> exact;
    CoordType closest;
    const auto searchCell = [&](int cell) {
      Link* const first = G.grid[cell];
      const int n = static_cast<int>(G.grid[cell + 1] - first);
      const std::size_t k = static_cast<std::size_t>(first - links);
      double d2[lanes::kWidth];
      for (int g = 0; g < n; g += lanes::kWidth) {
        ScalarType reach = minDist * ScalarType(1 + 1e-9) + slack_;
        int near = nearBoxes(p, k + g, reach * reach, d2);
        if (n - g < lanes::kWidth) near &= (1 << (n - g)) - 1;
        for (int l = 0; l < lanes::kWidth; ++l) {
          if (!(near >> l & 1)) continue;
          // Against the closest distance so far, which a face before it in
          // the group may have lowered.
          reach = minDist * ScalarType(1 + 1e-9) + slack_;
          if (d2[l] > reach * reach) continue;
          const auto& f = *first[g + l].Elem();
          if (!f.IsD() && exact(f, p, minDist, closest)) found = true;
        }
      }
    };
    const ScalarType step = G.voxel.Norm();
    ScalarType radius = step;
    vcg::Box3i done, todo;  // done starts empty
    if (G.bbox.IsInEx(p)) {
      vcg::Point3i ip;
      G.PToIP(p, ip);
      searchCell(ip[0] + G.siz[0] * (ip[1] + G.siz[1] * ip[2]));
      if (found) radius = minDist;
      done = vcg::Box3i(ip, ip);
    }
    const vcg::Box3i all(vcg::Point3i(0, 0, 0), G.siz - vcg::Point3i(1, 1, 1));
    for (;;) {
      G.BoxToIBox(vcg::Box3<ScalarType>(p, radius), todo);
      todo.Intersect(all);
      for (int x = todo.min[0]; x <= todo.max[0]; ++x)
        for (int y = todo.min[1]; y <= todo.max[1]; ++y)
          for (int z = todo.min[2]; z <= todo.max[2]; ++z)
            if (x < done.min[0] || x > done.max[0] || y < done.min[1] || y > done.max[1] || z < done.min[2] ||
                z > done.max[2])
              searchCell(x + G.siz[0] * (y + G.siz[1] * z));
      done = todo;
      if (!(minDist > radius)) break;
      radius = found ? minDist : radius + step;
    }
    return minDist;
  }

  /// closestFace over the tree: every face whose leaf's box is within the
  /// closest distance so far (plus its rounding) is measured, so the
  /// smallest distance is the one the grid search finds.
  ScalarType closestFaceInTree(const CoordType& p) const {
    ScalarType minDist = upperBound_;
    vcg::face::PointDistanceBaseFunctor<ScalarType> exact;
    CoordType closest;
    const auto reach2 = [&] {
      const double r = double(minDist) * (1 + 1e-9) + double(slack_);
      return r * r;
    };
    tree_.search(p, reach2, [&](const typename To::FaceType& f) {
      if (!f.IsD()) exact(f, p, minDist, closest);
    });
    return minDist;
  }

  /// The samples' order along a Morton (Z-order) curve over the grid's box,
  /// 21 bits per axis.
  std::vector<int> curveOrder() const {
    const vcg::Box3<ScalarType>& box = to_.fn == 0 ? vertexGrid_.bbox : faceGrid_.bbox;
    std::vector<std::pair<std::uint64_t, int>> keyed(points_.size());
    const double cells = double((1u << 21) - 1);
    for (std::size_t i = 0; i < points_.size(); ++i) {
      std::uint64_t key = 0;
      for (int j = 0; j < 3; ++j) {
        const double extent = double(box.max[j]) - double(box.min[j]);
        double t = extent > 0 ? (double(points_[i][j]) - double(box.min[j])) / extent : 0.0;
        t = t > 0 ? (t < 1 ? t : 1.0) : 0.0;  // NaN goes to 0 too
        std::uint64_t q = static_cast<std::uint64_t>(t * cells);
        // Spread q's 21 bits three apart.
        q &= 0x1fffff;
        q = (q | q << 32) & 0x1f00000000ffffull;
        q = (q | q << 16) & 0x1f0000ff0000ffull;
        q = (q | q << 8) & 0x100f00f00f00f00full;
        q = (q | q << 4) & 0x10c30c30c30c30c3ull;
        q = (q | q << 2) & 0x1249249249249249ull;
        key |= q << j;
      }
      keyed[i] = {key, static_cast<int>(i)};
    }
    std::sort(keyed.begin(), keyed.end());
    std::vector<int> order(points_.size());
    for (std::size_t i = 0; i < keyed.size(); ++i) order[i] = keyed[i].second;
    return order;
  }

  /// Grid over the live vertices [begin, end), as vcglib lays it, or over
  /// their box joined with cover (inflated the way vcglib inflates) when
  /// cover sticks out of it (faces: setFaceGrid).
  template <class Grid, class Iter>
  static void setGrid(Grid& grid, Iter begin, Iter end, int live, const vcg::Box3<ScalarType>& cover) {
    vcg::Box3<ScalarType> own, b;
    for (Iter i = begin; i != end; ++i) {
      if (i->IsD()) continue;
      i->GetBBox(b);
      own.Add(b);
    }
    vcg::Box3<ScalarType> all = own;
    all.Add(cover);
    if (cover.IsNull() || all == own) {
      grid.Set(begin, end);
      return;
    }
    const int size = std::max(1, live);
    const ScalarType infl = all.Diag() / size;
    all.min -= CoordType(infl, infl, infl);
    all.max += CoordType(infl, infl, infl);
    grid.Set(begin, end, all, size);
  }

  To& to_;
  bool useTree_ = false;
  FaceBoxTree<typename To::FaceType> tree_;
  FaceGrid faceGrid_;
  VertexGrid vertexGrid_;
  std::unique_ptr<float[]> box_;  ///< see setBoxes
  std::size_t stride_ = 0;
  ScalarType upperBound_;
  ScalarType slack_ = 0;
  bool simd_;
  std::vector<CoordType> points_;  ///< taken, not looked up yet
  double maxDist_ = 0;
  double sumDist_ = 0;
  int samples_ = 0;
};

/// What vcglib's SurfaceSampling<From, Sampler>::Montecarlo(m, ps, n) gives
/// ps: the same area-uniform samples in the same order, from the same
/// random numbers of SurfaceSampling<From, Sampler>'s generator. vcglib
/// finds each sample's face by a binary search over the cumulative face
/// areas, a cache miss per step on a large mesh; here the samples are
/// drawn first and their faces found in one pass in increasing order.
template <class From, class Sampler>
void montecarloSamples(From& m, Sampler& ps, int sampleNum) {
  using SS = vcg::tri::SurfaceSampling<From, Sampler>;
  using ScalarType = typename From::ScalarType;
  std::vector<ScalarType> cumulative(1, ScalarType(0));  // vcglib's intervals
  std::vector<typename From::FacePointer> face(1, nullptr);
  cumulative.reserve(m.fn + 1);
  face.reserve(m.fn + 1);
  for (auto fi = m.face.begin(); fi != m.face.end(); ++fi)
    if (!fi->IsD()) {
      cumulative.push_back(cumulative.back() + 0.5 * vcg::DoubleArea(*fi));
      face.push_back(&*fi);
    }
  const ScalarType meshArea = cumulative.back();
  const std::size_t n = static_cast<std::size_t>(std::max(0, sampleNum));
  std::vector<std::pair<ScalarType, int>> value(n);
  std::vector<typename From::CoordType> barycentric(n);
  for (std::size_t i = 0; i < n; ++i) {
    value[i] = {meshArea * SS::RandomDouble01(), static_cast<int>(i)};
    barycentric[i] = SS::RandomBarycentric();
  }
  // vcglib's lower_bound: the first interval end not below the value.
  std::vector<int> hit(n);
  std::sort(value.begin(), value.end());
  std::size_t k = 1;  // (a value of 0 would give vcglib the empty interval before the first face)
  for (const auto& v : value) {
    while (k + 1 < cumulative.size() && cumulative[k] < v.first) ++k;
    hit[v.second] = static_cast<int>(k);
  }
  for (std::size_t i = 0; i < n; ++i) ps.AddFace(*face[hit[i]], barycentric[i]);
}

/// Points along the edges of m, each edge once (on the first face that has
/// it): k points at j / (k + 1) of its length, j = 1..k, with k =
/// kEdgePoints or fewer so that about max(20000, 4F) points are taken, at
/// most kMaxEdgeSamples; beyond that, the midpoints of every s-th edge. No
/// randomness.
template <class From, class Sampler>
void edgeSamples(From& m, Sampler& ps) {
  using CoordType = typename From::CoordType;
  using ScalarType = typename From::ScalarType;
  using VP = typename From::ConstVertexPointer;
  struct Side {
    VP lo, hi;
    std::size_t face;
    int j;
  };
  std::vector<Side> sides;
  sides.reserve(3 * static_cast<std::size_t>(m.fn));
  for (std::size_t i = 0; i < m.face.size(); ++i) {
    const auto& f = m.face[i];
    if (f.IsD()) continue;
    for (int j = 0; j < 3; ++j) {
      const VP a = f.cV(j), b = f.cV((j + 1) % 3);
      sides.push_back({std::min(a, b), std::max(a, b), i, j});
    }
  }
  std::stable_sort(sides.begin(), sides.end(), [](const Side& x, const Side& y) {
    return std::less<VP>()(x.lo, y.lo) || (x.lo == y.lo && std::less<VP>()(x.hi, y.hi));
  });
  sides.erase(std::unique(sides.begin(), sides.end(),
                          [](const Side& x, const Side& y) { return x.lo == y.lo && x.hi == y.hi; }),
              sides.end());
  if (sides.empty()) return;
  const std::size_t budget =
      std::min<std::size_t>(kMaxEdgeSamples, std::max<std::size_t>(20000, 4 * static_cast<std::size_t>(m.fn)));
  const int k = static_cast<int>(std::min<std::size_t>(kEdgePoints, std::max<std::size_t>(1, budget / sides.size())));
  const std::size_t stride = std::max<std::size_t>(1, (sides.size() + budget - 1) / budget);
  for (std::size_t e = 0; e < sides.size(); e += stride) {
    const Side& s = sides[e];
    for (int i = 1; i <= k; ++i) {
      const ScalarType t = ScalarType(i) / ScalarType(k + 1);
      CoordType w(0, 0, 0);
      w[s.j] = 1 - t;
      w[(s.j + 1) % 3] = t;
      ps.AddFace(m.face[s.face], w);
    }
  }
}

/// One-sided distances from samples of `from` (all vertices plus area-uniform
/// random points with a fixed seed) to the surface of `to`. Both are double
/// meshes (MeshD or SampleMesh) without deleted faces and with an up-to-date
/// bounding box; `to` gets normalized face normals. simd: see DistanceSampler
/// (the results are the same either way). edgeMax, when not null, receives
/// the largest distance over those samples and edgeSamples(from) too (they
/// change neither returned value).
template <class From, class To>
std::pair<double, double> oneSidedDistance(From& from, To& to, double upperBound, int threads = 1,
                                           bool simd = true, FaceIndex index = FaceIndex::Auto,
                                           double* edgeMax = nullptr) {
  using Sampler = DistanceSampler<To>;
  Sampler hs(to, upperBound, from.bbox, simd, threads, index);
  using SS = vcg::tri::SurfaceSampling<From, Sampler>;
  SS::SamplingRandomGenerator().initialize(20130101u);
  // Every vertex and 2F area-uniform points, capped so that a multi-million
  // face mesh is measured in seconds rather than minutes.
  if (from.vn <= kMaxVertexSamples)
    SS::AllVertex(from, hs, false);
  else
    SS::VertexUniform(from, hs, kMaxVertexSamples);
  const int faceSamples = std::min(kMaxFaceSamples, std::max(10000, 2 * from.fn));
  if (from.fn > 0 && totalArea(from) > 0) montecarloSamples(from, hs, faceSamples);  // no area: nothing to sample
  hs.measure(threads);
  if (hs.samples() == 0) {
    if (edgeMax) *edgeMax = std::numeric_limits<double>::infinity();
    return {std::numeric_limits<double>::infinity(), 0.0};
  }
  const std::pair<double, double> r{double(hs.maxDist()), double(hs.meanDist())};
  if (edgeMax) {
    edgeSamples(from, hs);
    hs.measure(threads);
    *edgeMax = double(hs.maxDist());
  }
  return r;
}

/// surfaceDistance of two meshes that can be sampled as they are (as copyLive
/// leaves them, or see samplesAsIs): double, no deleted face, no live vertex
/// outside the live faces, bounding boxes up to date.
template <class MeshA, class MeshB>
DistanceStats distanceAsIs(MeshA& A, MeshB& B, int threads) {
  DistanceStats d;
  const double diag = B.bbox.Diag();
  if (A.fn == 0 || B.fn == 0 || !(diag > 0) || !std::isfinite(diag) || !std::isfinite(A.bbox.Diag())) {
    d.maxRel = d.meanRel = d.maxEdgeRel = std::numeric_limits<double>::infinity();
    return d;
  }
  // A mesh that has run away (e.g. an unguarded run that diverged) would make
  // the sampling grids degenerate and the search quadratic. Far beyond the
  // reference the box distance is a tight enough answer: report that bound.
  double farthest = 0;
  const auto farthestOutside = [&](const auto& M, const vcg::Box3d& other) {
    for (const auto& v : M.vert) {
      if (v.IsD()) continue;
      if (!isFinite(v.cP())) return false;
      vcg::Point3d q = v.cP();
      for (int j = 0; j < 3; ++j) q[j] = std::min(std::max(q[j], other.min[j]), other.max[j]);
      farthest = std::max(farthest, vcg::Distance(q, v.cP()));
    }
    return true;
  };
  if (!farthestOutside(A, B.bbox) || !farthestOutside(B, A.bbox)) {
    d.maxRel = d.meanRel = d.maxEdgeRel = std::numeric_limits<double>::infinity();
    return d;
  }
  if (farthest > kFarDiagonals * diag) {
    d.maxRel = d.maxEdgeRel = farthest / diag;
    d.meanRel = std::numeric_limits<double>::quiet_NaN();
    return d;
  }
  vcg::Box3d u = A.bbox;
  u.Add(B.bbox);
  const double bound = 2.0 * u.Diag() + 1.0;
  // A surface without area has no faces to measure against: use its points.
  SampleMesh Apts, Bpts;
  const bool aFlat = !(totalArea(A) > 0), bFlat = !(totalArea(B) > 0);
  if (aFlat) pointsOnly(A, Apts);
  if (bFlat) pointsOnly(B, Bpts);
  double abEdge = 0, baEdge = 0;
  const auto ab = bFlat ? oneSidedDistance(A, Bpts, bound, threads, true, FaceIndex::Auto, &abEdge)
                        : oneSidedDistance(A, B, bound, threads, true, FaceIndex::Auto, &abEdge);
  const auto ba = aFlat ? oneSidedDistance(B, Apts, bound, threads, true, FaceIndex::Auto, &baEdge)
                        : oneSidedDistance(B, A, bound, threads, true, FaceIndex::Auto, &baEdge);
  d.maxRel = std::max(ab.first, ba.first) / diag;
  d.meanRel = 0.5 * (ab.second + ba.second) / diag;
  d.maxEdgeRel = std::max(d.maxRel, std::max(abEdge, baEdge) / diag);
  return d;
}

}  // namespace detail

/// Total length of the border: the edges of exactly one live face (an edge
/// of three or more faces is not border). 0 for a closed mesh.
template <class MeshType>
double borderLength(const MeshType& m) {
  std::vector<std::pair<std::size_t, std::size_t>> edges;
  for (const auto& f : m.face)
    if (!f.IsD())
      for (int j = 0; j < 3; ++j) {
        const std::size_t a = f.cV(j) - &m.vert[0], b = f.cV((j + 1) % 3) - &m.vert[0];
        edges.emplace_back(std::min(a, b), std::max(a, b));
      }
  std::sort(edges.begin(), edges.end());
  double len = 0;
  for (std::size_t k = 0; k < edges.size();) {
    std::size_t e = k + 1;
    while (e < edges.size() && edges[e] == edges[k]) ++e;
    if (e - k == 1)
      len += (detail::toVec3<MeshType>(m.vert[edges[k].first].cP()) -
              detail::toVec3<MeshType>(m.vert[edges[k].second].cP()))
                 .Norm();
    k = e;
  }
  return len;
}

/// Corner-angle statistics of the live triangles of m, computed in double
/// on threads threads (the result is the same for any number: it is made
/// of counts, extremes and an order statistic).
template <class MeshType>
AngleStats computeAngleStats(const MeshType& m, int threads = 1) {
  AngleStats s;
  const long long nf = static_cast<long long>(m.face.size());
  // Per face its smallest angle; deleted faces get +inf and sort last.
  std::vector<double> triMin(m.face.size());
  double lo = 180, hi = 0;
  long long below30 = 0, above90 = 0, corners = 0, live = 0;
  threads = std::max(1, std::min(threads, 1024));
#pragma omp parallel num_threads(threads) if (threads > 1 && nf >= 8192)
  {
    std::array<long long, 180> hist{};
    double tlo = 180, thi = 0;
    long long tb = 0, ta = 0, tc = 0, tl = 0;
#pragma omp for schedule(static) nowait
    for (long long i = 0; i < nf; ++i) {
      const auto& f = m.face[static_cast<std::size_t>(i)];
      if (f.IsD()) {
        triMin[static_cast<std::size_t>(i)] = std::numeric_limits<double>::infinity();
        continue;
      }
      const Vec3 p[3] = {detail::toVec3<MeshType>(f.cP(0)), detail::toVec3<MeshType>(f.cP(1)),
                         detail::toVec3<MeshType>(f.cP(2))};
      const double a0 = angleBetween(p[1] - p[0], p[2] - p[0]) * kRadToDeg;
      const double a1 = angleBetween(p[2] - p[1], p[0] - p[1]) * kRadToDeg;
      const double a2 = std::max(0.0, 180.0 - a0 - a1);
      const double a[3] = {a0, a1, a2};
      double tmin = 180;
      for (double x : a) {
        if (!std::isfinite(x)) x = 0;  // a triangle too large for double arithmetic counts as degenerate
        tlo = std::min(tlo, x);
        thi = std::max(thi, x);
        tmin = std::min(tmin, x);
        const int bin = std::min(179, std::max(0, static_cast<int>(std::floor(x))));
        ++hist[bin];
        tb += x < 30.0;
        ta += x > 90.0;
        ++tc;
      }
      triMin[static_cast<std::size_t>(i)] = tmin;
      ++tl;
    }
#pragma omp critical(sodtAngleStats)
    {
      for (int b = 0; b < 180; ++b) s.histogram[b] += hist[b];
      lo = std::min(lo, tlo);
      hi = std::max(hi, thi);
      below30 += tb;
      above90 += ta;
      corners += tc;
      live += tl;
    }
  }
  s.faces = live;
  if (s.faces == 0) return s;
  s.minDeg = lo;
  s.maxDeg = hi;
  s.fracBelow30 = double(below30) / double(corners);
  s.fracAbove90 = double(above90) / double(corners);
  const std::size_t idx = static_cast<std::size_t>(std::floor(0.01 * double(live - 1)));
  std::nth_element(triMin.begin(), triMin.begin() + idx, triMin.end());
  s.p1TriMinDeg = triMin[idx];
  return s;
}

/// True when every edge of the live faces is shared by exactly two faces that
/// traverse it in opposite directions (closed, manifold along edges, oriented):
/// no directed edge a->b occurs twice, and each has its reverse b->a. The
/// directed edges are bucketed by their first vertex, so the test is linear
/// in the faces (times the valence), without sorting them all. The buckets
/// are sorted and checked on threads threads.
template <class MeshType>
bool isClosedOriented(const MeshType& m, int threads = 1) {
  if (m.vert.empty()) return false;
  const std::size_t nv = m.vert.size();
  std::vector<int> begin(nv + 1, 0);
  long long halfEdges = 0;
  for (const auto& f : m.face) {
    if (f.IsD()) continue;
    for (int j = 0; j < 3; ++j) ++begin[f.cV(j) - &m.vert[0] + 1];
    halfEdges += 3;
  }
  if (halfEdges == 0) return false;
  for (std::size_t v = 0; v < nv; ++v) begin[v + 1] += begin[v];
  // to[begin[a] .. begin[a + 1]): the ends of the directed edges leaving a.
  std::vector<int> to(static_cast<std::size_t>(halfEdges)), fill(begin.begin(), begin.end() - 1);
  for (const auto& f : m.face) {
    if (f.IsD()) continue;
    for (int j = 0; j < 3; ++j)
      to[fill[f.cV(j) - &m.vert[0]]++] = static_cast<int>(f.cV((j + 1) % 3) - &m.vert[0]);
  }
  threads = std::max(1, std::min(threads, 1024));
  const long long n = static_cast<long long>(nv);
  bool twice = false;  // a directed edge occurs twice
#pragma omp parallel for num_threads(threads) schedule(static) reduction(|| : twice) if (threads > 1 && n >= 8192)
  for (long long a = 0; a < n; ++a) {
    const auto first = to.begin() + begin[a], last = to.begin() + begin[a + 1];
    std::sort(first, last);
    twice = twice || std::adjacent_find(first, last) != last;
  }
  if (twice) return false;
  bool unpaired = false;  // a directed edge without its reverse
#pragma omp parallel for num_threads(threads) schedule(static) reduction(|| : unpaired) if (threads > 1 && n >= 8192)
  for (long long a = 0; a < n; ++a)
    for (int k = begin[a]; k < begin[a + 1] && !unpaired; ++k) {
      const int b = to[k];
      unpaired = !std::binary_search(to.begin() + begin[b], to.begin() + begin[b + 1], static_cast<int>(a));
    }
  return !unpaired;
}

/// Enclosed volume by the divergence theorem, in double, relative to the
/// bounding-box centre to limit cancellation. threads: for the closedness
/// test (the sum is serial, so the volume is the same for any number).
template <class MeshType>
VolumeResult enclosedVolume(const MeshType& m, int threads = 1) {
  VolumeResult r;
  r.closed = isClosedOriented(m, threads);
  if (!r.closed) return r;
  Vec3 lo(std::numeric_limits<double>::max(), std::numeric_limits<double>::max(),
          std::numeric_limits<double>::max());
  Vec3 hi = -lo;
  for (const auto& v : m.vert) {
    if (v.IsD()) continue;
    const Vec3 p = detail::toVec3<MeshType>(v.cP());
    for (int j = 0; j < 3; ++j) {
      lo[j] = std::min(lo[j], p[j]);
      hi[j] = std::max(hi[j], p[j]);
    }
  }
  const Vec3 o = (lo + hi) * 0.5;
  double vol = 0, comp = 0;  // Kahan summation
  for (const auto& f : m.face) {
    if (f.IsD()) continue;
    const Vec3 a = detail::toVec3<MeshType>(f.cP(0)) - o, b = detail::toVec3<MeshType>(f.cP(1)) - o,
               c = detail::toVec3<MeshType>(f.cP(2)) - o;
    const double term = (a * (b ^ c)) / 6.0 - comp;
    const double t = vol + term;
    comp = (t - vol) - term;
    vol = t;
  }
  r.volume = vol;
  return r;
}

/// Bounding box of the mesh's surface: the vertices of its live faces (of
/// all live vertices when it has no face). Unreferenced vertices, which the
/// smoother keeps untouched, do not change the mesh's size: not the
/// deviation bound, not a relative distance.
template <class MeshType>
vcg::Box3d surfaceBox(const MeshType& m) {
  vcg::Box3d b;
  bool anyFace = false;
  for (const auto& f : m.face)
    if (!f.IsD()) {
      anyFace = true;
      for (int j = 0; j < 3; ++j) b.Add(detail::toVec3<MeshType>(f.cV(j)->cP()));
    }
  if (!anyFace)
    for (const auto& v : m.vert)
      if (!v.IsD()) b.Add(detail::toVec3<MeshType>(v.cP()));
  return b;
}

/// Length of the diagonal of surfaceBox(m) (0 for an empty mesh).
template <class MeshType>
double bboxDiagonal(const MeshType& m) {
  const vcg::Box3d b = surfaceBox(m);
  return b.IsNull() ? 0.0 : b.Diag();
}

/// Symmetric surface distance between a and b by vcglib's point sampling
/// (every vertex plus max(10000, 2F) area-uniform samples each way, capped at
/// kMaxVertexSamples and kMaxFaceSamples; fixed seed, so the result is
/// repeatable), relative to b's bounding-box diagonal.
/// Neither mesh is modified: both are copied (positions and triangles, into
/// SampleMesh). Returns +inf when a mesh has no faces or a non-finite
/// coordinate. When a vertex lies more than kFarDiagonals diagonals outside
/// the other mesh's bounding box, maxRel is that box distance (a lower bound
/// of the Hausdorff distance) and meanRel is NaN. The samples are looked up
/// on threads threads, with the same result for any number.
template <class MeshA, class MeshB>
DistanceStats surfaceDistance(const MeshA& a, const MeshB& b, int threads = 1) {
  SampleMesh A, B;
  detail::copyLive(a, A);
  detail::copyLive(b, B);
  return detail::distanceAsIs(A, B, threads);
}

/// surfaceDistance(a, b), the same result bit for bit, without copying a
/// mesh that can be sampled as it is (no deleted face, and no live vertex
/// outside the live faces; any other is copied as surfaceDistance copies it).
/// For a multi-million vertex mesh this saves the copies' memory. a and b are
/// double meshes (MeshD or SampleMesh). A mesh sampled in place gets its
/// bounding box updated and its face normals normalized (vcglib's point-face
/// distance needs them); its positions, faces, vertex
/// normals, quality, colour and flags are left alone.
template <class MeshA, class MeshB>
DistanceStats surfaceDistanceInPlace(MeshA& a, MeshB& b, int threads = 1) {
  const bool copyA = !detail::samplesAsIs(a), copyB = !detail::samplesAsIs(b);
  SampleMesh A, B;
  if (copyA)
    detail::copyLive(a, A);
  else
    vcg::tri::UpdateBounding<MeshA>::Box(a);
  if (copyB)
    detail::copyLive(b, B);
  else
    vcg::tri::UpdateBounding<MeshB>::Box(b);
  if (copyA && copyB) return detail::distanceAsIs(A, B, threads);
  if (copyA) return detail::distanceAsIs(A, b, threads);
  if (copyB) return detail::distanceAsIs(a, B, threads);
  return detail::distanceAsIs(a, b, threads);
}

/// Symmetric Hausdorff distance relative to b's bounding-box diagonal.
template <class MeshA, class MeshB>
double hausdorffRel(const MeshA& a, const MeshB& b) {
  return surfaceDistance(a, b).maxRel;
}

namespace detail {

template <class MeshType>
std::vector<Vec3> positions(const MeshType& m) {
  std::vector<Vec3> pos(m.vert.size());
  for (std::size_t i = 0; i < m.vert.size(); ++i) pos[i] = toVec3<MeshType>(m.vert[i].cP());
  return pos;
}

}  // namespace detail

/// Number of live faces of m that face away from the surface of ref under
/// them: each against the face of ref nearest its centroid (of those
/// equally near, up to rounding, the best aligned; InputGrid::under), for
/// meshes whose faces do not correspond to ref's (after edge flips or a
/// repair that added or removed vertices). A face counts when its normal
/// and that face's are more than 90 degrees apart; when that face is a
/// face of ref folded against the surface at its corners
/// (foldedFaceSurfaceNormals), only when it also faces away from that
/// surface: either side is a valid orientation there, and moves or a
/// filter may unfold such a fold. Faces without area face nowhere and are left out
/// (the input's degenerate faces among them, which crease moves may shift
/// along their line). maxTurnDeg, when not null, receives the largest angle
/// between a face and its face of ref (the nearer of a folded face's two
/// orientations; 0 when none). Counts on threads threads, with the same
/// result for any number.
template <class MeshType, class RefType>
long long countFacesFacingAway(const MeshType& m, const RefType& ref, int threads = 1, double* maxTurnDeg = nullptr) {
  const FacingInput input(detail::positions(ref), makeFaceList(ref));
  long long n = 0;
  double worst = 0;
  const long long nf = static_cast<long long>(m.face.size());
  threads = std::max(1, std::min(threads, 1024));
#pragma omp parallel for num_threads(threads) schedule(static) reduction(+ : n) reduction(max : worst) \
    if (threads > 1 && nf >= 8192)
  for (long long i = 0; i < nf; ++i) {
    const auto& f = m.face[static_cast<std::size_t>(i)];
    if (f.IsD()) continue;
    const FacingInput::Verdict v = input.test(detail::toVec3<MeshType>(f.cP(0)), detail::toVec3<MeshType>(f.cP(1)),
                                              detail::toVec3<MeshType>(f.cP(2)));
    if (!v.measured) continue;
    n += v.away;
    worst = std::max(worst, v.turnRad);
  }
  if (maxTurnDeg) *maxTurnDeg = worst * kRadToDeg;
  return n;
}

/// Number of faces of m turned by more than 90 degrees from ref: face by
/// face while the face lists correspond (the same sizes and vertex
/// indices), a face counting also when it collapsed to zero area while the
/// face of ref had area; else each face against the face of ref under it
/// (countFacesFacingAway). Face by face too, a face over a face of ref
/// folded against the surface at its corners counts only when it also
/// faces away from that surface. faceByFace, when not null, receives which
/// of the two it measured. Counts on threads threads.
template <class MeshType, class RefType>
long long countInvertedFaces(const MeshType& m, const RefType& ref, int threads = 1, bool* faceByFace = nullptr) {
  if (faceByFace) *faceByFace = false;
  if (m.face.size() != ref.face.size() || m.vert.size() != ref.vert.size())
    return countFacesFacingAway(m, ref, threads);
  long long n = 0;
  bool differ = false;
  const long long nf = static_cast<long long>(m.face.size());
  threads = std::max(1, std::min(threads, 1024));
  const std::vector<Vec3> folded = foldedFaceSurfaceNormals(makeFaceList(ref), detail::positions(ref));
#pragma omp parallel for num_threads(threads) schedule(static) reduction(+ : n) reduction(|| : differ) \
    if (threads > 1 && nf >= 8192)
  for (long long i = 0; i < nf; ++i) {
    const auto& f = m.face[static_cast<std::size_t>(i)];
    const auto& g = ref.face[static_cast<std::size_t>(i)];
    if (differ || f.IsD() || g.IsD()) continue;
    bool same = true;
    for (int j = 0; j < 3; ++j) same = same && f.cV(j) - &m.vert[0] == g.cV(j) - &ref.vert[0];
    if (!same) {
      differ = true;
      continue;
    }
    const Vec3 nf3 = doubleAreaVector(detail::toVec3<MeshType>(f.cP(0)), detail::toVec3<MeshType>(f.cP(1)),
                                      detail::toVec3<MeshType>(f.cP(2)));
    const Vec3 ng3 = doubleAreaVector(detail::toVec3<RefType>(g.cP(0)), detail::toVec3<RefType>(g.cP(1)),
                                      detail::toVec3<RefType>(g.cP(2)));
    if (nf3.SquaredNorm() == 0) {
      n += ng3.SquaredNorm() > 0;
      continue;
    }
    const Vec3& other = folded[static_cast<std::size_t>(i)];
    n += nf3 * ng3 < 0 && !(other.SquaredNorm() > 0 && !(nf3 * other < 0));
  }
  if (differ) return countFacesFacingAway(m, ref, threads);
  if (faceByFace) *faceByFace = true;
  return n;
}

}  // namespace sodt
