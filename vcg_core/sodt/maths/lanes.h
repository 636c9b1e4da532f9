// SPDX-License-Identifier: GPL-3.0-or-later
// The Algorithm 1 target (tangent plane of Eq. 4, minimiser of Eq. 5) for
// four vertices at once, one per AVX2 lane, or Algorithm 3's (the minimiser
// on each vertex's fitted plane), and the move guard's test of the full
// step to it; and the guard's test of up to four step lengths of one vertex
// at once (allowedAt). Every lane performs the operations of starNormal,
// solveStar (or denoiseTargets), prepareGuard and moveAllowed (local_solve.h)
// in the same order, with no fused multiply-add, so each lane's result is
// bit for bit the one the scalar code gives. Builds without x86 GCC/Clang, or with SODT_NO_LANES
// defined, have no kernel and use the scalar code.
#pragma once

#include "geometry.h"

#include <limits>

#if !defined(SODT_NO_LANES) && (defined(__GNUC__) || defined(__clang__)) && \
    (defined(__x86_64__) || defined(__i386__))
#define SODT_HAVE_LANES 1
#include <immintrin.h>
#endif

namespace sodt {
namespace lanes {

/// Vertices per call.
constexpr int kWidth = 4;
/// Largest valence the kernel takes (its ring is kept in registers and on
/// the stack); rarer, larger stars go through the scalar code.
constexpr int kMaxValence = 12;

/// Output of targets4.
struct Targets {
  double x[kWidth], y[kWidth], z[kWidth];
  /// With a DenoiseInput: the fallback of denoiseTargets, when ok.
  double fx[kWidth], fy[kWidth], fz[kWidth];
  /// The unit normal of the tangent plane (starNormal), when ok.
  double nx[kWidth], ny[kWidth], nz[kWidth];
  /// Bit l set: lane l's solve succeeded (solveStar's ok) and its target is
  /// (x[l], y[l], z[l]); clear: the solve failed and the target is unset.
  int ok = 0;
};

/// What targets4 needs to compute Algorithm 3's move of smooth vertices
/// instead of Algorithm 1's (denoiseTargets in local_solve.h): vertex v's
/// fitted plane has its point's x, y, z at point + stride * v and its unit
/// normal's at dir + stride * v; lim bounds the move along that normal.
struct DenoiseInput {
  const double* point = nullptr;
  const double* dir = nullptr;
  int stride = 0;
  double lim = 0;
};

/// What targets4 needs to test the full step of each lane under the move
/// guard (see Targets::allowed).
struct GuardInput {
  /// x, y, z doubles per face: the input normals the fold test keeps every
  /// triangle within 90 degrees of (Star::refNormal), or null for none.
  const double* faceNormal = nullptr;
  /// With faceNormal: the largest turn from it allowed, as Star::maxTurnCos2.
  double maxTurnCos2 = 0;
  bool quality = false;       ///< the smallest-angle test as well as the fold test
  bool roundToFloat = false;  ///< the mesh stores float coordinates
};

/// The full step's verdict, written by targets4 when given a GuardInput.
/// The full step is the target rounded to what the mesh stores: y = c +
/// (target - c), through float when GuardInput::roundToFloat. Its verdict
/// is moveAllowed's for the star at y, with the references and limit of
/// prepareGuard (local_solve.h), bit for bit.
struct StepVerdict {
  double x[4], y[4], z[4];  ///< y per lane
  /// Bit l set: y is finite, differs from the centre, and moveAllowed accepts it.
  int allowed = 0;
  /// Bit l set: y is finite, differs from the centre, and moveAllowed refuses
  /// it; first[l] is the first triangle that fails. Lanes with neither bit
  /// set (failed solve, y not finite or equal to the centre) are undecided.
  int refused = 0;
  int first[4];
};

/// What prepareGuard (local_solve.h) returns for each lane of a group, bit
/// for bit, written by targets4 when asked: lane l's fold reference of star
/// triangle k is (cx[k][l], cy[k][l], cz[k][l]), its squared ring edge
/// ee[k][l], and the returned angle limit limit[l].
struct Prepared {
  double cx[kMaxValence][kWidth], cy[kMaxValence][kWidth], cz[kMaxValence][kWidth];
  double ee[kMaxValence][kWidth];
  double limit[kWidth];
};

static_assert(sizeof(Vec3) == 3 * sizeof(double), "positions must be packed x, y, z doubles");

/// Output of faceKeys4.
struct FaceKeys {
  double key[kWidth];
  /// Bit l set: face l's area vector points against its reference normal.
  int inverted = 0;
};

/// True when this build has the kernel and the processor can run it.
inline bool available() {
#ifdef SODT_HAVE_LANES
  static const bool ok = __builtin_cpu_supports("avx2") != 0;
  return ok;
#else
  return false;
#endif
}

/// Writes the index table of a group for targets4: (n + 1) rows of kWidth
/// entries, row 0 the lanes' centres, row k + 1 their k-th ring vertices
/// (star l has centre centre[l] and ring ringIdx[begin[l] + k], k < n, in
/// cyclic order), each index times 3, the offset of its x in pos. When
/// ringFace is not null, n more rows follow for the guard's full-step test
/// (see StepVerdict): row n + 1 + k holds the lanes' k-th star triangles,
/// ringFace[begin[l] + k] times 3, the offset of its x in
/// GuardInput::faceNormal.
inline void packGroup(const int* centre, const int* ringIdx, const int* begin, int n, int* table,
                      const int* ringFace = nullptr) {
  for (int l = 0; l < kWidth; ++l) {
    table[l] = 3 * centre[l];
    for (int k = 0; k < n; ++k) table[kWidth * (k + 1) + l] = 3 * ringIdx[begin[l] + k];
    if (ringFace)
      for (int k = 0; k < n; ++k) table[kWidth * (n + 1 + k) + l] = 3 * ringFace[begin[l] + k];
  }
}

#ifdef SODT_HAVE_LANES
namespace detail {
// "avx2" only: without the "fma" feature the compiler cannot contract a
// product and a sum into one rounding, so every operation rounds as the
// scalar code's does.
#define SODT_LANES_TARGET __attribute__((target("avx2")))

struct V3 {
  __m256d x, y, z;
};

SODT_LANES_TARGET inline __m256d add(__m256d a, __m256d b) { return _mm256_add_pd(a, b); }
SODT_LANES_TARGET inline __m256d sub(__m256d a, __m256d b) { return _mm256_sub_pd(a, b); }
SODT_LANES_TARGET inline __m256d mul(__m256d a, __m256d b) { return _mm256_mul_pd(a, b); }
/// a * b + c * d, rounded after each operation.
SODT_LANES_TARGET inline __m256d mulAdd2(__m256d a, __m256d b, __m256d c, __m256d d) {
  return add(mul(a, b), mul(c, d));
}
/// a * b - c * d, rounded after each operation.
SODT_LANES_TARGET inline __m256d mulSub2(__m256d a, __m256d b, __m256d c, __m256d d) {
  return sub(mul(a, b), mul(c, d));
}
/// u . v as vcg's Point3 computes it: (x x' + y y') + z z'.
SODT_LANES_TARGET inline __m256d dot(const V3& u, const V3& v) {
  return add(add(mul(u.x, v.x), mul(u.y, v.y)), mul(u.z, v.z));
}
/// u x v as vcg's Point3 computes it.
SODT_LANES_TARGET inline V3 cross(const V3& u, const V3& v) {
  return V3{mulSub2(u.y, v.z, u.z, v.y), mulSub2(u.z, v.x, u.x, v.z), mulSub2(u.x, v.y, u.y, v.x)};
}
SODT_LANES_TARGET inline V3 scale(const V3& u, __m256d s) { return V3{mul(u.x, s), mul(u.y, s), mul(u.z, s)}; }
SODT_LANES_TARGET inline __m256d absv(__m256d a) { return _mm256_andnot_pd(_mm256_set1_pd(-0.0), a); }
/// All-ones in the lanes where a is finite (std::isfinite).
SODT_LANES_TARGET inline __m256d finite(__m256d a) {
  return _mm256_cmp_pd(absv(a), _mm256_set1_pd(std::numeric_limits<double>::infinity()), _CMP_LT_OQ);
}
/// The points (x, y, z doubles) at p0..p3, one per lane: three-wide masked
/// loads (none reads past a point) and a transpose. Cheaper than three
/// gathers on the processors measured (bench/README.md).
SODT_LANES_TARGET inline V3 load4(const double* p0, const double* p1, const double* p2, const double* p3) {
  const __m256i xyz = _mm256_setr_epi64x(-1, -1, -1, 0);
  const __m256d a = _mm256_maskload_pd(p0, xyz), b = _mm256_maskload_pd(p1, xyz);
  const __m256d c = _mm256_maskload_pd(p2, xyz), d = _mm256_maskload_pd(p3, xyz);
  const __m256d x01z01 = _mm256_unpacklo_pd(a, b), y01 = _mm256_unpackhi_pd(a, b);
  const __m256d x23z23 = _mm256_unpacklo_pd(c, d), y23 = _mm256_unpackhi_pd(c, d);
  return V3{_mm256_permute2f128_pd(x01z01, x23z23, 0x20), _mm256_permute2f128_pd(y01, y23, 0x20),
            _mm256_permute2f128_pd(x01z01, x23z23, 0x31)};
}
/// The four points base + idx3[l] (idx3: indices times 3), one per lane.
SODT_LANES_TARGET inline V3 gather(const double* base, const int* idx3) {
  return load4(base + idx3[0], base + idx3[1], base + idx3[2], base + idx3[3]);
}
/// A ring vertex P in the frame (s, t, n), and |P|^2.
struct Local {
  __m256d x, y, z, len2;
};
SODT_LANES_TARGET inline Local local(const V3& P, const V3& s, const V3& t, const V3& n) {
  return Local{dot(s, P), dot(t, P), dot(n, P), dot(P, P)};
}
SODT_LANES_TARGET inline V3 sub(const V3& a, const V3& b) { return V3{sub(a.x, b.x), sub(a.y, b.y), sub(a.z, b.z)}; }
/// where ? b : a, lane by lane (where all-ones or all-zeros).
SODT_LANES_TARGET inline __m256d pick(__m256d a, __m256d b, __m256d where) { return _mm256_blendv_pd(a, b, where); }
/// std::max({a, b, c}) for values that are not NaN.
SODT_LANES_TARGET inline __m256d max3(__m256d a, __m256d b, __m256d c) {
  return _mm256_max_pd(_mm256_max_pd(a, b), c);
}
/// q in every lane.
SODT_LANES_TARGET inline V3 bcast(const Vec3& q) {
  return V3{_mm256_set1_pd(q[0]), _mm256_set1_pd(q[1]), _mm256_set1_pd(q[2])};
}
/// The squared cosine of the guard's angle tests: !(den > 0) ? 1 : dot <= 0 ?
/// 0 : std::min(1.0, dot * dot / den).
SODT_LANES_TARGET inline __m256d cos2(__m256d dot, __m256d den) {
  const __m256d zero = _mm256_setzero_pd(), one = _mm256_set1_pd(1.0);
  const __m256d q = _mm256_div_pd(mul(dot, dot), den);
  const __m256d m = pick(one, q, _mm256_cmp_pd(q, one, _CMP_LT_OQ));  // std::min(1.0, q) is q < 1 ? q : 1
  const __m256d r = pick(m, zero, _mm256_cmp_pd(dot, zero, _CMP_LE_OQ));
  return pick(one, r, _mm256_cmp_pd(den, zero, _CMP_GT_OQ));
}

/// moveAllowed's test of star triangle k with the centre at y: u and w
/// are its ring vertices k and k + 1 less y, uu and ww their squared
/// lengths, ee that of the ring edge between them, cur the triangle's fold
/// reference, ref its input normal (or null) and turn the squared cosine
/// of the largest turn from it (Star::maxTurnCos2), limit the angle limit.
/// All-ones in the lanes where the triangle passes.
SODT_LANES_TARGET inline __m256d triangleAllowed(const V3& u, const V3& w, __m256d uu, __m256d ww, __m256d ee,
                                                 const V3& cur, const V3* ref, __m256d turn, bool quality,
                                                 __m256d limit) {
  const __m256d zero = _mm256_setzero_pd();
  const V3 next = cross(u, w);
  const __m256d nn = dot(next, next);
  __m256d good = _mm256_cmp_pd(dot(next, cur), zero, _CMP_GT_OQ);
  if (ref) {
    // turnsBeyond (local_solve.h): d < 0 || d * d < turn * |next|^2 * |ref|^2.
    const __m256d d = dot(next, *ref);
    const __m256d far = _mm256_cmp_pd(mul(d, d), mul(mul(turn, nn), dot(*ref, *ref)), _CMP_LT_OQ);
    good = _mm256_andnot_pd(_mm256_or_pd(_mm256_cmp_pd(d, zero, _CMP_LT_OQ), far), good);
  }
  const __m256d l2 = max3(uu, ww, ee);
  good = _mm256_and_pd(good, _mm256_cmp_pd(nn, mul(mul(_mm256_set1_pd(kCollapse * kCollapse), l2), l2), _CMP_GT_OQ));
  if (quality) {
    // The smallest angle is opposite the shortest edge.
    const __m256d uw = dot(u, w);
    const __m256d atCentre = _mm256_and_pd(_mm256_cmp_pd(ee, uu, _CMP_LE_OQ), _mm256_cmp_pd(ee, ww, _CMP_LE_OQ));
    const __m256d atA = _mm256_andnot_pd(atCentre, _mm256_cmp_pd(ww, uu, _CMP_LE_OQ));
    const __m256d d = pick(pick(sub(ww, uw), sub(uu, uw), atA), uw, atCentre);
    const __m256d l1 = pick(pick(ww, uu, atA), uu, atCentre);
    const __m256d l3 = pick(ee, ww, atCentre);
    good = _mm256_andnot_pd(_mm256_cmp_pd(cos2(d, mul(l1, l3)), limit, _CMP_GT_OQ), good);
  }
  return good;
}

/// prepareGuard for a star of valence n (centre c, ring P, absolute, and X
/// = P - c, tangent-plane normals nrm), written to prepared when not null,
/// then, when out is not null, the full-step test of StepVerdict: the
/// lanes' targets, ok the lanes whose solve succeeded, faceRows the table's
/// face rows.
template <int n>
SODT_LANES_TARGET inline void guardN(const V3& c, const V3* P, const V3* X, const V3& target, const V3& nrm,
                                     __m256d ok, const int* faceRows, const GuardInput& in, StepVerdict* out,
                                     Prepared* prepared) {
  const __m256d zero = _mm256_setzero_pd(), one = _mm256_set1_pd(1.0);
  const __m256d collapse = _mm256_set1_pd(kCollapse);

  // prepareGuard: fold references, ring edge lengths, the star's worst angle.
  V3 cur[n];
  __m256d ee[n];
  __m256d worst = zero;
  for (int k = 0; k < n; ++k) {
    const int k1 = k + 1 < n ? k + 1 : 0;
    const V3& u = X[k];
    const V3& w = X[k1];
    const V3 e = sub(P[k1], P[k]);
    const __m256d uu = dot(u, u), ww = dot(w, w);
    ee[k] = dot(e, e);
    const V3 now = cross(u, w);
    const __m256d big =
        _mm256_cmp_pd(_mm256_sqrt_pd(dot(now, now)), mul(collapse, max3(uu, ww, ee[k])), _CMP_GT_OQ);
    cur[k] = V3{pick(nrm.x, now.x, big), pick(nrm.y, now.y, big), pick(nrm.z, now.z, big)};
    if (in.quality) {
      const __m256d eu = dot(e, u), ew = dot(e, w), uw = dot(u, w);
      const __m256d atCentre =
          _mm256_and_pd(_mm256_cmp_pd(ee[k], uu, _CMP_LE_OQ), _mm256_cmp_pd(ee[k], ww, _CMP_LE_OQ));
      const __m256d atA = _mm256_andnot_pd(atCentre, _mm256_cmp_pd(ww, uu, _CMP_LE_OQ));
      const __m256d d = pick(pick(ew, _mm256_xor_pd(eu, _mm256_set1_pd(-0.0)), atA), uw, atCentre);
      const __m256d den = pick(pick(mul(ww, ee[k]), mul(ee[k], uu), atA), mul(uu, ww), atCentre);
      const __m256d c2 = cos2(d, den);
      worst = pick(worst, c2, _mm256_cmp_pd(worst, c2, _CMP_LT_OQ));  // std::max(worst, c2)
    }
  }
  const __m256d limit = in.quality ? worst : one;
  if (prepared) {
    for (int k = 0; k < n; ++k) {
      _mm256_storeu_pd(prepared->cx[k], cur[k].x);
      _mm256_storeu_pd(prepared->cy[k], cur[k].y);
      _mm256_storeu_pd(prepared->cz[k], cur[k].z);
      _mm256_storeu_pd(prepared->ee[k], ee[k]);
    }
    _mm256_storeu_pd(prepared->limit, limit);
  }
  if (!out) return;

  // The full step, rounded as the mesh stores it.
  V3 y{add(c.x, sub(target.x, c.x)), add(c.y, sub(target.y, c.y)), add(c.z, sub(target.z, c.z))};
  if (in.roundToFloat)
    y = V3{_mm256_cvtps_pd(_mm256_cvtpd_ps(y.x)), _mm256_cvtps_pd(_mm256_cvtpd_ps(y.y)),
           _mm256_cvtps_pd(_mm256_cvtpd_ps(y.z))};
  const __m256d sameYZ = _mm256_and_pd(_mm256_cmp_pd(y.y, c.y, _CMP_EQ_OQ), _mm256_cmp_pd(y.z, c.z, _CMP_EQ_OQ));
  const __m256d same = _mm256_and_pd(_mm256_cmp_pd(y.x, c.x, _CMP_EQ_OQ), sameYZ);
  const __m256d decided =
      _mm256_andnot_pd(same, _mm256_and_pd(ok, _mm256_and_pd(finite(y.x), _mm256_and_pd(finite(y.y), finite(y.z)))));

  // moveAllowed at y, every triangle (its answer does not depend on the order).
  __m256d pass = _mm256_castsi256_pd(_mm256_set1_epi64x(-1));
  __m256d first = _mm256_set1_pd(-1.0);
  V3 u = sub(P[0], y);
  __m256d uu = dot(u, u);
  for (int k = 0; k < n; ++k) {
    const V3 w = sub(P[k + 1 < n ? k + 1 : 0], y);
    const __m256d ww = dot(w, w);
    const V3 r = in.faceNormal ? gather(in.faceNormal, faceRows + kWidth * k) : V3{zero, zero, zero};
    const __m256d good = triangleAllowed(u, w, uu, ww, ee[k], cur[k], in.faceNormal ? &r : nullptr,
                                         _mm256_set1_pd(in.maxTurnCos2), in.quality, limit);
    first = pick(first, _mm256_set1_pd(k), _mm256_andnot_pd(good, pass));
    pass = _mm256_and_pd(pass, good);
    u = w;
    uu = ww;
  }
  _mm256_storeu_pd(out->x, y.x);
  _mm256_storeu_pd(out->y, y.y);
  _mm256_storeu_pd(out->z, y.z);
  out->allowed = _mm256_movemask_pd(_mm256_and_pd(decided, pass));
  out->refused = _mm256_movemask_pd(_mm256_andnot_pd(pass, decided));
  _mm_storeu_si128(reinterpret_cast<__m128i*>(out->first), _mm256_cvtpd_epi32(first));
}
}  // namespace detail

namespace detail {
/// tangentFrame's s for the unit normal nrm: nrm x e with e the axis least
/// aligned with nrm, normalised (t is nrm x s).
SODT_LANES_TARGET inline V3 frameS(const V3& nrm) {
  const __m256d one = _mm256_set1_pd(1.0);
  const __m256d ax = absv(nrm.x), ay = absv(nrm.y), az = absv(nrm.z);
  const __m256d pickX = _mm256_and_pd(_mm256_cmp_pd(ax, ay, _CMP_LE_OQ), _mm256_cmp_pd(ax, az, _CMP_LE_OQ));
  const __m256d pickY = _mm256_andnot_pd(pickX, _mm256_cmp_pd(ay, az, _CMP_LE_OQ));
  const __m256d pickZ = _mm256_andnot_pd(_mm256_or_pd(pickX, pickY), _mm256_castsi256_pd(_mm256_set1_epi64x(-1)));
  const V3 e{_mm256_and_pd(pickX, one), _mm256_and_pd(pickY, one), _mm256_and_pd(pickZ, one)};
  const V3 s = cross(nrm, e);
  return scale(s, _mm256_div_pd(one, _mm256_sqrt_pd(dot(s, s))));
}

/// solveStar's target for the lanes' stars (centre c, ring X relative to
/// it) on the plane of normal nrm; clears the lanes of ok where it fails.
template <int n>
SODT_LANES_TARGET inline V3 solveN(const V3& c, const V3* X, const V3& nrm, __m256d& ok) {
  const __m256d zero = _mm256_setzero_pd(), one = _mm256_set1_pd(1.0);
  const V3 s = frameS(nrm);
  const V3 t = cross(nrm, s);

  // sodtCoefficients.
  __m256d C = zero, E = zero, F = zero, G = zero, H = zero, I = zero;
  const Local first = local(X[0], s, t, nrm);
  Local a = first;
  for (int k = 0; k < n; ++k) {
    const Local b = k + 1 < n ? local(X[k + 1], s, t, nrm) : first;
    const __m256d sw = sub(b.y, a.y), tw = sub(a.x, b.x);
    const __m256d cc = mulSub2(a.x, b.y, a.y, b.x);
    const __m256d ss = add(a.x, b.x), ts = add(a.y, b.y);
    const __m256d r = sub(add(a.len2, b.len2), add(add(mul(a.x, b.x), mul(a.y, b.y)), mul(a.z, b.z)));
    C = add(C, cc);
    E = add(E, mul(ss, sw));
    F = add(F, mul(ts, tw));
    G = add(G, mulAdd2(ss, tw, ts, sw));
    H = add(H, mulAdd2(ss, cc, r, sw));
    I = add(I, mulAdd2(ts, cc, r, tw));
    a = b;
  }
  E = add(E, C);
  F = add(F, C);

  // The 2x2 solve of solveStar.
  const __m256d four = _mm256_set1_pd(4.0), two = _mm256_set1_pd(2.0);
  const __m256d det = sub(mul(mul(four, E), F), mul(G, G));
  const __m256d scl = add(mul(four, absv(mul(E, F))), mul(G, G));
  ok = _mm256_and_pd(ok, _mm256_cmp_pd(E, zero, _CMP_GT_OQ));
  ok = _mm256_and_pd(ok, _mm256_cmp_pd(det, mul(_mm256_set1_pd(kSingularRel), scl), _CMP_GT_OQ));
  const __m256d inv = _mm256_div_pd(one, det);
  const __m256d u = mul(sub(mul(mul(two, F), H), mul(G, I)), inv);
  const __m256d v = mul(sub(mul(mul(two, E), I), mul(G, H)), inv);
  const V3 target{add(add(c.x, mul(s.x, u)), mul(t.x, v)), add(add(c.y, mul(s.y, u)), mul(t.y, v)),
                  add(add(c.z, mul(s.z, u)), mul(t.z, v))};
  ok = _mm256_and_pd(ok, _mm256_and_pd(finite(target.x), _mm256_and_pd(finite(target.y), finite(target.z))));
  return target;
}

SODT_LANES_TARGET inline V3 add(const V3& a, const V3& b) { return V3{add(a.x, b.x), add(a.y, b.y), add(a.z, b.z)}; }

/// StarQuadratic::quad(a, b) for the lanes.
SODT_LANES_TARGET inline __m256d quad(const __m256d (*Q)[3], const __m256d* a, const __m256d* b) {
  __m256d r = _mm256_setzero_pd();
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r = add(r, mul(mul(a[i], Q[i][j]), b[j]));
  return r;
}

/// boundNormalStep for the lanes.
SODT_LANES_TARGET inline V3 boundNormalStep(const V3& x, const V3& c, const V3& dir, __m256d lim) {
  const __m256d h = dot(sub(x, c), dir);
  const __m256d over = _mm256_cmp_pd(absv(h), lim, _CMP_GT_OQ);
  const __m256d signedLim = pick(_mm256_xor_pd(lim, _mm256_set1_pd(-0.0)), lim, _mm256_cmp_pd(h, _mm256_setzero_pd(), _CMP_GT_OQ));
  const V3 moved = sub(x, scale(dir, sub(h, signedLim)));
  return V3{pick(x.x, moved.x, over), pick(x.y, moved.y, over), pick(x.z, moved.z, over)};
}

/// denoiseTargets for the lanes' stars (centre c, ring P, and X = P - c;
/// the centres' indices times 3 in table's first row): returns the target,
/// writes the fallback, clears the lanes of ok where it fails.
template <int n>
SODT_LANES_TARGET inline V3 denoiseN(const V3& c, const V3* P, const V3* X, const int* table, const DenoiseInput& in,
                                     __m256d& ok, V3& fallback) {
  const __m256d zero = _mm256_setzero_pd(), two = _mm256_set1_pd(2.0);
  const long st = in.stride;
  const V3 point = load4(in.point + st * (table[0] / 3), in.point + st * (table[1] / 3),
                         in.point + st * (table[2] / 3), in.point + st * (table[3] / 3));
  const V3 dir = load4(in.dir + st * (table[0] / 3), in.dir + st * (table[1] / 3), in.dir + st * (table[2] / 3),
                       in.dir + st * (table[3] / 3));
  // ringCentroid.
  V3 centroid{zero, zero, zero};
  for (int k = 0; k < n; ++k) centroid = add(centroid, P[k]);
  const __m256d count = _mm256_set1_pd(double(n));
  centroid = V3{_mm256_div_pd(centroid.x, count), _mm256_div_pd(centroid.y, count), _mm256_div_pd(centroid.z, count)};
  // sodtQuadratic with dir.
  __m256d C = zero, Q[3][3], g[3] = {zero, zero, zero};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) Q[i][j] = zero;
  for (int k = 0; k < n; ++k) {
    const V3& Xa = X[k];
    const V3& Xb = X[k + 1 < n ? k + 1 : 0];
    const V3 e = sub(Xb, Xa), w = cross(e, dir), S = add(Xa, Xb);
    const __m256d cc = dot(cross(Xa, Xb), dir);
    const __m256d A = add(add(dot(Xa, Xa), dot(Xb, Xb)), dot(e, e));
    C = add(C, cc);
    const __m256d Sv[3] = {S.x, S.y, S.z}, wv[3] = {w.x, w.y, w.z};
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) Q[i][j] = add(Q[i][j], add(mul(Sv[i], wv[j]), mul(wv[i], Sv[j])));
    const __m256d twoC = mul(two, cc);
    for (int i = 0; i < 3; ++i) g[i] = sub(g[i], add(mul(Sv[i], twoC), mul(wv[i], A)));
  }
  for (int i = 0; i < 3; ++i) Q[i][i] = add(Q[i][i], mul(two, C));
  // tangentFrame(dir) and minimizeOnPlane.
  const V3 s = frameS(dir);
  const V3 t = cross(dir, s);
  const __m256d sv[3] = {s.x, s.y, s.z}, tv[3] = {t.x, t.y, t.z};
  const __m256d qss = quad(Q, sv, sv), qtt = quad(Q, tv, tv), qst = quad(Q, sv, tv);
  const V3 p0 = sub(point, c);
  const __m256d p0v[3] = {p0.x, p0.y, p0.z};
  __m256d grad[3];
  for (int i = 0; i < 3; ++i) {
    __m256d r = zero;
    for (int j = 0; j < 3; ++j) r = add(r, mul(Q[i][j], p0v[j]));
    grad[i] = add(g[i], mul(r, two));
  }
  const V3 gradv{grad[0], grad[1], grad[2]};
  const __m256d negZero = _mm256_set1_pd(-0.0);
  const __m256d rs = _mm256_xor_pd(dot(s, gradv), negZero), rt = _mm256_xor_pd(dot(t, gradv), negZero);
  const __m256d det = sub(mul(qss, qtt), mul(qst, qst));
  const __m256d scl = add(absv(mul(qss, qtt)), mul(qst, qst));
  ok = _mm256_and_pd(ok, _mm256_cmp_pd(qss, zero, _CMP_GT_OQ));
  ok = _mm256_and_pd(ok, _mm256_cmp_pd(det, mul(_mm256_set1_pd(kSingularRel), scl), _CMP_GT_OQ));
  const __m256d twoDet = mul(two, det);
  const __m256d u = _mm256_div_pd(sub(mul(qtt, rs), mul(qst, rt)), twoDet);
  const __m256d v = _mm256_div_pd(sub(mul(qss, rt), mul(qst, rs)), twoDet);
  const V3 p = add(add(p0, scale(s, u)), scale(t, v));
  ok = _mm256_and_pd(ok, _mm256_and_pd(finite(p.x), _mm256_and_pd(finite(p.y), finite(p.z))));
  // The fallback and the bound along dir.
  const V3 d = sub(sub(centroid, c), p0);
  const __m256d lim = _mm256_set1_pd(in.lim);
  fallback = boundNormalStep(sub(add(point, d), scale(dir, dot(d, dir))), c, dir, lim);
  const V3 target = boundNormalStep(add(c, p), c, dir, lim);
  ok = _mm256_and_pd(ok, _mm256_and_pd(finite(target.x), _mm256_and_pd(finite(target.y), finite(target.z))));
  ok = _mm256_and_pd(ok, _mm256_and_pd(finite(fallback.x), _mm256_and_pd(finite(fallback.y), finite(fallback.z))));
  return target;
}

/// targets4 for valence n, known at compile time so that the loops unroll.
template <int n>
SODT_LANES_TARGET inline void targetsN(const double* pos, const int* table, Targets& out, const GuardInput* guard,
                                       StepVerdict* verdict, Prepared* prepared, const DenoiseInput* denoise) {
  const __m256d zero = _mm256_setzero_pd(), one = _mm256_set1_pd(1.0);
  const V3 c = gather(pos, table);

  // The ring relative to the centre, and the area-weighted normal (starNormal).
  V3 P[n], X[n];
  for (int k = 0; k < n; ++k) {
    P[k] = gather(pos, table + kWidth * (k + 1));
    X[k] = sub(P[k], c);
  }
  V3 sum{zero, zero, zero};
  for (int k = 0; k < n; ++k) {
    const V3 a = cross(X[k], X[k + 1 < n ? k + 1 : 0]);
    sum = V3{add(sum.x, a.x), add(sum.y, a.y), add(sum.z, a.z)};
  }
  const __m256d len = _mm256_sqrt_pd(dot(sum, sum));
  __m256d ok = _mm256_and_pd(_mm256_cmp_pd(len, zero, _CMP_GT_OQ), finite(len));
  const V3 nrm = scale(sum, _mm256_div_pd(one, len));
  ok = _mm256_and_pd(ok, _mm256_cmp_pd(dot(nrm, nrm), zero, _CMP_NEQ_UQ));

  V3 target;
  if (denoise) {
    V3 fallback;
    target = denoiseN<n>(c, P, X, table, *denoise, ok, fallback);
    _mm256_storeu_pd(out.fx, fallback.x);
    _mm256_storeu_pd(out.fy, fallback.y);
    _mm256_storeu_pd(out.fz, fallback.z);
  } else {
    target = solveN<n>(c, X, nrm, ok);
  }
  _mm256_storeu_pd(out.x, target.x);
  _mm256_storeu_pd(out.y, target.y);
  _mm256_storeu_pd(out.z, target.z);
  _mm256_storeu_pd(out.nx, nrm.x);
  _mm256_storeu_pd(out.ny, nrm.y);
  _mm256_storeu_pd(out.nz, nrm.z);
  out.ok = _mm256_movemask_pd(ok);
  if (guard && (verdict || prepared))
    guardN<n>(c, P, X, target, nrm, ok, table + kWidth * (n + 1), *guard, verdict, prepared);
}
}  // namespace detail

/// For four interior vertices with the same valence n (3 <= n <= kMaxValence),
/// computes what solveStar(star) gives for each (with denoise, what
/// denoiseTargets gives), and the normal starNormal(star). pos holds x, y, z per
/// vertex; table is the group's index table (see packGroup). When guard is
/// not null, also what prepareGuard gives each lane with that normal (when
/// prepared is not null), and the full step's verdict (when verdict is not
/// null; the table must have its face rows).
SODT_LANES_TARGET inline void targets4(const double* pos, const int* table, int n, Targets& out,
                                       const GuardInput* guard = nullptr, StepVerdict* verdict = nullptr,
                                       Prepared* prepared = nullptr, const DenoiseInput* denoise = nullptr) {
  using detail::targetsN;
  if (verdict) verdict->allowed = verdict->refused = 0;
  switch (n) {
    case 3: return targetsN<3>(pos, table, out, guard, verdict, prepared, denoise);
    case 4: return targetsN<4>(pos, table, out, guard, verdict, prepared, denoise);
    case 5: return targetsN<5>(pos, table, out, guard, verdict, prepared, denoise);
    case 6: return targetsN<6>(pos, table, out, guard, verdict, prepared, denoise);
    case 7: return targetsN<7>(pos, table, out, guard, verdict, prepared, denoise);
    case 8: return targetsN<8>(pos, table, out, guard, verdict, prepared, denoise);
    case 9: return targetsN<9>(pos, table, out, guard, verdict, prepared, denoise);
    case 10: return targetsN<10>(pos, table, out, guard, verdict, prepared, denoise);
    case 11: return targetsN<11>(pos, table, out, guard, verdict, prepared, denoise);
    case 12: return targetsN<12>(pos, table, out, guard, verdict, prepared, denoise);
    default: out.ok = 0; return;
  }
}

/// moveAllowed (local_solve.h) for count (1 to kWidth) positions p of the
/// centre of one star at once, one per lane: the star's ring (n points in
/// cyclic order), its triangles' fold references cur and squared ring edges
/// ringEdge2 (prepareGuard), input normals ref (Star::refNormal) or null for
/// none and the largest turn from them maxTurnCos2 (Star::maxTurnCos2),
/// quality and cos2Limit as for moveAllowed. Returns bit l set when
/// moveAllowed accepts p[l], bit for bit. witness as for moveAllowed: the
/// test starts at triangle *witness (the answer does not depend on it) and
/// ends early once every position has failed; when one has, *witness gets a
/// triangle that failed.
SODT_LANES_TARGET inline int allowedAt(const Vec3* ring, int n, const Vec3* cur, const double* ringEdge2,
                                       const Vec3* ref, double maxTurnCos2, bool quality, double cos2Limit,
                                       const Vec3* p, int count, int* witness) {
  using namespace detail;
  if (n == 0) return (1 << count) - 1;
  const __m256d limit = _mm256_set1_pd(cos2Limit), turn = _mm256_set1_pd(maxTurnCos2);
  const Vec3& last = p[count - 1];  // the spare lanes repeat the last position
  const V3 y = load4(&p[0][0], count > 1 ? &p[1][0] : &last[0], count > 2 ? &p[2][0] : &last[0],
                     count > 3 ? &p[3][0] : &last[0]);
  const int k0 = witness && *witness > 0 && *witness < n ? *witness : 0;
  __m256d pass = _mm256_castsi256_pd(_mm256_set1_epi64x(-1));
  const int lanesUsed = (1 << count) - 1;
  V3 u = sub(bcast(ring[k0]), y);
  __m256d uu = dot(u, u);
  int firstFail = -1;
  for (int t = 0, k = k0; t < n; ++t) {
    const int k1 = k + 1 < n ? k + 1 : 0;
    const V3 w = sub(bcast(ring[k1]), y);
    const __m256d ww = dot(w, w);
    const V3 r = ref ? bcast(ref[k]) : V3();
    const __m256d good = triangleAllowed(u, w, uu, ww, _mm256_set1_pd(ringEdge2[k]), bcast(cur[k]), ref ? &r : nullptr,
                                         turn, quality, limit);
    if (firstFail < 0 && (_mm256_movemask_pd(good) & lanesUsed) != lanesUsed) firstFail = k;
    pass = _mm256_and_pd(pass, good);
    if ((_mm256_movemask_pd(pass) & lanesUsed) == 0) break;
    u = w;
    uu = ww;
    k = k1;
  }
  if (witness && firstFail >= 0) *witness = firstFail;
  return _mm256_movemask_pd(pass) & lanesUsed;
}

namespace detail {
/// The vertices tri[0], tri[3], tri[6], tri[9] of pos (x, y, z per vertex).
SODT_LANES_TARGET inline V3 loadCorner(const double* pos, const int* tri) {
  return load4(pos + 3 * tri[0], pos + 3 * tri[3], pos + 3 * tri[6], pos + 3 * tri[9]);
}
}  // namespace detail

/// For four faces with vertex indices tri[0..11] (three per face), computes
/// what the per-face pass of SweepQualityMeter does for each, bit for bit:
/// the key minAngleSin2 (sweep_quality.h) and, when ref is not null, whether
/// doubleAreaVector(a, b, c) * ref[face] < 0, ref holding the four faces'
/// normals as x, y, z doubles. pos holds x, y, z per vertex.
SODT_LANES_TARGET inline void faceKeys4(const double* pos, const int* tri, const double* ref, FaceKeys& out) {
  using namespace detail;
  const __m256d zero = _mm256_setzero_pd(), one = _mm256_set1_pd(1.0);
  const V3 a = loadCorner(pos, tri), b = loadCorner(pos, tri + 1), c = loadCorner(pos, tri + 2);
  const V3 ab{sub(b.x, a.x), sub(b.y, a.y), sub(b.z, a.z)};
  const V3 ac{sub(c.x, a.x), sub(c.y, a.y), sub(c.z, a.z)};
  const V3 bc{sub(c.x, b.x), sub(c.y, b.y), sub(c.z, b.z)};
  const V3 area = cross(ab, ac);
  const __m256d l1 = dot(ab, ab), l2 = dot(ac, ac), l3 = dot(bc, bc);
  // std::max(x, y) is x unless x < y, _mm256_max_pd(x, y) is y unless
  // x > y: the same value for the finite, non-negative lengths here.
  const __m256d longest = _mm256_max_pd(_mm256_max_pd(l1, l2), l3);
  const __m256d middle = _mm256_max_pd(_mm256_min_pd(l1, l2), _mm256_min_pd(_mm256_max_pd(l1, l2), l3));
  const __m256d den = mul(longest, middle);
  const __m256d s2 = _mm256_min_pd(_mm256_div_pd(dot(area, area), den), one);
  _mm256_storeu_pd(out.key, _mm256_and_pd(_mm256_cmp_pd(den, zero, _CMP_GT_OQ), s2));
  out.inverted = 0;
  if (ref) {
    const V3 r = load4(ref, ref + 3, ref + 6, ref + 9);
    out.inverted = _mm256_movemask_pd(_mm256_cmp_pd(dot(area, r), zero, _CMP_LT_OQ));
  }
}
#undef SODT_LANES_TARGET
#else
/// No kernel in this build: available() is false, so these are never called.
inline void targets4(const double*, const int*, int, Targets& out, const GuardInput* = nullptr,
                     StepVerdict* verdict = nullptr, Prepared* = nullptr, const DenoiseInput* = nullptr) {
  out.ok = 0;
  if (verdict) verdict->allowed = verdict->refused = 0;
}
inline void faceKeys4(const double*, const int*, const double*, FaceKeys& out) {
  out = FaceKeys();  // never called: available() is false
}
inline int allowedAt(const Vec3*, int, const Vec3*, const double*, const Vec3*, double, bool, double, const Vec3*,
                     int, int*) {
  return 0;
}
#endif

}  // namespace lanes
}  // namespace sodt
