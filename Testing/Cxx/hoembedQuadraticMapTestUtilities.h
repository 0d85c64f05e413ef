// Brute-force references for the tests of the quadratic maps (closest point, exclusion
// rules, barycentric forms): distances to a tet map by sampling and by constrained solves.
#ifndef hoembedQuadraticMapTestUtilities_h
#define hoembedQuadraticMapTestUtilities_h

#include "hoembedClosestPoint.h"

#include <algorithm>
#include <cmath>
#include <limits>

// Smallest squared distance from v to the tet map m sampled on the lattice of n steps per
// edge of the reference tet.
inline double LatticeDistance2(const hoembed::QuadraticMap& m, const double v[3], int n)
{
  double best = std::numeric_limits<double>::infinity();
  for (int i = 0; i <= n; ++i)
    for (int j = 0; i + j <= n; ++j)
      for (int k = 0; i + j + k <= n; ++k)
      {
        const double pc[3] = { double(i) / n, double(j) / n, double(k) / n };
        double y[3];
        hoembed::EvaluateMap(m, pc, y);
        best = std::min(best,
          (y[0] - v[0]) * (y[0] - v[0]) + (y[1] - v[1]) * (y[1] - v[1]) +
            (y[2] - v[2]) * (y[2] - v[2]));
      }
  return best;
}

// The reference tet10's nodes (VTK order).
const double RefTet10[10][3] = { { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 }, { 0.5, 0, 0 },
  { 0.5, 0.5, 0 }, { 0, 0.5, 0 }, { 0, 0, 0.5 }, { 0.5, 0, 0.5 }, { 0, 0.5, 0.5 } };

// Distance from v to the element of the tet map m by brute force: constrained solves from
// 5 starts and a dense sample (16 steps per edge) of the element.
inline double BruteDistanceToTetMap(const hoembed::QuadraticMap& m, const double v[3])
{
  const double starts[5][3] = { { 0.25, 0.25, 0.25 }, { 0.7, 0.1, 0.1 }, { 0.1, 0.7, 0.1 },
    { 0.1, 0.1, 0.7 }, { 0.1, 0.1, 0.1 } };
  double best = std::numeric_limits<double>::infinity();
  for (const auto& s0 : starts)
  {
    hoembed::ClosestPointResult r;
    hoembed::ClosestPointOnMap(m, v, s0, r, 200);
    best = std::min(best, r.Distance2);
  }
  return std::sqrt(std::min(best, LatticeDistance2(m, v, 16)));
}

#endif
