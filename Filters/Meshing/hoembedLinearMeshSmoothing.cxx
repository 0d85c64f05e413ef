#include "hoembedLinearMeshSmoothing.h"

#include "hoembedCsr.h"
#include "hoembedElementGeometry.h"
#include "hoembedTetMeshTopology.h"
#include "hoembedVector3.h"

#include <algorithm>
#include <cmath>

namespace hoembed
{
namespace
{
using Id = std::int64_t;

// Qualities above this count as this in the sum a move may raise: a move is meant for the
// poor tets (a median at 300 elements of 0.3-0.4, Benchmarks/RESULTS.md), not to trade
// them for good ones.
constexpr double kQualityCap = 0.7;

// The worst scaled Jacobian `worst` and the sum of the capped ones `sum` of the tets
// around[begin, end); false when one is not positive.
bool Score(const std::vector<double>& pts, const std::vector<Id>& tets, const Id* begin,
  const Id* end, double& worst, double& sum)
{
  worst = 1.0;
  sum = 0.0;
  for (const Id* t = begin; t != end; ++t)
  {
    double x[12];
    for (int a = 0; a < 4; ++a)
      for (int d = 0; d < 3; ++d)
        x[3 * a + d] = pts[3 * tets[4 * *t + a] + d];
    if (!(Tet4JacobianDeterminant(x) > 0.0))
      return false;
    const double q = Tet4ScaledJacobian(x);
    worst = std::min(worst, q);
    sum += std::min(q, kQualityCap);
  }
  return true;
}
} // namespace

void TetsAroundCorners(
  const std::vector<Id>& tets, Id nPts, std::vector<Id>& off, std::vector<Id>& around)
{
  const Id nTets = static_cast<Id>(tets.size() / 4);
  BuildCsr(
    nPts,
    [&](auto&& emit) {
      for (Id t = 0; t < nTets; ++t)
        for (int a = 0; a < 4; ++a)
          emit(tets[4 * t + a], t);
    },
    off, around);
}

Id OptimiseLinearCorners(std::vector<double>& pts, const std::vector<Id>& tets,
  const TetMeshTopology& topo, const SurfaceQueries& surface, int sweeps,
  const std::vector<double>& restore, double floor)
{
  const Id nPts = static_cast<Id>(pts.size() / 3);
  const Id nTets = static_cast<Id>(tets.size() / 4);
  std::vector<Id> off, around;
  TetsAroundCorners(tets, nPts, off, around);
  const std::vector<double> start = pts;
  // The crossing repair puts some boundary corners back where `restore` has them: the
  // worst tet around v over every choice of its boundary corners put back (at most 16
  // shapes per tet; v where it is unless it is put back too).
  auto restoredWorst = [&](const Id* begin, const Id* end) {
    double w = 1.0;
    for (const Id* t = begin; t != end; ++t)
    {
      const Id* c = &tets[4 * *t];
      int boundaryMask = 0;
      for (int a = 0; a < 4; ++a)
        boundaryMask |= topo.IsBoundaryNode(c[a]) ? 1 << a : 0;
      for (int mask = 1; mask < 16; ++mask)
      {
        if ((mask & boundaryMask) != mask)
          continue;
        double x[12];
        for (int a = 0; a < 4; ++a)
          for (int d = 0; d < 3; ++d)
            x[3 * a + d] = (mask >> a & 1 ? restore : pts)[3 * c[a] + d];
        if (!(Tet4JacobianDeterminant(x) > 0.0))
          return -1.0;
        w = std::min(w, Tet4ScaledJacobian(x));
      }
    }
    return w;
  };
  std::vector<double> reach(nPts, -1.0);
  Id moved = 0;
  for (int sweep = 0; sweep < sweeps; ++sweep)
  {
    Id movedNow = 0;
    for (Id v = 0; v < nPts; ++v)
    {
      if (off[v] == off[v + 1])
        continue;
      const Id* begin = around.data() + off[v];
      const Id* end = around.data() + off[v + 1];
      double* x = &pts[3 * v];
      // the mean length of the edges at v (each once per tet: a weight by tets)
      double L = 0.0;
      for (const Id* t = begin; t != end; ++t)
        for (int a = 0; a < 4; ++a)
          if (tets[4 * *t + a] != v)
            L += std::sqrt(Distance2(x, &pts[3 * tets[4 * *t + a]]));
      L /= 3.0 * static_cast<double>(end - begin);
      if (!(L > 0.0))
        continue;
      if (reach[v] < 0.0)
        reach[v] = L / 3.0;
      const bool boundary = topo.IsBoundaryNode(v);
      double dirs[6][3] = { { 1, 0, 0 }, { -1, 0, 0 }, { 0, 1, 0 }, { 0, -1, 0 }, { 0, 0, 1 },
        { 0, 0, -1 } };
      int nDirs = 6;
      double n[3] = { 0.0, 0.0, 0.0 };
      if (boundary)
      {
        if (!surface.Closest)
          continue;
        double c[3];
        surface.Closest(x, c);
        // only corners on the surface slide on it (the others: an envelope's corner far
        // from the surface, or one whose projection was refused)
        if (Distance2(x, c) > 1e-12 * L * L)
          continue;
        for (Id k = topo.NodeFaceOffsets[v]; k < topo.NodeFaceOffsets[v + 1]; ++k)
        {
          const Id* f = &topo.BoundaryFaceNodes[3 * topo.NodeFaces[k]];
          double u[3], w[3], m[3];
          for (int d = 0; d < 3; ++d)
          {
            u[d] = pts[3 * f[1] + d] - pts[3 * f[0] + d];
            w[d] = pts[3 * f[2] + d] - pts[3 * f[0] + d];
          }
          Cross(u, w, m);
          if (Normalize(m) > 0.0)
            for (int d = 0; d < 3; ++d)
              n[d] += m[d];
        }
        if (!(Normalize(n) > 0.0))
          continue;
        double p[3], q[3];
        Perpendiculars(n, p, q);
        for (int d = 0; d < 3; ++d)
        {
          dirs[0][d] = p[d];
          dirs[1][d] = -p[d];
          dirs[2][d] = q[d];
          dirs[3][d] = -q[d];
        }
        nDirs = 4;
      }
      double worst = 0.0, sum = 0.0;
      if (!Score(pts, tets, begin, end, worst, sum))
        continue;
      const double restoredBar = std::min(floor, restoredWorst(begin, end));
      const double x0[3] = { x[0], x[1], x[2] };
      double step = 0.25 * L;
      for (int it = 0; it < 8 && step > 0.02 * L; ++it)
      {
        bool better = false;
        for (int k = 0; k < nDirs && !better; ++k)
        {
          const double keep[3] = { x[0], x[1], x[2] };
          double c[3];
          for (int d = 0; d < 3; ++d)
            c[d] = keep[d] + step * dirs[k][d];
          if (boundary)
          {
            const double probe[3] = { c[0], c[1], c[2] };
            surface.Closest(probe, c);
            double s[3];
            for (int d = 0; d < 3; ++d)
              s[d] = c[d] - keep[d];
            const double len = std::sqrt(Dot(s, s));
            // a crease (or a jump to another part of the surface): the surface point
            // leaves the corner's tangent plane
            if (!(len > 0.0) || len > 1.5 * step || std::fabs(Dot(s, n)) > 0.3 * len)
              continue;
          }
          if (Distance2(c, &start[3 * v]) > reach[v] * reach[v])
            continue;
          for (int d = 0; d < 3; ++d)
            x[d] = c[d];
          double w = 0.0, s = 0.0;
          if (Score(pts, tets, begin, end, w, s) && w >= worst && s > sum + 1e-12 &&
            restoredWorst(begin, end) >= restoredBar)
          {
            worst = w;
            sum = s;
            better = true;
          }
          else
            for (int d = 0; d < 3; ++d)
              x[d] = keep[d];
        }
        if (!better)
          step *= 0.5;
      }
      if (x[0] != x0[0] || x[1] != x0[1] || x[2] != x0[2])
        ++movedNow;
    }
    moved += movedNow;
    if (movedNow == 0)
      break;
  }
  return moved;
}
} // namespace hoembed
