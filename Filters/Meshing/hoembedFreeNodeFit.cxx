#include "hoembedFreeNodeFit.h"

#include "hoembedCurvedBoundary.h"
#include "hoembedElementGeometry.h"
#include "hoembedShapeFunctions.h"

#include <algorithm>
#include <cmath>

namespace hoembed
{
using Id = std::int64_t;

namespace
{
// Acceptability margin of a tet10: >= 0 exactly when it is acceptable (without an extra
// check), below -1 when not provably valid, more negative the worse. `floor` is the part
// of the required quality set by the element's straight shape before the fit: corners
// move here, and a corner move that spoils the straight shape must not lower the bar
// (Tet10RequiredQuality of the new shape alone would accept any sliver it makes).
// `straightFloor` bars the straight shape itself: every later step measures its cells
// against their straight shape and may straighten them (the crossing repair, the
// quality floor's safety net), so a corner move that took a straight shape below the
// floor left a cell that those steps take below it (rocker-arm at 4000 elements: 14
// straight shapes below the floor after the fit, one curved cell at 0.039 in the end,
// where the tet4 mesh of the same corners has none).
double Margin(
  const double* x, double qualityRatio, double minQuality, double floor, double straightFloor)
{
  const double det4 = Tet4JacobianDeterminant(x);
  if (!(det4 > 0.0))
    return -3.0;
  const double q = Tet10MinScaledJacobian(x);
  const double straight = Tet4ScaledJacobian(x);
  if (q > 0.0)
  {
    const double m = q - std::max(floor, Tet10RequiredQuality(straight, qualityRatio, minQuality));
    // (only a breach counts: the search's objective and stopping point stay the same
    // wherever the straight shape keeps its bar, and so does its work)
    return straight >= straightFloor ? m : std::min(m, straight - straightFloor);
  }
  double lo, hi;
  Tet10JacobianBounds(x, lo, hi, 1);
  return -1.0 + std::max(-1.0, std::min(0.0, lo / det4));
}
} // namespace

Id FitWithFreeNodes(std::vector<double>& pts, const std::vector<Id>& conn,
  const std::vector<Id>& nodes, const std::vector<double>& targets, std::vector<double>& alpha,
  const std::vector<char>& isFree, double qualityRatio, double minQuality,
  std::int64_t evaluationsPerCell)
{
  // Why it is built so:
  // - Only boundary mid-edge nodes carry the surface; corners and interior mid-edge
  //   nodes are free to go wherever keeps their elements acceptable, so a node pulled
  //   back for quality can often reach the surface after its neighbours make room.
  // - The objective (the worst margin around a node: a minimum over sampled scaled
  //   Jacobians and a Bernstein bound) is not smooth, so a derivative-free pattern search
  //   (axis steps, halved on failure) is used rather than Newton or Ceres; it only ever
  //   accepts a move that raises the worst margin, so no element gets worse on the way.
  // - Each node's attempt is all or nothing: positions are restored unless every touched
  //   element passes the acceptance test itself, so a failed attempt leaves no trace.
  // - The work is bounded by evaluations per cell (the caller's budget), so the fit costs
  //   at most a fixed multiple of the mesh size whatever the input.
  const Id np = static_cast<Id>(pts.size() / 3);
  const Id nc = static_cast<Id>(conn.size() / 10);
  // Cells around every node (CSR).
  std::vector<Id> off(np + 1, 0), cells(conn.size());
  for (Id c = 0; c < nc; ++c)
    for (int a = 0; a < 10; ++a)
      ++off[conn[10 * c + a] + 1];
  for (Id i = 0; i < np; ++i)
    off[i + 1] += off[i];
  {
    std::vector<Id> fill(off.begin(), off.end() - 1);
    for (Id c = 0; c < nc; ++c)
      for (int a = 0; a < 10; ++a)
        cells[fill[conn[10 * c + a]]++] = c;
  }
  // The floor each element keeps whatever the corners do (see Margin).
  std::vector<double> floor(nc), straightFloor(nc);
  for (Id c = 0; c < nc; ++c)
  {
    double x[12];
    for (int a = 0; a < 4; ++a)
      for (int d = 0; d < 3; ++d)
        x[3 * a + d] = pts[3 * conn[10 * c + a] + d];
    const double straight = Tet4ScaledJacobian(x);
    floor[c] = std::min(minQuality, 0.999 * straight);
    straightFloor[c] = std::min(minQuality, straight);
  }
  // Work limit: margin evaluations, proportional to the mesh size.
  std::int64_t evaluations = 0;
  const std::int64_t budget = evaluationsPerCell * nc;
  auto margin = [&](Id c) {
    ++evaluations;
    double x[30];
    for (int a = 0; a < 10; ++a)
      for (int d = 0; d < 3; ++d)
        x[3 * a + d] = pts[3 * conn[10 * c + a] + d];
    return Margin(x, qualityRatio, minQuality, floor[c], straightFloor[c]);
  };
  auto worstAround = [&](Id i) {
    double w = 1e300;
    for (Id k = off[i]; k < off[i + 1]; ++k)
      w = std::min(w, margin(cells[k]));
    return w;
  };
  auto edgeLength = [&](Id f) {
    const Id c = cells[off[f]];
    for (int a = 4; a < 10; ++a)
      if (conn[10 * c + a] == f)
      {
        const Id u = conn[10 * c + TetEdgeCorners[a - 4][0]];
        const Id v = conn[10 * c + TetEdgeCorners[a - 4][1]];
        double s = 0.0;
        for (int d = 0; d < 3; ++d)
          s += (pts[3 * u + d] - pts[3 * v + d]) * (pts[3 * u + d] - pts[3 * v + d]);
        return std::sqrt(s);
      }
    double s = 0.0; // a corner: its mean edge length in its first cell
    for (int a = 0; a < 4; ++a)
      s += std::sqrt(
        (pts[3 * conn[10 * c + a]] - pts[3 * f]) * (pts[3 * conn[10 * c + a]] - pts[3 * f]) +
        (pts[3 * conn[10 * c + a] + 1] - pts[3 * f + 1]) *
          (pts[3 * conn[10 * c + a] + 1] - pts[3 * f + 1]) +
        (pts[3 * conn[10 * c + a] + 2] - pts[3 * f + 2]) *
          (pts[3 * conn[10 * c + a] + 2] - pts[3 * f + 2]));
    return s / 3.0;
  };
  // Pattern search on free node f: maximise the worst margin around it.
  auto improve = [&](Id f) {
    const double L = edgeLength(f);
    double best = worstAround(f);
    double step = 0.2 * L;
    for (int it = 0; it < 40 && step > 0.005 * L && best < 0.02 && evaluations < budget; ++it)
    {
      bool moved = false;
      for (int dir = 0; dir < 6 && !moved; ++dir)
      {
        const int d = dir / 2;
        const double s = dir % 2 ? -step : step;
        pts[3 * f + d] += s;
        const double w = worstAround(f);
        if (w > best)
        {
          best = w;
          moved = true;
        }
        else
          pts[3 * f + d] -= s;
      }
      if (!moved)
        step *= 0.5;
    }
  };

  Id fitted = 0;
  std::vector<Id> freeNodes, touched;
  std::vector<double> saved;
  for (size_t k = 0; k < nodes.size() && evaluations < budget; ++k)
  {
    if (alpha[k] >= 1.0)
      continue;
    const Id m = nodes[k];
    const double keep[3] = { pts[3 * m], pts[3 * m + 1], pts[3 * m + 2] };
    for (int d = 0; d < 3; ++d)
      pts[3 * m + d] = targets[3 * k + d];
    // Failing cells; give up when one of them has no free node.
    freeNodes.clear();
    bool hopeless = false, anyFailing = false;
    for (Id j = off[m]; j < off[m + 1] && !hopeless; ++j)
    {
      const Id c = cells[j];
      if (margin(c) >= 0.0)
        continue;
      anyFailing = true;
      bool hasFree = false;
      for (int a = 0; a < 10; ++a)
        if (isFree[conn[10 * c + a]])
        {
          hasFree = true;
          freeNodes.push_back(conn[10 * c + a]);
        }
      hopeless = !hasFree;
    }
    std::sort(freeNodes.begin(), freeNodes.end());
    freeNodes.erase(std::unique(freeNodes.begin(), freeNodes.end()), freeNodes.end());
    bool ok = !anyFailing;
    if (!ok && !hopeless)
    {
      saved.clear();
      for (Id f : freeNodes)
        saved.insert(saved.end(), &pts[3 * f], &pts[3 * f] + 3);
      for (int sweep = 0; sweep < 3 && !ok; ++sweep)
      {
        for (Id f : freeNodes)
          if (worstAround(f) < 0.0)
            improve(f);
        const double w = worstAround(m);
        if (w < -1.0 && sweep > 0)
          break; // still not valid after two sweeps: not worth more work
        ok = w >= 0.0;
        for (size_t i = 0; ok && i < freeNodes.size(); ++i)
          ok = worstAround(freeNodes[i]) >= 0.0;
      }
      if (ok) // confirm with the acceptance test itself
      {
        touched.assign(cells.begin() + off[m], cells.begin() + off[m + 1]);
        for (Id f : freeNodes)
          touched.insert(touched.end(), cells.begin() + off[f], cells.begin() + off[f + 1]);
        for (size_t i = 0; ok && i < touched.size(); ++i)
        {
          double x[30];
          for (int a = 0; a < 10; ++a)
            for (int d = 0; d < 3; ++d)
              x[3 * a + d] = pts[3 * conn[10 * touched[i] + a] + d];
          ok = Tet10Acceptable(x, qualityRatio, minQuality) &&
            Tet10MinScaledJacobian(x) >= floor[touched[i]] &&
            Tet4ScaledJacobian(x) >= straightFloor[touched[i]];
        }
      }
      if (!ok)
        for (size_t i = 0; i < freeNodes.size(); ++i)
          for (int d = 0; d < 3; ++d)
            pts[3 * freeNodes[i] + d] = saved[3 * i + d];
    }
    if (ok)
    {
      alpha[k] = 1.0;
      ++fitted;
    }
    else
      for (int d = 0; d < 3; ++d)
        pts[3 * m + d] = keep[d];
  }
  return fitted;
}
} // namespace hoembed
