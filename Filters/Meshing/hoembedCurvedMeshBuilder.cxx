#include "hoembedCurvedMeshBuilder.h"

#include "hoembedBoundaryCrossings.h"
#include "hoembedCsr.h"
#include "hoembedCurvedBoundary.h"
#include "hoembedFreeNodeFit.h"
#include "hoembedLinearMeshSmoothing.h"
#include "hoembedElementGeometry.h"
#include "hoembedQuadraticMap.h"
#include "hoembedShapeFunctions.h"
#include "hoembedTetGenBridge.h"
#include "hoembedTetMeshTopology.h"
#include "hoembedVector3.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <unordered_map>

namespace hoembed
{
namespace
{
using Id = std::int64_t;
constexpr double kPi = 3.141592653589793;

double TetDet(const std::vector<double>& p, const Id* t)
{
  double x[12];
  for (int a = 0; a < 4; ++a)
    for (int d = 0; d < 3; ++d)
      x[3 * a + d] = p[3 * t[a] + d];
  return Tet4JacobianDeterminant(x);
}

double TetQuality(const std::vector<double>& p, const Id* t)
{
  double x[12];
  for (int a = 0; a < 4; ++a)
    for (int d = 0; d < 3; ++d)
      x[3 * a + d] = p[3 * t[a] + d];
  return Tet4ScaledJacobian(x);
}

// Number of pieces of the tet mesh connected through faces.
Id CountFaceComponents(const std::vector<Id>& tets, Id nPts)
{
  const Id nt = static_cast<Id>(tets.size() / 4);
  TetMeshTopology topo;
  if (!topo.Build(tets.data(), nt, 4, nPts).empty())
    return nt; // inconsistent: as bad as it gets
  std::vector<char> seen(nt, 0);
  std::vector<Id> stack;
  Id components = 0;
  for (Id s = 0; s < nt; ++s)
  {
    if (seen[s])
      continue;
    ++components;
    seen[s] = 1;
    stack.push_back(s);
    while (!stack.empty())
    {
      const Id t = stack.back();
      stack.pop_back();
      for (int f = 0; f < 4; ++f)
      {
        const Id n = topo.FaceNeighbor[4 * t + f];
        if (n >= 0 && !seen[n])
        {
          seen[n] = 1;
          stack.push_back(n);
        }
      }
    }
  }
  return components;
}

// n += the unit normal of the triangle f (3 point ids into pts).
void AddUnitNormal(const double* pts, const Id* f, double n[3])
{
  double a[3], b[3], fn[3];
  for (int d = 0; d < 3; ++d)
  {
    a[d] = pts[3 * f[1] + d] - pts[3 * f[0] + d];
    b[d] = pts[3 * f[2] + d] - pts[3 * f[0] + d];
  }
  hoembed::Cross(a, b, fn);
  hoembed::Normalize(fn);
  for (int d = 0; d < 3; ++d)
    n[d] += fn[d];
}
// Unit normal of boundary edge e of the linear mesh: the mean of its faces' normals.
bool BoundaryEdgeNormal(
  const std::vector<double>& pts, const TetMeshTopology& topo4, Id e, double n[3])
{
  const Id u = topo4.BoundaryEdgeNodes[3 * e], v = topo4.BoundaryEdgeNodes[3 * e + 1];
  n[0] = n[1] = n[2] = 0.0;
  for (Id k = topo4.NodeFaceOffsets[u]; k < topo4.NodeFaceOffsets[u + 1]; ++k)
  {
    const Id* f = &topo4.BoundaryFaceNodes[3 * topo4.NodeFaces[k]];
    if (f[0] != v && f[1] != v && f[2] != v)
      continue;
    AddUnitNormal(pts.data(), f, n);
  }
  return hoembed::Normalize(n) > 0.0;
}

// Target of the mid-edge node of boundary edge e on the fine surface: where the edge's
// normal line through its midpoint S first meets the surface (within half the edge
// length), else the closest point to S.
void MidEdgeTarget(const std::vector<double>& pts, const TetMeshTopology& topo4, Id e,
  const SurfaceQueries& surface, bool rayFirst, double target[3])
{
  const Id u = topo4.BoundaryEdgeNodes[3 * e], v = topo4.BoundaryEdgeNodes[3 * e + 1];
  double S[3], n[3];
  for (int d = 0; d < 3; ++d)
    S[d] = 0.5 * (pts[3 * u + d] + pts[3 * v + d]);
  double closest[3];
  surface.Closest(S, closest);
  const double dist = std::sqrt(hoembed::Distance2(S, closest));
  if (rayFirst && BoundaryEdgeNormal(pts, topo4, e, n))
  {
    const double L = std::sqrt(hoembed::Distance2(&pts[3 * u], &pts[3 * v]));
    double best = std::numeric_limits<double>::max();
    for (double sgn : { 1.0, -1.0 })
    {
      double end[3], hit[3];
      for (int d = 0; d < 3; ++d)
        end[d] = S[d] + sgn * 0.5 * L * n[d];
      if (surface.Ray(S, end, hit))
      {
        const double dh = std::sqrt(hoembed::Distance2(hit, S));
        if (dh < best && dh < 3.0 * dist + 1e-12 * L)
        {
          best = dh;
          target[0] = hit[0];
          target[1] = hit[1];
          target[2] = hit[2];
        }
      }
    }
    if (best < std::numeric_limits<double>::max())
      return;
  }
  target[0] = closest[0];
  target[1] = closest[1];
  target[2] = closest[2];
}

// True when `target` is too far from the straight position of boundary edge e's
// mid-edge node to be meant for it, or the surface there faces the other way (the limit
// is off when `limit` is 0); the target is then that straight position.
bool KeepOnEnvelope(const std::vector<double>& pts, const TetMeshTopology& topo4, Id e,
  double limit, const SurfaceQueries& surface, double target[3])
{
  if (!(limit > 0.0))
    return false;
  const Id u = topo4.BoundaryEdgeNodes[3 * e], v = topo4.BoundaryEdgeNodes[3 * e + 1];
  double S[3], n[3];
  for (int d = 0; d < 3; ++d)
    S[d] = 0.5 * (pts[3 * u + d] + pts[3 * v + d]);
  const bool faces =
    !surface.Faces || !BoundaryEdgeNormal(pts, topo4, e, n) || surface.Faces(target, n);
  if (faces && hoembed::Distance2(S, target) <= limit * limit)
    return false;
  for (int d = 0; d < 3; ++d)
    target[d] = S[d];
  return true;
}

// A boundary mid-edge node pulled back from its closest point gets a second chance: other
// points of the fine surface near its straight position (along the edge's normal, and
// the closest points to a ring of points around it), nearest first; the first that keeps
// every element around the node acceptable is taken (alpha becomes 1).
void RetargetPulledBackNodes(std::vector<double>& pts, const std::vector<Id>& conn,
  const TetMeshTopology& topo4, const std::vector<Id>& nodes, std::vector<double>& alpha, Id nbe,
  const SurfaceQueries& surface, double qualityRatio, double minQuality, const Tet10Check& extra,
  double maxDistance)
{
  const Id nc = static_cast<Id>(conn.size() / 10);
  std::unordered_map<Id, std::vector<Id>> cellsOf;
  for (Id e = 0; e < nbe; ++e)
    if (alpha[e] < 1.0)
      cellsOf[nodes[e]];
  if (cellsOf.empty())
    return;
  for (Id c = 0; c < nc; ++c)
    for (int a = 4; a < 10; ++a)
    {
      auto it = cellsOf.find(conn[10 * c + a]);
      if (it != cellsOf.end())
        it->second.push_back(c);
    }
  auto acceptable = [&](Id m) {
    for (Id c : cellsOf[m])
    {
      double x[30];
      for (int a = 0; a < 10; ++a)
        for (int d = 0; d < 3; ++d)
          x[3 * a + d] = pts[3 * conn[10 * c + a] + d];
      if (!Tet10Acceptable(x, qualityRatio, minQuality, extra))
        return false;
    }
    return true;
  };
  for (Id e = 0; e < nbe; ++e)
  {
    if (alpha[e] >= 1.0)
      continue;
    const Id m = nodes[e];
    const Id u = topo4.BoundaryEdgeNodes[3 * e], v = topo4.BoundaryEdgeNodes[3 * e + 1];
    double S[3], n[3], t1[3], t2[3];
    for (int d = 0; d < 3; ++d)
      S[d] = 0.5 * (pts[3 * u + d] + pts[3 * v + d]);
    const double L = std::sqrt(hoembed::Distance2(&pts[3 * u], &pts[3 * v]));
    if (!BoundaryEdgeNormal(pts, topo4, e, n))
      continue;
    hoembed::Perpendiculars(n, t1, t2);
    std::vector<std::array<double, 4>> candidates; // distance to S, point
    auto add = [&](const double p[3]) {
      const double dist = std::sqrt(hoembed::Distance2(p, S));
      if (!(maxDistance > 0.0) || (dist <= maxDistance && (!surface.Faces || surface.Faces(p, n))))
        candidates.push_back({ dist, p[0], p[1], p[2] });
    };
    for (double sgn : { 1.0, -1.0 })
    {
      double end[3], hit[3];
      for (int d = 0; d < 3; ++d)
        end[d] = S[d] + sgn * 0.5 * L * n[d];
      if (surface.Ray(S, end, hit))
        add(hit);
    }
    for (double r : { 0.05, 0.1, 0.2, 0.3, 0.4, 0.5, 0.7 })
      for (int k = 0; k < 16; ++k)
      {
        const double th = 2.0 * kPi * k / 16.0;
        double q[3], cp[3];
        for (int d = 0; d < 3; ++d)
          q[d] = S[d] + r * L * (std::cos(th) * t1[d] + std::sin(th) * t2[d]);
        surface.Closest(q, cp);
        add(cp);
      }
    if (surface.VerticesWithin)
    {
      std::vector<double> near;
      surface.VerticesWithin(S, 0.6 * L, near);
      for (size_t k = 0; k < near.size() / 3; ++k)
        add(&near[3 * k]);
    }
    std::sort(candidates.begin(), candidates.end());
    double keep[3] = { pts[3 * m], pts[3 * m + 1], pts[3 * m + 2] };
    bool placed = false;
    for (const auto& c : candidates)
    {
      for (int d = 0; d < 3; ++d)
        pts[3 * m + d] = c[1 + d];
      if (acceptable(m))
      {
        placed = true;
        break;
      }
    }
    if (placed)
      alpha[e] = 1.0;
    else
      for (int d = 0; d < 3; ++d)
        pts[3 * m + d] = keep[d];
  }
}

// Boundary corners onto the surface, where their tets stay valid and keep half their
// quality, and stay above the quality floor `minQuality` (a tet already below it keeps
// all it has: curving cannot mend a poor straight shape, so none is made here); full
// move, else a half, a quarter, else none.
void ProjectCorners(std::vector<double>& pts, const std::vector<Id>& tets,
  const TetMeshTopology& topo, const SurfaceQueries& surface, double maxDistance, double minQuality)
{
  const Id nPts = static_cast<Id>(pts.size() / 3);
  std::vector<Id> off, around;
  TetsAroundCorners(tets, nPts, off, around);
  std::vector<double> before;
  for (Id i = 0; i < nPts; ++i)
  {
    if (!topo.IsBoundaryNode(i))
      continue;
    double x0[3] = { pts[3 * i], pts[3 * i + 1], pts[3 * i + 2] }, target[3];
    surface.Closest(x0, target);
    if (maxDistance > 0.0 && hoembed::Distance2(x0, target) > maxDistance * maxDistance)
      continue;
    if (maxDistance > 0.0 && surface.Faces)
    {
      // the corner's outward normal: the sum of its boundary faces' normals
      double n[3] = { 0.0, 0.0, 0.0 };
      for (Id k = topo.NodeFaceOffsets[i]; k < topo.NodeFaceOffsets[i + 1]; ++k)
      {
        const Id* f = &topo.BoundaryFaceNodes[3 * topo.NodeFaces[k]];
        AddUnitNormal(pts.data(), f, n);
      }
      if (hoembed::Normalize(n) > 0.0 && !surface.Faces(target, n))
        continue;
    }
    before.clear();
    for (Id k = off[i]; k < off[i + 1]; ++k)
    {
      const double q = TetQuality(pts, &tets[4 * around[k]]);
      before.push_back(std::max(0.5 * q, std::min(minQuality, q)));
    }
    for (double a : { 1.0, 0.5, 0.25, 0.0 })
    {
      for (int d = 0; d < 3; ++d)
        pts[3 * i + d] = x0[d] + a * (target[d] - x0[d]);
      bool ok = true;
      for (Id k = off[i]; ok && k < off[i + 1]; ++k)
      {
        const Id* t = &tets[4 * around[k]];
        ok = TetDet(pts, t) > 0.0 && TetQuality(pts, t) >= before[k - off[i]];
      }
      if (ok)
        break;
    }
  }
}

// Straight tets below the quality floor (slivers TetGen leaves where it may not split
// the boundary) get their corners moved: a pattern search per corner (axis steps from a
// fifth of the mean edge length at the corner, halved on failure, at most that far from
// where it started) that raises the worst scaled Jacobian of the tets around it. Every
// tet stays positive and no tet around the corner drops below the floor or below what it
// had, so nothing is made worse; boundary corners may leave the surface by that much
// (their mid-edge nodes still go onto it). Returns the number of corners moved.
Id ImprovePoorTets(std::vector<double>& pts, const std::vector<Id>& tets, double minQuality)
{
  const Id nPts = static_cast<Id>(pts.size() / 3);
  const Id nTets = static_cast<Id>(tets.size() / 4);
  if (!(minQuality > 0.0))
    return 0;
  std::vector<Id> off, around;
  TetsAroundCorners(tets, nPts, off, around);
  // the worst margin around corner v: quality over its bar (the floor, or less for a tet
  // already below it), the smallest first; -inf when a tet is not positive
  std::vector<double> bar(nTets);
  for (Id t = 0; t < nTets; ++t)
    bar[t] = std::min(minQuality, TetQuality(pts, &tets[4 * t]));
  auto worst = [&](Id v) {
    double w = std::numeric_limits<double>::infinity();
    for (Id k = off[v]; k < off[v + 1]; ++k)
    {
      const Id* t = &tets[4 * around[k]];
      if (!(TetDet(pts, t) > 0.0))
        return -std::numeric_limits<double>::infinity();
      w = std::min(w, TetQuality(pts, t));
    }
    return w;
  };
  auto keepsBars = [&](Id v) {
    for (Id k = off[v]; k < off[v + 1]; ++k)
      if (TetQuality(pts, &tets[4 * around[k]]) < bar[around[k]])
        return false;
    return true;
  };
  Id moved = 0;
  for (int sweep = 0; sweep < 3; ++sweep)
  {
    bool any = false;
    for (Id t = 0; t < nTets; ++t)
    {
      if (TetQuality(pts, &tets[4 * t]) >= minQuality)
        continue;
      for (int a = 0; a < 4; ++a)
      {
        const Id v = tets[4 * t + a];
        const double x0[3] = { pts[3 * v], pts[3 * v + 1], pts[3 * v + 2] };
        double L = 0.0;
        for (int b = 0; b < 4; ++b)
          L += std::sqrt(hoembed::Distance2(x0, &pts[3 * tets[4 * t + b]])) / 3.0;
        const double reach = 0.2 * L;
        double best = worst(v), step = reach;
        const double start = best;
        for (int it = 0; it < 60 && step > 0.01 * reach; ++it)
        {
          bool better = false;
          for (int dir = 0; dir < 6 && !better; ++dir)
          {
            const int d = dir / 2;
            const double s = dir % 2 ? -step : step;
            pts[3 * v + d] += s;
            const double w = std::fabs(pts[3 * v + d] - x0[d]) <= reach ? worst(v) : -1.0;
            if (w > best && keepsBars(v))
            {
              best = w;
              better = true;
            }
            else
              pts[3 * v + d] -= s;
          }
          if (!better)
            step *= 0.5;
        }
        if (best > start)
        {
          ++moved;
          any = true;
        }
      }
    }
    if (!any)
      break;
  }
  return moved;
}

struct QuadraticNodes
{
  std::vector<Id> Conn;       // 10 per cell
  std::vector<Id> EdgeMid;    // boundary edge e -> its mid-edge node
  std::vector<Id> MidCorners; // 2 per node: the edge's corners (-1 for corner nodes)
  Id NumberOfCorners = 0;
};

QuadraticNodes AddMidEdgeNodes(
  std::vector<double>& pts, const std::vector<Id>& tets, const TetMeshTopology& topo)
{
  QuadraticNodes q;
  const Id nTets = static_cast<Id>(tets.size() / 4);
  q.NumberOfCorners = static_cast<Id>(pts.size() / 3);
  q.MidCorners.assign(2 * q.NumberOfCorners, -1);
  const auto nc = static_cast<std::uint64_t>(q.NumberOfCorners);
  std::unordered_map<std::uint64_t, Id> mids;
  mids.reserve(static_cast<size_t>(8 * nTets));
  q.Conn.resize(10 * nTets);
  for (Id t = 0; t < nTets; ++t)
  {
    const Id* c = &tets[4 * t];
    for (int a = 0; a < 4; ++a)
      q.Conn[10 * t + a] = c[a];
    for (int e = 0; e < 6; ++e)
    {
      const Id u = std::min(c[TetEdgeCorners[e][0]], c[TetEdgeCorners[e][1]]);
      const Id v = std::max(c[TetEdgeCorners[e][0]], c[TetEdgeCorners[e][1]]);
      auto it = mids.find(static_cast<std::uint64_t>(u) * nc + static_cast<std::uint64_t>(v));
      if (it == mids.end())
      {
        it = mids
               .emplace(static_cast<std::uint64_t>(u) * nc + static_cast<std::uint64_t>(v),
                 static_cast<Id>(pts.size() / 3))
               .first;
        for (int d = 0; d < 3; ++d)
          pts.push_back(0.5 * (pts[3 * u + d] + pts[3 * v + d]));
        q.MidCorners.push_back(u);
        q.MidCorners.push_back(v);
      }
      q.Conn[10 * t + 4 + e] = it->second;
    }
  }
  const Id nbe = topo.GetNumberOfBoundaryEdges();
  q.EdgeMid.resize(nbe);
  for (Id e = 0; e < nbe; ++e)
  {
    const auto u = static_cast<std::uint64_t>(topo.BoundaryEdgeNodes[3 * e]);
    const auto v = static_cast<std::uint64_t>(topo.BoundaryEdgeNodes[3 * e + 1]);
    q.EdgeMid[e] = mids.at(u * nc + v);
  }
  return q;
}

// Boundary mid-edge nodes to their surface targets (`envelope` marks those with no
// surface point near: they stay), interior ones by the harmonic
// extension of those moves, pulled back where elements are not acceptable. Fills
// `targets` (3 per boundary edge first, then the interior nodes that moved).
CurvingResult CurveTowardsSurface(CurvedMesh& out, const TetMeshTopology& topo,
  const QuadraticNodes& quad, const SurfaceQueries& surface, const CurvedMeshOptions& options,
  std::vector<double>& targets, std::vector<char>& envelope)
{
  const Id nPts = static_cast<Id>(out.Points.size() / 3);
  const Id nbe = topo.GetNumberOfBoundaryEdges();
  std::vector<Id> nodes(quad.EdgeMid);
  envelope.assign(nbe, 0);
  targets.assign(3 * nbe, 0.0);
  std::vector<double> disp(3 * nPts, 0.0);
  std::vector<char> fixed(nPts, 0);
  for (Id e = 0; e < nbe; ++e)
  {
    MidEdgeTarget(out.Points, topo, e, surface, true, &targets[3 * e]);
    envelope[e] =
      KeepOnEnvelope(out.Points, topo, e, options.MaxTargetDistance, surface, &targets[3 * e]);
    fixed[nodes[e]] = 1;
    for (int d = 0; d < 3; ++d)
      disp[3 * nodes[e] + d] = targets[3 * e + d] - out.Points[3 * nodes[e] + d];
  }
  disp = ExtendMidNodeDisplacement(out.Points, out.Conn, disp, fixed, 20);
  for (Id i = quad.NumberOfCorners; i < nPts; ++i)
  {
    const double* di = &disp[3 * i];
    if (fixed[i] || (di[0] == 0.0 && di[1] == 0.0 && di[2] == 0.0))
      continue;
    nodes.push_back(i);
    for (int d = 0; d < 3; ++d)
      targets.push_back(out.Points[3 * i + d] + di[d]);
  }
  return CurveMidEdgeNodes(
    out.Points, out.Conn, nodes, targets, options.QualityRatio, options.MinimumQuality);
}

// Work limit of the free-node fit, in element evaluations per cell. The quality floor
// (CurvedMeshOptions::MinimumQuality) pulls back more nodes than validity alone, and the
// fit brings most of them back given the work (Benchmarks/HISTORY.md, "Element
// quality"): on scorpion at 1000 elements it brings back 39 of 106 with 300, 65 with
// 2000, as many with 6000.
constexpr std::int64_t FitEvaluationsPerCell = 2000;

// Second chances for the pulled-back boundary nodes: other surface points near them, then
// moves of the free nodes around them (only boundary mid-edge nodes are meant to lie on
// the surface: the others, and the corners, may move to make room for the boundary ones
// still pulled back; corners then leave the surface a little, which the mid-edge nodes
// make up for), then the other surface points again.
void SecondChances(CurvedMesh& out, const TetMeshTopology& topo, const QuadraticNodes& quad,
  const SurfaceQueries& surface, const CurvedMeshOptions& options,
  const std::vector<double>& targets, CurvingResult& curving)
{
  const Id nPts = static_cast<Id>(out.Points.size() / 3);
  const Id nbe = topo.GetNumberOfBoundaryEdges();
  for (int pass = 0; pass < 4; ++pass) // a node placed can free its neighbours
    RetargetPulledBackNodes(out.Points, out.Conn, topo, quad.EdgeMid, curving.Alpha, nbe, surface,
      options.QualityRatio, options.MinimumQuality, Tet10Check(), options.MaxTargetDistance);
  std::vector<char> isFree(nPts, 0);
  for (Id i = 0; i < nPts; ++i)
    isFree[i] = i < quad.NumberOfCorners || !out.BoundaryNode[i] ? 1 : 0;
  std::vector<double> alphaB(curving.Alpha.begin(), curving.Alpha.begin() + nbe);
  std::vector<double> targetsB(targets.begin(), targets.begin() + 3 * nbe);
  FitWithFreeNodes(out.Points, out.Conn, quad.EdgeMid, targetsB, alphaB, isFree,
    options.QualityRatio, options.MinimumQuality, FitEvaluationsPerCell);
  std::copy(alphaB.begin(), alphaB.end(), curving.Alpha.begin());
  RetargetPulledBackNodes(out.Points, out.Conn, topo, quad.EdgeMid, curving.Alpha, nbe, surface,
    options.QualityRatio, options.MinimumQuality, Tet10Check(), options.MaxTargetDistance);
}

// The extra test is costly: run it once on the result, and pull back (from the straight
// position, with the full test) only the nodes of the cells that fail it.
void ApplyExtraCheck(CurvedMesh& out, const QuadraticNodes& quad, Id nbe,
  const CurvedMeshOptions& options, CurvingResult& curving)
{
  const Id nPts = static_cast<Id>(out.Points.size() / 3);
  const Id nTets = static_cast<Id>(out.Conn.size() / 10);
  std::vector<char> mark(nPts, 0);
  std::vector<Id> redo;
  std::vector<double> redoTargets;
  for (Id c = 0; c < nTets; ++c)
  {
    double x[30];
    for (int a = 0; a < 10; ++a)
      for (int d = 0; d < 3; ++d)
        x[3 * a + d] = out.Points[3 * out.Conn[10 * c + a] + d];
    if (options.ExtraCheck(x))
      continue;
    for (int a = 4; a < 10; ++a)
    {
      const Id m = out.Conn[10 * c + a];
      if (mark[m])
        continue;
      mark[m] = 1;
      redo.push_back(m);
      redoTargets.insert(redoTargets.end(), &out.Points[3 * m], &out.Points[3 * m] + 3);
      const Id u = quad.MidCorners[2 * m], v = quad.MidCorners[2 * m + 1];
      for (int d = 0; d < 3; ++d)
        out.Points[3 * m + d] = 0.5 * (out.Points[3 * u + d] + out.Points[3 * v + d]);
    }
  }
  if (redo.empty())
    return;
  CurvingResult again =
    CurveMidEdgeNodes(out.Points, out.Conn, redo, redoTargets, options.QualityRatio,
      std::max(options.MinimumQuality, options.QualityTarget), options.ExtraCheck);
  std::vector<Id> edgeOf(nPts, -1);
  for (Id e = 0; e < nbe; ++e)
    edgeOf[quad.EdgeMid[e]] = e;
  for (size_t k = 0; k < redo.size(); ++k)
    if (again.Alpha[k] < 1.0 && edgeOf[redo[k]] >= 0)
      curving.Alpha[edgeOf[redo[k]]] = std::min(curving.Alpha[edgeOf[redo[k]]], again.Alpha[k]);
}

// The quality target (CurvedMeshOptions::QualityTarget), after the second chances, which
// search for surface points and free-node moves under the floor alone (with the target in
// them the mesher took 4 times as long on bunny at 1000 elements), and before the extra
// check, which keeps it. Every curved mid-edge node is put back straight and curved again
// towards where it was, with max(floor, target) as the floor of
// hoembed::Tet10RequiredQuality: a cell below min(target, its straight quality) gets its
// nodes blended back towards straight, just enough (bisection, hoembed::CurveMidEdgeNodes),
// the others keep their shape.
void ApplyQualityTarget(CurvedMesh& out, const QuadraticNodes& quad, Id nbe,
  const CurvedMeshOptions& options, CurvingResult& curving)
{
  const Id nPts = static_cast<Id>(out.Points.size() / 3);
  const Id nTets = static_cast<Id>(out.Conn.size() / 10);
  const std::vector<double> before = out.Points;
  auto quality = [&out](Id c) {
    double x[30];
    for (int a = 0; a < 10; ++a)
      for (int d = 0; d < 3; ++d)
        x[3 * a + d] = out.Points[3 * out.Conn[10 * c + a] + d];
    return Tet10MinScaledJacobian(x);
  };
  std::vector<double> qBefore(nTets);
  for (Id c = 0; c < nTets; ++c)
    qBefore[c] = quality(c);
  std::vector<Id> nodes;
  std::vector<double> where;
  for (Id m = quad.NumberOfCorners; m < nPts; ++m)
  {
    const Id u = quad.MidCorners[2 * m], v = quad.MidCorners[2 * m + 1];
    double mid[3];
    bool moved = false;
    for (int d = 0; d < 3; ++d)
    {
      mid[d] = 0.5 * (out.Points[3 * u + d] + out.Points[3 * v + d]);
      moved = moved || out.Points[3 * m + d] != mid[d];
    }
    if (!moved)
      continue;
    nodes.push_back(m);
    where.insert(where.end(), &out.Points[3 * m], &out.Points[3 * m] + 3);
    for (int d = 0; d < 3; ++d)
      out.Points[3 * m + d] = mid[d];
  }
  if (nodes.empty())
    return;
  const double floor = std::max(options.MinimumQuality, options.QualityTarget);
  // Interior nodes first, the boundary ones where they are: a cell that its interior
  // nodes can lift keeps its boundary nodes on the surface (sphere and bumpy blob at 1000
  // elements: 99.3% and 97.3% of the boundary mid-edge nodes stay on it, 98.3% and 96.6%
  // when all go back together). Then every node, from where that left it.
  std::vector<Id> inner;
  std::vector<double> innerAt;
  for (size_t k = 0; k < nodes.size(); ++k)
  {
    if (out.BoundaryNode[nodes[k]])
    {
      for (int d = 0; d < 3; ++d)
        out.Points[3 * nodes[k] + d] = where[3 * k + d];
      continue;
    }
    inner.push_back(nodes[k]);
    innerAt.insert(innerAt.end(), &where[3 * k], &where[3 * k] + 3);
  }
  if (!inner.empty())
    CurveMidEdgeNodes(out.Points, out.Conn, inner, innerAt, options.QualityRatio, floor);
  for (size_t k = 0; k < nodes.size(); ++k)
  {
    const Id m = nodes[k];
    const Id u = quad.MidCorners[2 * m], v = quad.MidCorners[2 * m + 1];
    for (int d = 0; d < 3; ++d)
    {
      where[3 * k + d] = out.Points[3 * m + d];
      out.Points[3 * m + d] = 0.5 * (out.Points[3 * u + d] + out.Points[3 * v + d]);
    }
  }
  const CurvingResult again =
    CurveMidEdgeNodes(out.Points, out.Conn, nodes, where, options.QualityRatio, floor);
  std::vector<Id> edgeOf(nPts, -1);
  for (Id e = 0; e < nbe; ++e)
    edgeOf[quad.EdgeMid[e]] = e;
  // A cell whose straight shape is below the floor may only keep the floor through its
  // curved nodes, and the target asks nothing of it (min(target, straight)): where the
  // blending of its neighbours' nodes took it below the floor, its nodes go back to where
  // they were (once each; the safety net after this pass catches a neighbour left invalid).
  std::vector<char> restored(nPts, 0);
  for (bool changed = true; changed;)
  {
    changed = false;
    for (Id c = 0; c < nTets; ++c)
    {
      if (!(qBefore[c] >= options.MinimumQuality) || quality(c) >= options.MinimumQuality)
        continue;
      for (int a = 4; a < 10; ++a)
      {
        const Id m = out.Conn[10 * c + a];
        if (restored[m])
          continue;
        restored[m] = 1;
        changed = true;
        for (int d = 0; d < 3; ++d)
          out.Points[3 * m + d] = before[3 * m + d];
      }
    }
  }
  for (size_t k = 0; k < nodes.size(); ++k)
    if (edgeOf[nodes[k]] >= 0 && !restored[nodes[k]])
      curving.Alpha[edgeOf[nodes[k]]] *= again.Alpha[k];
}

// Every cell that `keep` refuses gets all its mid-edge nodes straight, and so on for the
// cells around them. Terminates (each node is straightened once, for good) and ends with
// every cell kept where a straight cell is. Returns the number of nodes straightened.
template <typename Keep>
Id StraightenCellsUntil(
  CurvedMesh& out, const QuadraticNodes& quad, Id nbe, CurvingResult& curving, const Keep& keep)
{
  const Id nPts = static_cast<Id>(out.Points.size() / 3);
  const Id nTets = static_cast<Id>(out.Conn.size() / 10);
  std::vector<Id> edgeOf(nPts, -1);
  for (Id e = 0; e < nbe; ++e)
    edgeOf[quad.EdgeMid[e]] = e;
  std::vector<char> straightened(nPts, 0);
  Id count = 0;
  for (bool changed = true; changed;)
  {
    changed = false;
    for (Id c = 0; c < nTets; ++c)
    {
      double x[30];
      for (int a = 0; a < 10; ++a)
        for (int d = 0; d < 3; ++d)
          x[3 * a + d] = out.Points[3 * out.Conn[10 * c + a] + d];
      if (keep(x))
        continue;
      for (int a = 4; a < 10; ++a)
      {
        const Id m = out.Conn[10 * c + a];
        if (straightened[m])
          continue;
        straightened[m] = 1;
        changed = true;
        ++count;
        const Id u = quad.MidCorners[2 * m], v = quad.MidCorners[2 * m + 1];
        for (int d = 0; d < 3; ++d)
          out.Points[3 * m + d] = 0.5 * (out.Points[3 * u + d] + out.Points[3 * v + d]);
        if (edgeOf[m] >= 0)
          curving.Alpha[edgeOf[m]] = 0.0;
      }
    }
  }
  return count;
}

// Safety net: any cell still not valid gets its mid-edge nodes straight (a straight tet10
// is valid when its corners are).
void StraightenInvalidCells(
  CurvedMesh& out, const QuadraticNodes& quad, Id nbe, CurvingResult& curving)
{
  StraightenCellsUntil(
    out, quad, nbe, curving, [](const double* x) { return Tet10MinScaledJacobian(x) > 0.0; });
}

// The quality floor, last: the crossing repair moves nodes without asking the quality
// (a partial pull-back, a restored corner, straightened interior nodes), which can leave
// a cell below hoembed::Tet10RequiredQuality of its straight shape (fertility at 3000: one
// cell at 0.017 whose straight shape is 0.22). Such a cell gets its mid-edge nodes
// straight (a straight cell is acceptable). Returns the number of nodes straightened.
Id StraightenPoorCells(CurvedMesh& out, const QuadraticNodes& quad, Id nbe,
  const CurvedMeshOptions& options, CurvingResult& curving)
{
  return StraightenCellsUntil(out, quad, nbe, curving, [&](const double* x) {
    return Tet10Acceptable(x, options.QualityRatio, options.MinimumQuality);
  });
}

// Moves mid-edge node m to keep * its displacement from the straight position.
void PullNode(CurvedMesh& out, const QuadraticNodes& quad, Id m, double keep)
{
  const Id u = quad.MidCorners[2 * m], v = quad.MidCorners[2 * m + 1];
  for (int d = 0; d < 3; ++d)
  {
    const double mid = 0.5 * (out.Points[3 * u + d] + out.Points[3 * v + d]);
    out.Points[3 * m + d] = mid + keep * (out.Points[3 * m + d] - mid);
  }
}

// Mid-edge node -> the cells that use it (CSR).
struct MidNodeCells
{
  std::vector<Id> Offsets, Cells;
  MidNodeCells(const CurvedMesh& out)
  {
    const Id nTets = static_cast<Id>(out.Conn.size() / 10);
    this->Offsets.assign(out.Points.size() / 3 + 1, 0);
    this->Cells.resize(6 * nTets);
    for (Id c = 0; c < nTets; ++c)
      for (int a = 4; a < 10; ++a)
        ++this->Offsets[out.Conn[10 * c + a] + 1];
    for (size_t i = 1; i < this->Offsets.size(); ++i)
      this->Offsets[i] += this->Offsets[i - 1];
    std::vector<Id> fill(this->Offsets.begin(), this->Offsets.end() - 1);
    for (Id c = 0; c < nTets; ++c)
      for (int a = 4; a < 10; ++a)
        this->Cells[fill[out.Conn[10 * c + a]]++] = c;
  }
};

// A pulled-back boundary node can leave a cell invalid where interior mid-edge nodes
// follow the old boundary: those interior nodes are straightened (they carry no surface),
// so that the safety net (StraightenInvalidCells) does not straighten boundary nodes too.
void StraightenInteriorAround(
  CurvedMesh& out, const QuadraticNodes& quad, const MidNodeCells& around, Id m)
{
  for (Id k = around.Offsets[m]; k < around.Offsets[m + 1]; ++k)
  {
    const Id c = around.Cells[k];
    double x[30];
    for (int a = 0; a < 10; ++a)
      for (int d = 0; d < 3; ++d)
        x[3 * a + d] = out.Points[3 * out.Conn[10 * c + a] + d];
    if (Tet10MinScaledJacobian(x) > 0.0)
      continue;
    for (int a = 4; a < 10; ++a)
      if (!out.BoundaryNode[out.Conn[10 * c + a]])
        PullNode(out, quad, out.Conn[10 * c + a], 0.0);
  }
}

// Separates one crossing pair of faces (their 12 node ids in `two`): of its six mid-edge
// nodes, the one that separates the pair with the smallest pull-back (1/2, 1/4, 1/8 or
// all of its displacement) is pulled back, until the pair is apart; if no single node
// does, the first two (one per face) that do with the same factor; else every mid-edge
// node of both faces goes straight. As few boundary nodes as
// possible leave the surface.
void SeparatePair(CurvedMesh& out, const QuadraticNodes& quad, const MidNodeCells& around,
  const std::vector<Id>& two, const std::vector<Id>& edgeOf, CurvingResult& curving)
{
  static const double keeps[] = { 0.5, 0.25, 0.125, 0.0 };
  for (int step = 0; step < 6 && !FindCurvedFaceCrossings(out.Points, two).empty(); ++step)
  {
    Id bestNode = -1;
    int bestLevel = 4;
    for (int k = 0; k < 12; ++k)
    {
      if (k % 6 < 3)
        continue;
      const Id m = two[k];
      const double kept[3] = { out.Points[3 * m], out.Points[3 * m + 1], out.Points[3 * m + 2] };
      for (int level = 0; level < bestLevel; ++level)
      {
        PullNode(out, quad, m, keeps[level]);
        const bool apart = FindCurvedFaceCrossings(out.Points, two).empty();
        for (int d = 0; d < 3; ++d)
          out.Points[3 * m + d] = kept[d];
        if (apart)
        {
          bestLevel = level;
          bestNode = m;
          break;
        }
      }
    }
    std::vector<Id> pull;
    if (bestNode >= 0)
      pull.push_back(bestNode);
    else
    {
      // one node of each face, the same factor for both
      for (int level = 0; level < 4 && pull.empty(); ++level)
        for (int i = 3; i < 6 && pull.empty(); ++i)
          for (int j = 9; j < 12 && pull.empty(); ++j)
          {
            const Id m = two[i], n = two[j];
            const double km[3] = { out.Points[3 * m], out.Points[3 * m + 1],
              out.Points[3 * m + 2] };
            const double kn[3] = { out.Points[3 * n], out.Points[3 * n + 1],
              out.Points[3 * n + 2] };
            PullNode(out, quad, m, keeps[level]);
            PullNode(out, quad, n, keeps[level]);
            if (FindCurvedFaceCrossings(out.Points, two).empty())
            {
              pull = { m, n };
              bestLevel = level;
            }
            for (int d = 0; d < 3; ++d)
            {
              out.Points[3 * m + d] = km[d];
              out.Points[3 * n + d] = kn[d];
            }
          }
      if (pull.empty())
        for (int k = 0; k < 12; ++k)
          if (k % 6 >= 3)
            pull.push_back(two[k]);
    }
    const double keep = bestLevel < 4 ? keeps[bestLevel] : 0.0;
    for (Id m : pull)
    {
      PullNode(out, quad, m, keep);
      if (edgeOf[m] >= 0)
        curving.Alpha[edgeOf[m]] *= keep;
      StraightenInteriorAround(out, quad, around, m);
    }
    if (pull.size() > 2)
      break;
  }
}

// Straight faces that still cross have corners that moved onto the surface across each
// other: those corners go back to TetGen's positions (whose boundary does not cross
// itself), or half or a quarter of the way there, where every straight tet around them
// stays valid and keeps min(floor, its straight quality) (TetGen's corner can be what
// ImprovePoorTets moved to lift a sliver: its straight shape, which the floor's safety
// net falls back to, would be below the floor where the tet4 mesh has none; dragon at
// 1000 elements: one cell at 0.011), with the mid-edge nodes of the cells around them
// straight; searched again, three rounds at most.
// Straightening a cell's six mid-edge nodes also changes the cells that share its edges
// away from the moved corner, and a moved corner leaves the curved edges of its own cells
// on the old geometry: either can leave a cell invalid though its corners are not. Each
// round therefore ends with the safety net (StraightenInvalidCells: every straight tet is
// positive, those around a moved corner by the check here, the others untouched), and
// the pairs are counted on that valid state: a pair the net makes cross again is left.
void RestoreCrossingCorners(CurvedMesh& out, const QuadraticNodes& quad, Id nbe,
  const std::vector<Id>& faces, const std::vector<double>& straight, double minQuality,
  std::vector<std::array<Id, 2>>& pairs, CurvingResult& curving, const std::vector<Id>& edgeOf)
{
  const Id nTets = static_cast<Id>(out.Conn.size() / 10);
  std::vector<std::vector<Id>> cellsOf(quad.NumberOfCorners);
  for (Id c = 0; c < nTets; ++c)
    for (int a = 0; a < 4; ++a)
      cellsOf[out.Conn[10 * c + a]].push_back(c);
  auto straightQuality = [&](Id c) {
    double x[12];
    for (int a = 0; a < 4; ++a)
      for (int d = 0; d < 3; ++d)
        x[3 * a + d] = out.Points[3 * out.Conn[10 * c + a] + d];
    return Tet4JacobianDeterminant(x) > 0.0 ? Tet4ScaledJacobian(x) : -1.0;
  };
  std::vector<double> bar;
  for (int round = 0; round < 3 && !pairs.empty(); ++round)
  {
    for (const auto& pr : pairs)
      for (Id f : pr)
        for (int k = 0; k < 3; ++k)
        {
          const Id v = faces[6 * f + k];
          double keep[3];
          bar.clear();
          for (Id c : cellsOf[v])
            bar.push_back(std::min(minQuality, straightQuality(c)));
          for (int d = 0; d < 3; ++d)
            keep[d] = out.Points[3 * v + d];
          bool ok = false;
          for (double a : { 1.0, 0.5, 0.25 })
          {
            for (int d = 0; d < 3; ++d)
              out.Points[3 * v + d] = keep[d] + a * (straight[3 * v + d] - keep[d]);
            ok = true;
            for (size_t i = 0; ok && i < cellsOf[v].size(); ++i)
            {
              const double qc = straightQuality(cellsOf[v][i]);
              ok = qc > 0.0 && qc >= bar[i];
            }
            if (ok)
              break;
          }
          if (!ok)
          {
            for (int d = 0; d < 3; ++d)
              out.Points[3 * v + d] = keep[d];
            continue;
          }
          for (Id c : cellsOf[v])
            for (int a = 4; a < 10; ++a)
            {
              const Id m = out.Conn[10 * c + a];
              PullNode(out, quad, m, 0.0);
              if (edgeOf[m] >= 0)
                curving.Alpha[edgeOf[m]] = 0.0;
            }
        }
    StraightenInvalidCells(out, quad, nbe, curving);
    pairs = FindCurvedFaceCrossings(out.Points, faces);
  }
}

// The six nodes of every boundary face (tri6), in the order FindCurvedFaceCrossings reads.
std::vector<Id> BoundaryFaceNodes(const CurvedMesh& out, const TetMeshTopology& topo)
{
  const Id nbf = topo.GetNumberOfBoundaryFaces();
  std::vector<Id> faces(6 * nbf);
  for (Id f = 0; f < nbf; ++f)
    for (int k = 0; k < 6; ++k)
      faces[6 * f + k] =
        out.Conn[10 * topo.BoundaryFaceCell[f] + TetFaceNodes[topo.BoundaryFaceLocal[f]][k]];
  return faces;
}

// Two parts of the boundary that come close (thin parts, folds) can cross once curved,
// though every element is valid. Each crossing pair of curved boundary faces (certified,
// hoembed::FindCurvedFaceCrossings) is separated by pulling back as little as possible
// (SeparatePair); the search runs again (three rounds), and straight faces still
// crossing get their corners back (RestoreCrossingCorners).
void RepairBoundaryCrossings(CurvedMesh& out, const TetMeshTopology& topo,
  const QuadraticNodes& quad, Id nbe, const std::vector<double>& straight, double minQuality,
  CurvingResult& curving)
{
  const std::vector<Id> faces = BoundaryFaceNodes(out, topo);
  std::vector<std::array<Id, 2>> pairs = FindCurvedFaceCrossings(out.Points, faces);
  out.CrossingPairsFound = static_cast<Id>(pairs.size());
  if (pairs.empty())
    return;
  std::vector<Id> edgeOf(out.Points.size() / 3, -1);
  for (Id e = 0; e < nbe; ++e)
    edgeOf[quad.EdgeMid[e]] = e;
  const MidNodeCells around(out);
  for (int round = 0; round < 3 && !pairs.empty(); ++round)
  {
    for (const auto& pr : pairs)
    {
      std::vector<Id> two(12);
      for (int k = 0; k < 12; ++k)
        two[k] = faces[6 * pr[k / 6] + k % 6];
      SeparatePair(out, quad, around, two, edgeOf, curving);
    }
    StraightenInvalidCells(out, quad, nbe, curving);
    pairs = FindCurvedFaceCrossings(out.Points, faces);
  }
  if (!pairs.empty())
    RestoreCrossingCorners(out, quad, nbe, faces, straight, minQuality, pairs, curving, edgeOf);
  out.CrossingPairsLeft = static_cast<Id>(pairs.size());
}

// The quality target's promise (min(target, straight quality)), which the crossing repair
// can break as it can the floor (bumpy blob at 1000, target 0.3: 2-3 cells below): such a
// cell gets its mid-edge nodes straight, unless that takes a cell around them below the
// floor (a sliver that only its curved nodes kept above it): then the cell stays as it
// is. Each node once; returns the number of nodes straightened.
Id StraightenBelowTarget(CurvedMesh& out, const QuadraticNodes& quad, Id nbe,
  const CurvedMeshOptions& options, CurvingResult& curving)
{
  if (!(options.QualityTarget > options.MinimumQuality))
    return 0;
  const Id nTets = static_cast<Id>(out.Conn.size() / 10);
  const MidNodeCells around(out);
  std::vector<Id> edgeOf(out.Points.size() / 3, -1);
  for (Id e = 0; e < nbe; ++e)
    edgeOf[quad.EdgeMid[e]] = e;
  auto cellQuality = [&](Id c, double& straight) {
    double x[30];
    for (int a = 0; a < 10; ++a)
      for (int d = 0; d < 3; ++d)
        x[3 * a + d] = out.Points[3 * out.Conn[10 * c + a] + d];
    straight = Tet4ScaledJacobian(x);
    return Tet10MinScaledJacobian(x);
  };
  std::vector<char> straightened(out.Points.size() / 3, 0);
  Id count = 0;
  for (bool changed = true; changed;)
  {
    changed = false;
    for (Id c = 0; c < nTets; ++c)
    {
      double straight = 0.0;
      const double qc = cellQuality(c, straight);
      if (qc >= std::min(options.QualityTarget, 0.999 * straight))
        continue;
      Id nodes[6];
      double saved[18];
      std::vector<Id> touched;
      for (int a = 4; a < 10; ++a)
      {
        const Id m = out.Conn[10 * c + a];
        nodes[a - 4] = m;
        std::copy(&out.Points[3 * m], &out.Points[3 * m] + 3, &saved[3 * (a - 4)]);
        touched.insert(touched.end(), around.Cells.begin() + around.Offsets[m],
          around.Cells.begin() + around.Offsets[m + 1]);
      }
      std::sort(touched.begin(), touched.end());
      touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
      std::vector<double> qBefore(touched.size());
      for (size_t k = 0; k < touched.size(); ++k)
      {
        double st = 0.0;
        qBefore[k] = cellQuality(touched[k], st);
      }
      // blended back half, three quarters, then all the way: the least that lifts it
      bool ok = false;
      double used = 0.0;
      for (double keep : { 0.5, 0.25, 0.0 })
      {
        used = keep;
        bool any = false;
        for (int k = 0; k < 6; ++k)
          if (!straightened[nodes[k]])
          {
            std::copy(&saved[3 * k], &saved[3 * k] + 3, &out.Points[3 * nodes[k]]);
            PullNode(out, quad, nodes[k], keep);
            any = true;
          }
        double st = 0.0;
        ok = any && cellQuality(c, st) >= std::min(options.QualityTarget, 0.999 * st);
        for (size_t k = 0; ok && k < touched.size(); ++k)
        {
          const double qk = cellQuality(touched[k], st);
          ok = qk > 0.0 && !(qBefore[k] >= options.MinimumQuality && qk < options.MinimumQuality);
        }
        if (ok)
          break;
      }
      if (!ok)
      {
        for (int k = 0; k < 6; ++k)
          std::copy(&saved[3 * k], &saved[3 * k] + 3, &out.Points[3 * nodes[k]]);
        continue;
      }
      for (Id m : nodes)
        if (!straightened[m])
        {
          straightened[m] = 1;
          ++count;
          changed = true;
          if (edgeOf[m] >= 0)
            curving.Alpha[edgeOf[m]] *= used;
        }
    }
  }
  return count;
}

// Interior mid-edge nodes carry no surface: once the boundary is final they may go
// wherever their cells are best. Curving bends the cells along the boundary and the
// harmonic extension and the blending (ApplyQualityTarget) only keep them above a floor;
// here each interior mid-edge node of a cell that curving left below its straight shape
// moves to raise the cells around it towards their straight quality without lowering the
// worst of them (a pattern search: axis steps from a tenth of its edge, halved on
// failure).
// Boundary faces do not change, so no crossing comes back; each moved node is confirmed
// with the acceptance test (with the extra check) of every cell around it, else it goes
// back. Gauss-Seidel sweeps in node order (deterministic), work bounded by evaluations
// per cell. Returns the number of nodes moved.
Id OptimiseInteriorMidNodes(CurvedMesh& out, const QuadraticNodes& quad,
  const CurvedMeshOptions& options, Id evaluationsPerCell = 100)
{
  const Id nPts = static_cast<Id>(out.Points.size() / 3);
  const Id nTets = static_cast<Id>(out.Conn.size() / 10);
  const MidNodeCells around(out);
  std::vector<double> straight(nTets), q(nTets);
  auto cellNodes = [&](Id c, double* x) {
    for (int a = 0; a < 10; ++a)
      for (int d = 0; d < 3; ++d)
        x[3 * a + d] = out.Points[3 * out.Conn[10 * c + a] + d];
  };
  for (Id c = 0; c < nTets; ++c)
  {
    double x[30];
    cellNodes(c, x);
    straight[c] = Tet4ScaledJacobian(x);
    q[c] = Tet10MinScaledJacobian(x);
  }
  std::int64_t evaluations = 0;
  const std::int64_t budget = evaluationsPerCell * nTets;
  // The worst minimum scaled Jacobian around node m and the sum over those cells of
  // min(quality, straight quality): the move must not lower the first and raises the
  // second, so that every bent cell gains, not only the worst one (raising the worst
  // alone left the median where it was).
  // Besides, no cell may fall below the level the quality target promises it,
  // min(max(floor, target), its straight quality), unless it was below already (then not
  // below where it was).
  const double target = std::max(options.MinimumQuality, options.QualityTarget);
  auto keeps = [&](Id c, double qc) {
    return qc >= std::min(q[c], std::min(target, 0.999 * straight[c]));
  };
  auto around2 = [&](Id m, double& sum) {
    double w = 1e300;
    sum = 0.0;
    bool kept = true;
    for (Id k = around.Offsets[m]; k < around.Offsets[m + 1]; ++k)
    {
      const Id c = around.Cells[k];
      double x[30];
      cellNodes(c, x);
      ++evaluations;
      const double qc = Tet10SampledScaledJacobian(x);
      w = std::min(w, qc);
      sum += std::min(qc, straight[c]);
      kept = kept && keeps(c, qc);
    }
    return kept ? w : -1e300;
  };
  // Worth a try: a cell around the node that curving took below its straight shape.
  auto bent = [&](Id m) {
    for (Id k = around.Offsets[m]; k < around.Offsets[m + 1]; ++k)
    {
      const Id c = around.Cells[k];
      if (q[c] < 0.9 * straight[c])
        return true;
    }
    return false;
  };
  Id moved = 0;
  for (int sweep = 0; sweep < 2 && evaluations < budget; ++sweep)
  {
    Id movedNow = 0;
    for (Id m = quad.NumberOfCorners; m < nPts && evaluations < budget; ++m)
    {
      if (out.BoundaryNode[m] || around.Offsets[m] == around.Offsets[m + 1] || !bent(m))
        continue;
      const Id u = quad.MidCorners[2 * m], v = quad.MidCorners[2 * m + 1];
      double L = 0.0;
      for (int d = 0; d < 3; ++d)
        L += (out.Points[3 * u + d] - out.Points[3 * v + d]) *
          (out.Points[3 * u + d] - out.Points[3 * v + d]);
      L = std::sqrt(L);
      const double start[3] = { out.Points[3 * m], out.Points[3 * m + 1], out.Points[3 * m + 2] };
      double sumBefore = 0.0;
      const double before = around2(m, sumBefore);
      double best = sumBefore;
      double step = 0.1 * L;
      for (int it = 0; it < 12 && step > 0.01 * L && evaluations < budget; ++it)
      {
        bool better = false;
        for (int dir = 0; dir < 6 && !better; ++dir)
        {
          const int d = dir / 2;
          const double s = dir % 2 ? -step : step;
          out.Points[3 * m + d] += s;
          double sum = 0.0;
          const double w = around2(m, sum);
          if (w >= before && sum > best + 1e-9)
          {
            best = sum;
            better = true;
          }
          else
            out.Points[3 * m + d] -= s;
        }
        if (!better)
          step *= 0.5;
      }
      if (!(best > sumBefore + 1e-6))
      {
        for (int d = 0; d < 3; ++d)
          out.Points[3 * m + d] = start[d];
        continue;
      }
      // the search used the sampled quality: the proven one (and the acceptance test)
      // decides, against the worst around before the move
      double worstBefore = 1e300;
      for (Id k = around.Offsets[m]; k < around.Offsets[m + 1]; ++k)
        worstBefore = std::min(worstBefore, q[around.Cells[k]]);
      bool ok = true;
      for (Id k = around.Offsets[m]; ok && k < around.Offsets[m + 1]; ++k)
      {
        double x[30];
        cellNodes(around.Cells[k], x);
        const double qc = Tet10MinScaledJacobian(x);
        ok = qc >= worstBefore && keeps(around.Cells[k], qc) && TetIsValid(x, 10) &&
          Tet10Acceptable(x, options.QualityRatio, options.MinimumQuality, options.ExtraCheck);
      }
      if (!ok)
      {
        for (int d = 0; d < 3; ++d)
          out.Points[3 * m + d] = start[d];
        continue;
      }
      for (Id k = around.Offsets[m]; k < around.Offsets[m + 1]; ++k)
      {
        double x[30];
        cellNodes(around.Cells[k], x);
        q[around.Cells[k]] = Tet10MinScaledJacobian(x);
      }
      ++movedNow;
    }
    moved += movedNow;
    if (movedNow == 0)
      break;
  }
  return moved;
}

// Counts of the boundary mid-edge nodes on the surface and pulled back; the pulled-back
// edges with their targets.
void CountCurvedNodes(CurvedMesh& out, const TetMeshTopology& topo,
  const std::vector<double>& targets, const std::vector<char>& envelope,
  const CurvingResult& curving)
{
  const Id nbe = topo.GetNumberOfBoundaryEdges();
  for (Id e = 0; e < nbe; ++e)
    (envelope[e] ? out.EnvelopeNodes
                 : (curving.Alpha[e] < 1.0 ? out.RelaxedNodes : out.CurvedNodes))++;
  for (Id e = 0; e < nbe; ++e)
  {
    if (curving.Alpha[e] < 1.0 && !envelope[e])
    {
      out.RelaxedEdges.push_back(topo.BoundaryEdgeNodes[3 * e]);
      out.RelaxedEdges.push_back(topo.BoundaryEdgeNodes[3 * e + 1]);
      out.RelaxedEdgeTargets.insert(
        out.RelaxedEdgeTargets.end(), &targets[3 * e], &targets[3 * e] + 3);
    }
  }
}
} // namespace

// (documented in the header) Each pass removes what it can without a neighbour of a removed
// tet being removed too, then rebuilds the topology.
std::int64_t RemoveBoundarySlivers(const std::vector<double>& p, std::vector<std::int64_t>& tets,
  std::int64_t nPts, double qualityThreshold)
{
  Id removed = 0;
  for (int pass = 0; pass < 4; ++pass)
  {
    const Id nt = static_cast<Id>(tets.size() / 4);
    TetMeshTopology topo;
    if (!topo.Build(tets.data(), nt, 4, nPts).empty())
      break;
    std::unordered_map<std::uint64_t, char> boundaryEdges;
    for (Id e = 0; e < topo.GetNumberOfBoundaryEdges(); ++e)
      boundaryEdges[static_cast<std::uint64_t>(topo.BoundaryEdgeNodes[3 * e]) * nPts +
        topo.BoundaryEdgeNodes[3 * e + 1]] = 1;
    std::vector<char> drop(nt, 0);
    Id dropped = 0;
    for (Id t = 0; t < nt; ++t)
    {
      int nb = 0;
      bool neighbourDropped = false;
      int interior[2], ni = 0;
      for (int f = 0; f < 4; ++f)
      {
        const Id nbr = topo.FaceNeighbor[4 * t + f];
        if (nbr < 0)
          ++nb;
        else
        {
          neighbourDropped |= drop[nbr] != 0;
          if (ni < 2)
            interior[ni++] = f;
        }
      }
      if (nb != 2 || neighbourDropped || TetQuality(p, &tets[4 * t]) >= qualityThreshold)
        continue;
      // The edge shared by the two interior faces becomes a boundary edge.
      Id common[3];
      int nc = 0;
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b)
          if (TetFaceNodes[interior[0]][a] == TetFaceNodes[interior[1]][b])
            common[nc++] = tets[4 * t + TetFaceNodes[interior[0]][a]];
      if (nc != 2)
        continue;
      const Id u = std::min(common[0], common[1]), v = std::max(common[0], common[1]);
      if (boundaryEdges.count(static_cast<std::uint64_t>(u) * nPts + v))
        continue;
      drop[t] = 1;
      ++dropped;
    }
    if (dropped == 0)
      break;
    std::vector<Id> kept;
    kept.reserve(tets.size());
    for (Id t = 0; t < nt; ++t)
      if (!drop[t])
        kept.insert(kept.end(), tets.begin() + 4 * t, tets.begin() + 4 * t + 4);
    // Removing a tet may leave a neighbour hanging on by an edge or a vertex only (the
    // mesh would no longer be one face-connected piece): then keep this pass undone.
    if (CountFaceComponents(kept, nPts) > CountFaceComponents(tets, nPts))
      break;
    tets.swap(kept);
    removed += dropped;
  }
  return removed;
}

CurvedMesh BuildCurvedMesh(std::vector<double> pts, std::vector<Id> tets,
  const SurfaceQueries& surface, const CurvedMeshOptions& options,
  const std::function<void(double)>& progress)
{
  CurvedMesh out;
  auto report = [&](double f) {
    if (progress)
      progress(f);
  };
  out.RemovedSlivers +=
    RemoveBoundarySlivers(pts, tets, static_cast<Id>(pts.size() / 3), options.SliverQuality);
  TetMeshTopology topo;
  const std::string err =
    topo.Build(tets.data(), static_cast<Id>(tets.size() / 4), 4, static_cast<Id>(pts.size() / 3));
  if (!err.empty())
  {
    out.Error = "the linear mesh is inconsistent: " + err;
    return out;
  }
  const std::vector<double> tetgenCorners = pts;
  if (options.ProjectCorners)
    ProjectCorners(pts, tets, topo, surface, options.MaxTargetDistance, options.MinimumQuality);
  // The boundary stays TetGen's when the corners stay (the driver's straight last resort)
  // and on an envelope (MaxTargetDistance): there the closest surface point of a slid corner
  // can lie on a part the envelope encloses (overlapping bodies: a boundary 4.4% of the
  // diagonal inside the input, against 2.3% without the slide).
  const bool slide = options.ProjectCorners && !(options.MaxTargetDistance > 0.0);
  OptimiseLinearCorners(pts, tets, topo, slide ? surface : SurfaceQueries(), options.CornerSweeps,
    tetgenCorners, options.MinimumQuality);
  ImprovePoorTets(pts, tets, options.MinimumQuality); // tet4 and tet10: the same corners
  report(0.3);
  // AbortExecute between the steps (hoembed::ScopedTetGenAbort of the calling thread)
  auto aborted = [&out]() {
    if (!MeshingAbortRequested())
      return false;
    out.Error = "aborted";
    return true;
  };
  if (aborted())
    return out;

  out.LinearPoints = pts;
  out.LinearBoundary.assign(topo.BoundaryFaceNodes.begin(),
    topo.BoundaryFaceNodes.begin() + 3 * topo.GetNumberOfBoundaryFaces());
  out.Points = pts;
  out.BoundaryNode.assign(pts.size() / 3, 0);
  for (Id i = 0; i < static_cast<Id>(pts.size() / 3); ++i)
    out.BoundaryNode[i] = topo.IsBoundaryNode(i) ? 1 : 0;
  if (options.Order == 1)
  {
    out.Conn = tets;
    return out;
  }

  const QuadraticNodes quad = AddMidEdgeNodes(out.Points, tets, topo);
  out.Conn = quad.Conn;
  out.BoundaryNode.resize(out.Points.size() / 3, 0);
  const Id nbe = topo.GetNumberOfBoundaryEdges();
  for (Id e = 0; e < nbe; ++e)
    out.BoundaryNode[quad.EdgeMid[e]] = 1;
  if (!options.CurveBoundary)
    return out;

  std::vector<double> targets;
  std::vector<char> envelope;
  CurvingResult curving = CurveTowardsSurface(out, topo, quad, surface, options, targets, envelope);
  report(0.7);
  if (aborted())
    return out;
  SecondChances(out, topo, quad, surface, options, targets, curving);
  if (aborted())
    return out;
  if (options.QualityTarget > 0.0)
    ApplyQualityTarget(out, quad, nbe, options, curving);
  if (options.ExtraCheck)
    ApplyExtraCheck(out, quad, nbe, options, curving);
  StraightenInvalidCells(out, quad, nbe, curving);
  RepairBoundaryCrossings(out, topo, quad, nbe, tetgenCorners, options.MinimumQuality, curving);
  const Id poorStraightened = StraightenPoorCells(out, quad, nbe, options, curving);
  if (poorStraightened + StraightenBelowTarget(out, quad, nbe, options, curving) > 0)
  {
    // straightened boundary nodes change the curved faces: count the crossing pairs again
    // (the driver changes the mesh when any is left)
    out.CrossingPairsLeft =
      static_cast<Id>(FindCurvedFaceCrossings(out.Points, BoundaryFaceNodes(out, topo)).size());
  }
  OptimiseInteriorMidNodes(out, quad, options);
  CountCurvedNodes(out, topo, targets, envelope, curving);
  report(1.0);
  return out;
}
} // namespace hoembed
