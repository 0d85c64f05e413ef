#include "hoembedCurvedBoundary.h"

#include "hoembedElementGeometry.h"

#include <algorithm>
#include <deque>
#include <limits>

namespace hoembed
{
using Id = std::int64_t;

double Tet10RequiredQuality(double straight, double qualityRatio, double minQuality)
{
  // A straight shape at the floor keeps the floor itself (less the round-off between the
  // straight tet10's sampled value and the tet4's): 0.999 of it alone let curving take a
  // cell whose straight shape is 0.05002 to 0.04997 (fertility at 10000 elements), below
  // the floor where the tet4 mesh has none.
  const double keep = straight >= minQuality ? (1.0 - 1e-12) * straight : 0.999 * straight;
  return std::max(qualityRatio * straight, std::min(minQuality, keep));
}

bool Tet10Acceptable(
  const double* x, double qualityRatio, double minQuality, const Tet10Check& extra)
{
  const double det4 = Tet4JacobianDeterminant(x);
  if (!(det4 > 0.0))
  {
    return false;
  }
  double lo, hi;
  Tet10JacobianBounds(x, lo, hi, 3);
  if (!(lo > 0.0))
  {
    return false;
  }
  // Corner nodes are the first four: the straight tet4's quality.
  const double straight = Tet4ScaledJacobian(x);
  return Tet10MinScaledJacobian(x) >= Tet10RequiredQuality(straight, qualityRatio, minQuality) &&
    (!extra || extra(x));
}

CurvingResult CurveMidEdgeNodes(std::vector<double>& points, const std::vector<Id>& conn,
  const std::vector<Id>& nodes, const std::vector<double>& targets, double qualityRatio,
  double minQuality, const Tet10Check& extra)
{
  CurvingResult result;
  const Id nn = static_cast<Id>(nodes.size());
  const Id np = static_cast<Id>(points.size() / 3);
  const Id nc = static_cast<Id>(conn.size() / 10);
  result.Alpha.assign(nn, 1.0);

  std::vector<double> straight(3 * nn);
  std::vector<Id> slot(np, -1); // node id -> index in `nodes`
  for (Id k = 0; k < nn; ++k)
  {
    slot[nodes[k]] = k;
    for (int d = 0; d < 3; ++d)
    {
      straight[3 * k + d] = points[3 * nodes[k] + d];
      points[3 * nodes[k] + d] = targets[3 * k + d];
    }
  }
  auto place = [&](Id k) {
    for (int d = 0; d < 3; ++d)
    {
      points[3 * nodes[k] + d] =
        straight[3 * k + d] + result.Alpha[k] * (targets[3 * k + d] - straight[3 * k + d]);
    }
  };

  // Cells around each listed node (CSR).
  std::vector<Id> off(nn + 1, 0);
  for (Id c = 0; c < nc; ++c)
    for (int a = 4; a < 10; ++a)
      if (slot[conn[10 * c + a]] >= 0)
        ++off[slot[conn[10 * c + a]] + 1];
  for (Id k = 0; k < nn; ++k)
    off[k + 1] += off[k];
  std::vector<Id> cells(off[nn]);
  {
    std::vector<Id> fill(off.begin(), off.end() - 1);
    for (Id c = 0; c < nc; ++c)
      for (int a = 4; a < 10; ++a)
        if (slot[conn[10 * c + a]] >= 0)
          cells[fill[slot[conn[10 * c + a]]]++] = c;
  }

  std::vector<char> queued(nc, 0);
  std::deque<Id> queue;
  for (Id c : cells)
  {
    if (!queued[c])
    {
      queued[c] = 1;
      queue.push_back(c);
    }
  }
  auto gather = [&](Id c, double* x) {
    for (int a = 0; a < 10; ++a)
      for (int d = 0; d < 3; ++d)
        x[3 * a + d] = points[3 * conn[10 * c + a] + d];
  };

  Id budget = 50 * (nc + 1);
  while (!queue.empty())
  {
    const Id c = queue.front();
    queue.pop_front();
    queued[c] = 0;
    double x[30];
    gather(c, x);
    if (Tet10Acceptable(x, qualityRatio, minQuality, extra))
    {
      continue;
    }
    // Pull back one node at a time, the one whose pull-back helps most, and only as far
    // as needed; fall back on pulling it all the way when the budget is spent.
    for (int guard = 0; guard < 6; ++guard)
    {
      Id best = -1;
      double bestBound = -std::numeric_limits<double>::infinity();
      for (int a = 4; a < 10; ++a)
      {
        const Id k = slot[conn[10 * c + a]];
        if (k < 0 || result.Alpha[k] <= 0.0)
          continue;
        const double keep = result.Alpha[k];
        result.Alpha[k] = 0.0;
        place(k);
        gather(c, x);
        double lo, hi;
        hoembed::Tet10JacobianBounds(x, lo, hi, 1);
        if (Tet10Acceptable(x, qualityRatio, minQuality, extra))
          lo = std::numeric_limits<double>::max();
        if (lo > bestBound)
        {
          bestBound = lo;
          best = k;
        }
        result.Alpha[k] = keep;
        place(k);
      }
      if (best < 0)
        break; // nothing left to pull back
      const double alpha0 = result.Alpha[best];
      double lo = 0.0, hi = 1.0;
      if (--budget > 0)
      {
        for (int it = 0; it < 12; ++it)
        {
          const double beta = 0.5 * (lo + hi);
          result.Alpha[best] = alpha0 * beta;
          place(best);
          gather(c, x);
          (Tet10Acceptable(x, qualityRatio, minQuality, extra) ? lo : hi) = beta;
        }
      }
      result.Alpha[best] = alpha0 * lo;
      place(best);
      for (Id i = off[best]; i < off[best + 1]; ++i)
      {
        if (cells[i] != c && !queued[cells[i]])
        {
          queued[cells[i]] = 1;
          queue.push_back(cells[i]);
        }
      }
      gather(c, x);
      if (Tet10Acceptable(x, qualityRatio, minQuality, extra))
        break;
    }
  }
  for (Id k = 0; k < nn; ++k)
  {
    (result.Alpha[k] >= 1.0 ? result.Curved : result.Relaxed)++;
  }
  return result;
}

std::vector<double> ExtendMidNodeDisplacement(const std::vector<double>& points,
  const std::vector<Id>& conn, const std::vector<double>& fixedDisp,
  const std::vector<char>& isFixed, int iterations)
{
  const Id np = static_cast<Id>(points.size() / 3);
  const Id nc = static_cast<Id>(conn.size() / 10);
  std::vector<double> u(fixedDisp);
  std::vector<char> isMid(np, 0);
  for (Id c = 0; c < nc; ++c)
    for (int a = 4; a < 10; ++a)
      isMid[conn[10 * c + a]] = 1;
  for (Id i = 0; i < np; ++i)
    if (!isFixed[i])
      u[3 * i] = u[3 * i + 1] = u[3 * i + 2] = 0.0;
  std::vector<double> sum(3 * np), next;
  std::vector<int> count(np);
  for (int it = 0; it < iterations; ++it)
  {
    std::fill(sum.begin(), sum.end(), 0.0);
    std::fill(count.begin(), count.end(), 0);
    for (Id c = 0; c < nc; ++c)
    {
      double s[3] = { 0, 0, 0 };
      for (int a = 4; a < 10; ++a)
        for (int d = 0; d < 3; ++d)
          s[d] += u[3 * conn[10 * c + a] + d];
      for (int a = 4; a < 10; ++a)
      {
        const Id m = conn[10 * c + a];
        if (isFixed[m])
          continue;
        for (int d = 0; d < 3; ++d)
          sum[3 * m + d] += s[d] - u[3 * m + d];
        count[m] += 5;
      }
    }
    for (Id i = 0; i < np; ++i)
      if (isMid[i] && !isFixed[i] && count[i] > 0)
        for (int d = 0; d < 3; ++d)
          u[3 * i + d] = sum[3 * i + d] / count[i];
  }
  return u;
}
} // namespace hoembed
