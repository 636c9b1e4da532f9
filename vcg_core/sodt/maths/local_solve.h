// SPDX-License-Identifier: GPL-3.0-or-later
// The S-ODT vertex update on a one-ring star: tangent plane (paper Eq. 4),
// quadratic coefficients (Eq. 8), 2x2 solve (Eq. 7), and the move guards.
#pragma once

#include "geometry.h"

#include <cmath>
#include <cstddef>
#include <limits>
#include <vector>

namespace sodt {

/// One-ring of an interior vertex. Triangle k is (center, ring[k], ring[k+1])
/// with indices taken cyclically, in the orientation of the mesh faces.
struct Star {
  Vec3 center;
  std::vector<Vec3> ring;
  /// Optional unit normals of the star's triangles in the input mesh (zero
  /// for a triangle that was degenerate there); the fold guard keeps every
  /// triangle within 90 degrees of these so that no face ends up inverted,
  /// and within the angle of maxTurnCos2.
  std::vector<Vec3> refNormal;
  /// Squared cosine of the largest turn from refNormal the guard allows
  /// (faceTurnCos2 of SodtParams::maxFaceTurnDeg); 0 for 90 degrees.
  double maxTurnCos2 = 0;

  std::size_t size() const { return ring.size(); }
  /// ring[k] for k in [0, 2 size()): the cyclic successor of the last entry is the first.
  const Vec3& at(std::size_t k) const { return ring[k < ring.size() ? k : k - ring.size()]; }
};

/// The squared cosine of a largest face turn of deg degrees, for
/// turnsBeyond: 0 from 90 degrees on, where the test is the sign test of
/// the fold guard alone, exactly (cos(90 deg) is not 0 in double).
inline double faceTurnCos2(double deg) {
  if (!(deg < 90)) return 0.0;
  const double c = std::cos(deg * kPi / 180.0);
  return c * c;
}

/// True when the area vector a of a triangle turns against ref (a unit
/// normal, or zero for none) or by more than the angle whose squared cosine
/// is maxTurnCos2 (faceTurnCos2): a.ref < 0, or (a.ref)^2 < maxTurnCos2
/// |a|^2 |ref|^2 without a square root. Never true for a zero ref; with
/// maxTurnCos2 = 0 the sign test alone. The AVX2 form
/// (lanes::detail::triangleAllowed) computes the same products in the same
/// order.
inline bool turnsBeyond(const Vec3& a, const Vec3& ref, double maxTurnCos2) {
  const double d = a * ref;
  return d < 0 || d * d < maxTurnCos2 * a.SquaredNorm() * ref.SquaredNorm();
}

/// Result of the local solve.
struct LocalMove {
  bool ok = false;  ///< false: degenerate star, or the quadratic is not convex
  Vec3 target;      ///< minimiser x* (equal to the centre when !ok)
  Vec3 normal;      ///< unit normal n of the tangent plane
};

/// Coefficients of the quadratic of Eq. 5 restricted to the plane
/// x' = x0 + u s + v t: its minimiser solves [2E G; G 2F] (u v)^T = (H I)^T.
struct SodtSystem {
  double C = 0, E = 0, F = 0, G = 0, H = 0, I = 0;
};

/// Unit normal of the tangent plane (Eq. 4): the area-weighted mean of the
/// face normals, i.e. the normalised sum of the triangles' area vectors.
/// Returns the zero vector when that sum vanishes.
inline Vec3 starNormal(const Star& st) {
  const std::size_t n = st.size();
  if (n == 0) return Vec3(0, 0, 0);
  Vec3 sum(0, 0, 0);
  const Vec3 first = st.ring[0] - st.center;
  Vec3 a = first;
  for (std::size_t k = 0; k < n; ++k) {
    const Vec3 b = k + 1 < n ? st.ring[k + 1] - st.center : first;
    sum += a ^ b;
    a = b;
  }
  const double len = sum.Norm();
  if (!(len > 0) || !std::isfinite(len)) return Vec3(0, 0, 0);
  return sum * (1.0 / len);
}

/// D'_k = det(x_k - p, x_{k+1} - p, n): signed area of triangle k with the
/// centre at p, projected on the plane of normal n (doubled).
inline double projectedDoubleArea(const Star& st, std::size_t k, const Vec3& p, const Vec3& n) {
  return ((st.at(k) - p) ^ (st.at(k + 1) - p)) * n;
}

/// The objective of Eq. 5 with the centre at p, evaluated term by term.
/// Used by tests to check the closed form; O(N).
inline double sodtEnergy(const Star& st, const Vec3& p, const Vec3& n) {
  double e = 0;
  for (std::size_t k = 0; k < st.size(); ++k) {
    const Vec3 a = st.at(k) - p, b = st.at(k + 1) - p, c = st.at(k + 1) - st.at(k);
    e += (a.SquaredNorm() + b.SquaredNorm() + c.SquaredNorm()) * projectedDoubleArea(st, k, p, n);
  }
  return e;
}

/// Coefficients of Eq. 8 in the frame (s, t, n), relative to the centre.
///
/// With X_k = x_k - x0, e_k = X_{k+1} - X_k and w_k = e_k x n, the projected
/// area is D'_k = c_k - p.w_k with c_k = det(X_k, X_{k+1}, n); the cubic terms
/// cancel because sum_k D'_k = C is constant (Appendix B), leaving a quadratic.
inline SodtSystem sodtCoefficients(const Star& st, const Vec3& n, const Vec3& s, const Vec3& t) {
  // In the frame (s, t, n) the products of Eq. 8 become planar: with
  // X = (x, y, z), w_k = e_k x n has s.w = e_y and t.w = -e_x, and
  // c_k = x_a y_b - y_a x_b. Each ring vertex is projected once.
  SodtSystem q;
  const std::size_t N = st.size();
  if (N == 0) return q;
  struct Local {
    double x, y, z, len2;
  };
  const auto local = [&](const Vec3& P) {
    const Vec3 X = P - st.center;
    const Local l{s * X, t * X, n * X, X.SquaredNorm()};
    return l;
  };
  const Local first = local(st.ring[0]);
  Local a = first;
  for (std::size_t k = 0; k < N; ++k) {
    const Local b = k + 1 < N ? local(st.ring[k + 1]) : first;
    const double sw = b.y - a.y, tw = a.x - b.x;  // s.w and t.w
    const double c = a.x * b.y - a.y * b.x;
    const double ss = a.x + b.x, ts = a.y + b.y;
    const double r = a.len2 + b.len2 - (a.x * b.x + a.y * b.y + a.z * b.z);
    q.C += c;
    q.E += ss * sw;
    q.F += ts * tw;
    q.G += ss * tw + ts * sw;
    q.H += ss * c + r * sw;
    q.I += ts * c + r * tw;
    a = b;
  }
  q.E += q.C;
  q.F += q.C;
  return q;
}

/// Closed-form S-ODT minimiser of Eq. 5 over the tangent plane of Eq. 4
/// (Algorithm 1, one vertex). Computed in double; never returns NaN.
/// \return ok=false when the star is degenerate or the quadratic is not
///         strictly convex (Hessian test E > 0 and 4EF > G^2).
inline LocalMove solveStar(const Star& st, const Vec3& normal) {
  LocalMove mv;
  mv.target = st.center;
  if (st.size() < 3) return mv;
  mv.normal = normal;
  if (mv.normal.SquaredNorm() == 0) return mv;
  Vec3 s, t;
  tangentFrame(mv.normal, s, t);
  const SodtSystem q = sodtCoefficients(st, mv.normal, s, t);
  const double det = 4 * q.E * q.F - q.G * q.G;
  // Relative test: a determinant at rounding level is singular in practice.
  const double scale = 4 * std::abs(q.E * q.F) + q.G * q.G;
  if (!(q.E > 0) || !(det > kSingularRel * scale)) return mv;
  const double inv = 1.0 / det;
  const double u = (2 * q.F * q.H - q.G * q.I) * inv;
  const double v = (2 * q.E * q.I - q.G * q.H) * inv;
  const Vec3 target = st.center + s * u + t * v;
  if (!isFinite(target)) return mv;
  mv.ok = true;
  mv.target = target;
  return mv;
}

/// solveStar with the tangent plane of Eq. 4 computed here.
inline LocalMove solveStar(const Star& st) { return solveStar(st, starNormal(st)); }

/// The objective of Eq. 5 as a quadratic over all of R^3, for a fixed unit
/// vector n in D'_k: E(center + p) = p^T Q p + g . p + const. It is exact for
/// every p (not only in the plane through the centre), because sum_k D'_k is
/// constant for any p (Appendix B) and D'_k is affine in p.
struct StarQuadratic {
  double Q[3][3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
  Vec3 g = Vec3(0, 0, 0);

  double quad(const Vec3& a, const Vec3& b) const {  // a^T Q b
    double r = 0;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) r += a[i] * Q[i][j] * b[j];
    return r;
  }
  Vec3 apply(const Vec3& a) const {
    Vec3 r(0, 0, 0);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) r[i] += Q[i][j] * a[j];
    return r;
  }
};

/// Builds the quadratic of Eq. 5 relative to the star's centre.
///
/// With X_k = x_k - x0, e_k = X_{k+1} - X_k, w_k = e_k x n, c_k = det(X_k, X_{k+1}, n),
/// S_k = X_k + X_{k+1}, A_k = |X_k|^2 + |X_{k+1}|^2 + |e_k|^2 and C = sum c_k:
/// E(x0 + p) = 2 C |p|^2 + sum_k (A_k - 2 p.S_k)(c_k - p.w_k), so
/// Q = 2 C I + sum_k (S_k w_k^T + w_k S_k^T) and g = -sum_k (2 c_k S_k + A_k w_k).
/// Summed over the faces (center, at(k), at(k + 1)) for k < faces: a
/// closed star (sodtQuadratic) or an open fan (boundary.h).
template <class RingAt>
StarQuadratic fanQuadratic(const Vec3& center, std::size_t faces, RingAt at, const Vec3& n) {
  StarQuadratic q;
  double C = 0;
  for (std::size_t k = 0; k < faces; ++k) {
    const Vec3 Xa = at(k) - center, Xb = at(k + 1) - center;
    const Vec3 e = Xb - Xa, w = e ^ n, S = Xa + Xb;
    const double c = (Xa ^ Xb) * n;
    const double A = Xa.SquaredNorm() + Xb.SquaredNorm() + e.SquaredNorm();
    C += c;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) q.Q[i][j] += S[i] * w[j] + w[i] * S[j];
    q.g -= S * (2 * c) + w * A;
  }
  for (int i = 0; i < 3; ++i) q.Q[i][i] += 2 * C;
  return q;
}

/// fanQuadratic over a closed star.
inline StarQuadratic sodtQuadratic(const Star& st, const Vec3& n) {
  return fanQuadratic(st.center, st.size(), [&st](std::size_t k) -> const Vec3& { return st.at(k); }, n);
}

/// Minimiser of the quadratic over the line centre + p0 + d e (e a unit
/// vector), written to p (relative to the centre). False when the quadratic
/// is not strictly convex along e.
///
/// With the coefficients of the paper's Eq. 11 for p0 = 0, A = e^T Q e / 2 and
/// B = -g.e / 2, the minimiser is d* = +B / (2A): the printed "d* = -B/(2A)"
/// has the wrong sign (it is a maximiser's mirror image and diverges).
inline bool minimizeOnLine(const StarQuadratic& q, const Vec3& p0, const Vec3& e, Vec3& p) {
  const double a = q.quad(e, e);
  const double b = e * (q.g + q.apply(p0) * 2.0);
  const double scale = std::abs(q.Q[0][0]) + std::abs(q.Q[1][1]) + std::abs(q.Q[2][2]);
  if (!(a > kSingularRel * scale)) return false;
  const double d = -b / (2 * a);
  p = p0 + e * d;
  return isFinite(p);
}

/// Minimiser of the quadratic over the plane centre + p0 + u s + v t, written
/// to p (relative to the centre). False when not strictly convex there.
inline bool minimizeOnPlane(const StarQuadratic& q, const Vec3& p0, const Vec3& s, const Vec3& t, Vec3& p) {
  const double qss = q.quad(s, s), qtt = q.quad(t, t), qst = q.quad(s, t);
  const Vec3 grad = q.g + q.apply(p0) * 2.0;
  const double rs = -(s * grad), rt = -(t * grad);
  // 2 [qss qst; qst qtt] (u v)^T = (rs rt)^T
  const double det = qss * qtt - qst * qst;
  const double scale = std::abs(qss * qtt) + qst * qst;
  if (!(qss > 0) || !(det > kSingularRel * scale)) return false;
  const double u = (qtt * rs - qst * rt) / (2 * det);
  const double v = (qss * rt - qst * rs) / (2 * det);
  p = p0 + s * u + t * v;
  return isFinite(p);
}

/// Centroid of the star's ring.
inline Vec3 ringCentroid(const Star& st) {
  Vec3 centroid(0, 0, 0);
  for (const Vec3& q : st.ring) centroid += q;
  centroid /= double(st.size());
  return centroid;
}

/// Moves x back along the unit vector dir to within lim of the height of
/// centre (Algorithm 3's bound on the move along the fitted normal).
inline void boundNormalStep(Vec3& x, const Vec3& centre, const Vec3& dir, double lim) {
  const double h = (x - centre) * dir;
  if (std::abs(h) > lim) x -= dir * (h - (h > 0 ? lim : -lim));
}

/// Algorithm 3's move of a smooth vertex (paper Sec. 2.5): the minimiser of
/// Eq. 5 (with dir in D'_k) over the fitted plane through point with unit
/// normal dir, and its fallback, the ring centroid shifted into that plane
/// along dir; both bounded to lim along dir (boundNormalStep). False when
/// the quadratic is not strictly convex on the plane or a result is not
/// finite (target and fallback may be written then).
inline bool denoiseTargets(const Star& st, const Vec3& point, const Vec3& dir, double lim, Vec3& target,
                           Vec3& fallback) {
  const Vec3 centroid = ringCentroid(st);
  const StarQuadratic q = sodtQuadratic(st, dir);
  Vec3 s, t, p;
  tangentFrame(dir, s, t);
  const Vec3 p0 = point - st.center;
  if (!minimizeOnPlane(q, p0, s, t, p)) return false;
  const Vec3 d = centroid - st.center - p0;
  fallback = point + d - dir * (d * dir);
  target = st.center + p;
  boundNormalStep(target, st.center, dir, lim);
  boundNormalStep(fallback, st.center, dir, lim);
  return isFinite(target) && isFinite(fallback);
}

/// Smallest interior angle (radians) over the triangles of the star with the
/// centre placed at p.
inline double starMinAngle(const Star& st, const Vec3& p) {
  double m = kPi;
  for (std::size_t k = 0; k < st.size(); ++k)
    m = std::min(m, triangleMinAngle(p, st.at(k), st.at(k + 1)));
  return m;
}

/// Squared cosine of the smallest angle over the star's triangles with the
/// centre at p (see triangleMinAngleCos2); larger means worse.
inline double starMinAngleCos2(const Star& st, const Vec3& p) {
  double c = 0;
  for (std::size_t k = 0; k < st.size(); ++k) c = std::max(c, triangleMinAngleCos2(p, st.at(k), st.at(k + 1)));
  return c;
}

/// True when, with the centre at p, no triangle of the star has a smaller
/// smallest angle than the one whose squared cosine is cos2Limit.
inline bool starKeepsMinAngle(const Star& st, const Vec3& p, double cos2Limit) {
  for (std::size_t k = 0; k < st.size(); ++k)
    if (triangleMinAngleCos2(p, st.at(k), st.at(k + 1)) > cos2Limit) return false;
  return true;
}

/// Fold test and, when quality is set, the smallest-angle test of
/// starKeepsMinAngle in one pass over the star: true when moving the centre
/// to p neither folds nor collapses a triangle (see moveFolds) nor gives one
/// a smaller smallest angle than the one with squared cosine cos2Limit.
/// ringEdge2[k] is |ring[k+1] - ring[k]|^2, which no move changes.
///
/// witness, when not null, is the triangle to test first (any index; the
/// answer does not depend on it) and receives the triangle that failed:
/// successive candidates of one vertex tend to fail on the same triangle.
inline bool moveAllowed(const Star& st, const Vec3& p, const std::vector<Vec3>& cur,
                        const std::vector<double>& ringEdge2, bool quality, double cos2Limit,
                        int* witness = nullptr) {
  const bool haveRef = st.refNormal.size() == st.size();
  const std::size_t n = st.size();
  if (n == 0) return true;
  const std::size_t k0 = witness && *witness > 0 && std::size_t(*witness) < n ? std::size_t(*witness) : 0;
  Vec3 u = st.ring[k0] - p;
  double uu = u.SquaredNorm();
  for (std::size_t t = 0, k = k0; t < n; ++t) {
    const std::size_t k1 = k + 1 < n ? k + 1 : 0;
    const Vec3 w = st.ring[k1] - p;
    const double ww = w.SquaredNorm();
    const Vec3 next = u ^ w;  // doubled area vector of (p, a, b)
    bool ok = next * cur[k] > 0 && !(haveRef && turnsBeyond(next, st.refNormal[k], st.maxTurnCos2));
    const double ee = ringEdge2[k];
    if (ok) {
      const double l2 = std::max({uu, ww, ee});
      ok = next.SquaredNorm() > kCollapse * kCollapse * l2 * l2;
    }
    if (ok && quality) {
      // The smallest angle is opposite the shortest edge (as triangleMinAngleCos2).
      double dot, l1, l3;
      const double uw = u * w;
      if (ee <= uu && ee <= ww) {
        dot = uw, l1 = uu, l3 = ww;  // corner at p
      } else if (ww <= uu) {
        dot = uu - uw, l1 = uu, l3 = ee;  // corner at a: (p - a).(b - a) = |u|^2 - u.w
      } else {
        dot = ww - uw, l1 = ww, l3 = ee;  // corner at b: (p - b).(a - b) = |w|^2 - u.w
      }
      const double den = l1 * l3;
      const double c2 = !(den > 0) ? 1.0 : (dot <= 0 ? 0.0 : std::min(1.0, dot * dot / den));
      ok = !(c2 > cos2Limit);
    }
    if (!ok) {
      if (witness) *witness = static_cast<int>(k);
      return false;
    }
    u = w;
    uu = ww;
    k = k1;
  }
  return true;
}

/// |ring[k+1] - ring[k]|^2 for every k, for moveAllowed.
inline void ringEdgeLengths2(const Star& st, std::vector<double>& out) {
  out.resize(st.size());
  for (std::size_t k = 0; k < st.size(); ++k) out[k] = (st.at(k + 1) - st.at(k)).SquaredNorm();
}

/// What moveAllowed needs for every step length of one visit, in one pass
/// over the star: per triangle the orientation reference of the fold test
/// in cur (its doubled area vector now, or the plane normal n for a
/// triangle that is degenerate now: area at most kCollapse times its
/// longest edge squared), ringEdgeLengths2(st, ringEdge2), and, when
/// quality is set, returns starMinAngleCos2(st, st.center) (else 1), bit
/// for bit: each spoke and ring edge is computed once and shared by the
/// triangles beside it (p - a is -(a - p) exactly, so the dot products only
/// change sign).
inline double prepareGuard(const Star& st, const Vec3& n, bool quality, std::vector<Vec3>& cur,
                           std::vector<double>& ringEdge2) {
  const std::size_t size = st.size();
  cur.resize(size);
  ringEdge2.resize(size);
  if (size == 0) return quality ? 0.0 : 1.0;
  double worst = 0;
  Vec3 u = st.ring[0] - st.center;
  double uu = u.SquaredNorm();
  for (std::size_t k = 0; k < size; ++k) {
    const Vec3& a = st.ring[k];
    const Vec3& b = st.ring[k + 1 < size ? k + 1 : 0];
    const Vec3 w = b - st.center, e = b - a;
    const double ww = w.SquaredNorm(), ee = e.SquaredNorm();
    ringEdge2[k] = ee;
    const Vec3 now = u ^ w;
    cur[k] = now.Norm() > kCollapse * std::max({uu, ww, ee}) ? now : n;
    if (quality) {
      // triangleMinAngleCos2(centre, a, b): the corner opposite the shortest edge.
      const double eu = e * u, ew = e * w, uw = u * w;
      const bool atCentre = ee <= uu && ee <= ww, atA = !atCentre && ww <= uu;
      const double dot = atCentre ? uw : atA ? -eu : ew;
      const double den = atCentre ? uu * ww : atA ? ee * uu : ww * ee;
      const double c2 = !(den > 0) ? 1.0 : dot <= 0 ? 0.0 : std::min(1.0, dot * dot / den);
      worst = std::max(worst, c2);
    }
    u = w;
    uu = ww;
  }
  return quality ? worst : 1.0;
}

/// True when moving the centre from st.center to p flips or collapses a
/// triangle of the star. A triangle collapses when its area falls to rounding
/// level relative to its longest edge; it flips when its area vector turns
/// against the one it has now (or against the plane normal n, for a triangle
/// that is degenerate now), or against its input normal st.refNormal[k] or
/// further from it than st.maxTurnCos2 allows (turnsBeyond). The fold test
/// of moveAllowed alone, for a single position.
inline bool moveFolds(const Star& st, const Vec3& p, const Vec3& n) {
  std::vector<Vec3> cur;
  std::vector<double> ringEdge2;
  prepareGuard(st, n, false, cur, ringEdge2);
  return !moveAllowed(st, p, cur, ringEdge2, false, 1.0);
}

/// Tangential Laplacian target: the centroid of the ring projected on the
/// plane through the centre with normal n (Eq. 3 with every S'_k = 1,
/// restricted to the tangent plane).
inline Vec3 tangentialLaplacianTarget(const Star& st, const Vec3& n) {
  Vec3 c(0, 0, 0);
  for (const Vec3& q : st.ring) c += q;
  c /= double(st.size());
  const Vec3 d = c - st.center;
  return st.center + d - n * (d * n);
}

}  // namespace sodt
