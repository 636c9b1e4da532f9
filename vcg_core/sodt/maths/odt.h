// SPDX-License-Identifier: GPL-3.0-or-later
// The "optimal" ODT update of Eq. 3 (true triangle areas S'_k), minimised
// numerically in the tangent plane: the reference the paper's S-ODT approximates.
#pragma once

#include "local_solve.h"

#include <cmath>

namespace sodt {

/// Eq. 3 with the centre at p: sum_k (|x_k - p|^2 + |x_{k+1} - p|^2 + |x_{k+1} - x_k|^2) S'_k,
/// S'_k the area of triangle (p, x_k, x_{k+1}).
inline double odtEnergy(const Star& st, const Vec3& p) {
  double e = 0;
  for (std::size_t k = 0; k < st.size(); ++k) {
    const Vec3 a = st.at(k) - p, b = st.at(k + 1) - p;
    e += (a.SquaredNorm() + b.SquaredNorm() + (b - a).SquaredNorm()) * 0.5 * (a ^ b).Norm();
  }
  return e;
}

/// Gradient of odtEnergy with respect to p. With a = x_k - p, b = x_{k+1} - p,
/// c = a x b: d|c|/dp = (a - b) x c / |c|, d(|a|^2 + |b|^2)/dp = -2 (a + b).
inline Vec3 odtGradient(const Star& st, const Vec3& p) {
  Vec3 g(0, 0, 0);
  for (std::size_t k = 0; k < st.size(); ++k) {
    const Vec3 a = st.at(k) - p, b = st.at(k + 1) - p, c = a ^ b;
    const double len = c.Norm();
    const double w = a.SquaredNorm() + b.SquaredNorm() + (b - a).SquaredNorm();
    g += (a + b) * (-2.0 * 0.5 * len);
    if (len > 0) g += ((a - b) ^ c) * (0.5 * w / len);
  }
  return g;
}

/// Minimiser of Eq. 3 over the tangent plane of Eq. 4 by damped Newton
/// iterations (analytic gradient, Hessian from central differences of the
/// gradient, backtracking line search), starting at the centre.
/// \param maxIterations Newton iterations at most.
/// \param iterationsUsed when not null, receives the iterations performed.
inline LocalMove solveStarOdt(const Star& st, int maxIterations = 50, int* iterationsUsed = nullptr) {
  LocalMove mv;
  mv.target = st.center;
  if (iterationsUsed) *iterationsUsed = 0;
  if (st.size() < 3) return mv;
  mv.normal = starNormal(st);
  if (mv.normal.SquaredNorm() == 0) return mv;
  Vec3 s, t;
  tangentFrame(mv.normal, s, t);
  double scale = 0;
  for (const Vec3& q : st.ring) scale = std::max(scale, (q - st.center).Norm());
  if (!(scale > 0)) return mv;
  const double h = 1e-6 * scale;
  Vec3 p = st.center;
  double e = odtEnergy(st, p);
  int it = 0;
  for (; it < maxIterations; ++it) {
    const Vec3 g = odtGradient(st, p);
    const double gs = g * s, gt = g * t;
    if (std::sqrt(gs * gs + gt * gt) <= 1e-12 * (e / scale + 1e-300)) break;
    // Hessian in (s, t) by central differences of the gradient.
    const Vec3 gsp = odtGradient(st, p + s * h), gsm = odtGradient(st, p - s * h);
    const Vec3 gtp = odtGradient(st, p + t * h), gtm = odtGradient(st, p - t * h);
    const double hss = ((gsp - gsm) * s) / (2 * h), htt = ((gtp - gtm) * t) / (2 * h);
    const double hst = 0.5 * (((gsp - gsm) * t) + ((gtp - gtm) * s)) / (2 * h);
    const double det = hss * htt - hst * hst;
    double du, dv;
    if (hss > 0 && det > 0) {
      du = -(htt * gs - hst * gt) / det;
      dv = -(hss * gt - hst * gs) / det;
    } else {  // not convex here: steepest descent, scaled to the star
      const double gn = std::sqrt(gs * gs + gt * gt);
      du = -gs / gn * 0.1 * scale;
      dv = -gt / gn * 0.1 * scale;
    }
    double f = 1.0;
    bool moved = false;
    for (int ls = 0; ls < 30; ++ls, f *= 0.5) {
      const Vec3 q = p + s * (du * f) + t * (dv * f);
      const double eq = odtEnergy(st, q);
      if (eq < e) {
        p = q;
        e = eq;
        moved = true;
        break;
      }
    }
    if (!moved) break;
  }
  if (iterationsUsed) *iterationsUsed = it;
  if (!isFinite(p)) return mv;
  mv.ok = true;
  mv.target = p;
  return mv;
}

}  // namespace sodt
