// The embedding on VTK_LAGRANGE_TETRAHEDRON of order 1-4 (hoembedLagrangeTet.h,
// hoembedLagrangeEmbedding.h, the driver's dispatch), against references nobody here
// wrote or that work differently:
//  - node order and shape functions: vtkLagrangeTetra (EvaluateLocation,
//    InterpolateFunctions) on curved cells; derivatives against finite differences;
//  - validity: a cell folded by one moved node is refused, the curved box accepted;
//  - closest distances: a brute force (every boundary face sampled on a lattice, the best
//    candidates refined by zooming lattices: no Newton, no bounds) on a mildly and a
//    strongly curved box of each order, every point: excess <= 1e-8 of the diagonal;
//    residuals <= 1e-10;
//  - a tet10 mesh re-expressed exactly at order 3 (the quadratic map at vtkLagrangeTetra's
//    nodes): its closest distances equal the tet10 path's to 1e-10 of the diagonal;
//  - rigid motion: p' + d n' of the moved mesh rebuilds R v + t to 1e-9 of the diagonal;
//  - errors: mixed cell types and the 15-node variant are refused with a sentence.
#include "hoembedEmbeddingDriver.h"
#include "hoembedLagrangeEmbedding.h"
#include "hoembedLagrangeTestUtilities.h"

#include "vtkLagrangeTetra.h"
#include "vtkPoints.h"

#include <algorithm>
#include <random>

using namespace hoembed_test;

namespace
{
void TestAgainstVTKCell()
{
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> jitter(-0.05, 0.05), unit(0.0, 1.0);
  for (int p = 1; p <= 4; ++p)
  {
    const hoembed::LagrangeTetBasis& b = *hoembed::GetLagrangeTetBasis(p);
    const int n = b.NumberOfNodes;
    vtkNew<vtkLagrangeTetra> cell;
    cell->GetPointIds()->SetNumberOfIds(n);
    cell->GetPoints()->SetNumberOfPoints(n);
    cell->Initialize();
    // VTK's own parametric node positions against ours
    const double* vpc = cell->GetParametricCoords();
    std::vector<double> x(3 * n);
    for (int k = 0; k < n; ++k)
    {
      double pc[3];
      hoembed::LagrangeTetNodeParametric(b, k, pc);
      for (int d = 0; d < 3; ++d)
        HOEMBED_CHECK(std::abs(pc[d] - vpc[3 * k + d]) < 1e-14, "order %d node %d", p, k);
      // a curved cell: the straight node moved a little
      const double straight[3] = { 1.0 + 2 * pc[0] + 0.3 * pc[1], 0.5 * pc[0] + 1.7 * pc[1],
        0.2 * pc[1] + 1.5 * pc[2] };
      for (int d = 0; d < 3; ++d)
      {
        x[3 * k + d] = straight[d] + (p > 1 ? jitter(rng) : 0.0);
        cell->GetPoints()->SetPoint(k, x.data() + 3 * k);
      }
      cell->GetPointIds()->SetId(k, k);
    }
    std::vector<double> w(n), N(n);
    for (int s = 0; s < 20; ++s)
    {
      double pc[3] = { unit(rng), unit(rng), unit(rng) };
      const double sum = pc[0] + pc[1] + pc[2];
      if (sum > 1)
        for (double& c : pc)
          c /= 1.5 * sum;
      double vx[3], hx[3], J[3][3], H[3][3][3];
      int sub = 0;
      cell->EvaluateLocation(sub, pc, vx, w.data());
      hoembed::EvaluateLagrangeTet(b, x.data(), pc, hx, J, H);
      hoembed::LagrangeTetShape(b, pc, N.data());
      for (int d = 0; d < 3; ++d)
        HOEMBED_CHECK(std::abs(vx[d] - hx[d]) < 1e-12, "order %d: x differs from VTK's by %g", p,
          vx[d] - hx[d]);
      for (int k = 0; k < n; ++k)
        HOEMBED_CHECK(
          std::abs(w[k] - N[k]) < 1e-12, "order %d: N_%d %g vs VTK %g", p, k, N[k], w[k]);
      // derivatives against central differences
      const double h = 1e-6;
      for (int i = 0; i < 3; ++i)
      {
        double a[3] = { pc[0], pc[1], pc[2] }, c[3] = { pc[0], pc[1], pc[2] };
        a[i] += h;
        c[i] -= h;
        double xa[3], xc[3], Ja[3][3], Jc[3][3];
        hoembed::EvaluateLagrangeTet(b, x.data(), a, xa, Ja);
        hoembed::EvaluateLagrangeTet(b, x.data(), c, xc, Jc);
        for (int d = 0; d < 3; ++d)
        {
          HOEMBED_CHECK(std::abs((xa[d] - xc[d]) / (2 * h) - J[i][d]) < 1e-7, "order %d dx", p);
          for (int j = 0; j < 3; ++j)
            HOEMBED_CHECK(
              std::abs((Ja[j][d] - Jc[j][d]) / (2 * h) - H[i][j][d]) < 1e-6, "order %d d2x", p);
        }
      }
    }
    HOEMBED_CHECK(hoembed::LagrangeTetIsValid(b, x.data()), "order %d: curved cell refused", p);
    // fold the cell: move the last corner through the opposite face
    std::vector<double> folded = x;
    folded[3 * 3 + 2] = -1.0;
    HOEMBED_CHECK(!hoembed::LagrangeTetIsValid(b, folded.data()), "order %d: folded accepted", p);
    if (p >= 2)
    {
      // a subtler fold: one edge node pushed far beyond the opposite corner
      std::vector<double> bent = x;
      bent[3 * 4 + 0] = 8.0;
      HOEMBED_CHECK(!hoembed::LagrangeTetIsValid(b, bent.data()), "order %d: bent accepted", p);
    }
  }
}

// A boundary face's point through its cell's shape functions (not the face's Bernstein
// form that the search evaluates).
void CellFacePoint(
  const hoembed::LagrangeEmbeddingMesh& m, std::int64_t f, const double uv[2], double x[3])
{
  double pc[3];
  hoembed::TetFaceToTetParametric(m.Corners.BoundaryFaceLocal[f], uv, pc);
  m.CellPoint(m.Corners.BoundaryFaceCell[f], pc, x);
}

// The search's face evaluation (Bernstein net, derivatives from its differences) against
// the cell's shape functions and central differences of them.
void CheckFacePoints(const hoembed::LagrangeEmbeddingMesh& m, int p)
{
  double worst = 0.0;
  const double h = 1e-5;
  for (std::int64_t f = 0; f < m.Corners.GetNumberOfBoundaryFaces(); f += 7)
    for (const auto& uv : { std::array<double, 2>{ 0.2, 0.3 }, { 0.6, 0.1 }, { 0.05, 0.9 } })
    {
      double x[3], xu[3], xv[3], H[3][3], y[3];
      m.FacePoint(f, uv.data(), x, xu, xv, H);
      CellFacePoint(m, f, uv.data(), y);
      double fd[3][3], fdd[3][3];
      const double du[2][2] = { { h, 0 }, { 0, h } };
      for (int k = 0; k < 2; ++k)
      {
        double a[2] = { uv[0] + du[k][0], uv[1] + du[k][1] };
        double c[2] = { uv[0] - du[k][0], uv[1] - du[k][1] };
        double xa[3], xc[3];
        CellFacePoint(m, f, a, xa);
        CellFacePoint(m, f, c, xc);
        for (int d = 0; d < 3; ++d)
        {
          fd[k][d] = (xa[d] - xc[d]) / (2 * h);
          fdd[2 * k][d] = (xa[d] - 2 * y[d] + xc[d]) / (h * h);
        }
      }
      for (int d = 0; d < 3; ++d)
      {
        worst = std::max(worst, std::abs(x[d] - y[d]) * 1e4); // exact to round-off
        worst = std::max(worst, std::abs(xu[d] - fd[0][d]));
        worst = std::max(worst, std::abs(xv[d] - fd[1][d]));
        worst = std::max(worst, std::abs(H[0][d] - fdd[0][d]) * 1e-2);
        worst = std::max(worst, std::abs(H[2][d] - fdd[2][d]) * 1e-2);
      }
    }
  HOEMBED_CHECK(worst < 1e-6, "order %d: face evaluation off by %g (scaled)", p, worst);
}

// Brute force: each boundary face sampled on a lattice, the best few refined by zooming
// lattices around them (no derivatives, no bounds, the cells' shape functions: independent
// of the search).
double BruteDistance(const hoembed::LagrangeEmbeddingMesh& m, const double v[3])
{
  const std::int64_t nf = m.Corners.GetNumberOfBoundaryFaces();
  std::vector<std::pair<double, std::array<double, 3>>> cand; // (d2, face, u, v)
  const int L = 14;
  for (std::int64_t f = 0; f < nf; ++f)
  {
    double best = HUGE_VAL, bu = 0, bv = 0;
    for (int i = 0; i <= L; ++i)
      for (int j = 0; i + j <= L; ++j)
      {
        const double uv[2] = { double(i) / L, double(j) / L };
        double x[3];
        CellFacePoint(m, f, uv, x);
        const double d2 = (x[0] - v[0]) * (x[0] - v[0]) + (x[1] - v[1]) * (x[1] - v[1]) +
          (x[2] - v[2]) * (x[2] - v[2]);
        if (d2 < best)
          best = d2, bu = uv[0], bv = uv[1];
      }
    cand.push_back({ best, { double(f), bu, bv } });
  }
  std::sort(
    cand.begin(), cand.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  double best = HUGE_VAL;
  for (std::size_t k = 0; k < std::min<std::size_t>(6, cand.size()); ++k)
  {
    const std::int64_t f = static_cast<std::int64_t>(cand[k].second[0]);
    double u = cand[k].second[1], w = cand[k].second[2], h = 1.0 / L, d2best = cand[k].first;
    for (int round = 0; round < 60; ++round)
    {
      double nu = u, nw = w;
      for (int i = -5; i <= 5; ++i)
        for (int j = -5; j <= 5; ++j)
        {
          double uv[2] = { u + h * i / 5, w + h * j / 5 };
          if (uv[0] < 0 || uv[1] < 0 || uv[0] + uv[1] > 1)
          {
            // clamp into the triangle
            uv[0] = std::max(0.0, uv[0]);
            uv[1] = std::max(0.0, uv[1]);
            const double s = uv[0] + uv[1];
            if (s > 1)
              uv[0] /= s, uv[1] /= s;
          }
          double x[3];
          CellFacePoint(m, f, uv, x);
          const double d2 = (x[0] - v[0]) * (x[0] - v[0]) + (x[1] - v[1]) * (x[1] - v[1]) +
            (x[2] - v[2]) * (x[2] - v[2]);
          if (d2 < d2best)
            d2best = d2, nu = uv[0], nw = uv[1];
        }
      u = nu;
      w = nw;
      h *= 0.6;
    }
    best = std::min(best, d2best);
  }
  return std::sqrt(best);
}

void TestClosestPerOrder(bool strong)
{
  std::mt19937 rng(strong ? 13 : 11);
  // the strongly curved box: points close to its boundary, where the faces' bends matter
  std::uniform_real_distribution<double> box(strong ? -0.45 : -0.7, strong ? 2.45 : 2.7);
  for (int p = 1; p <= 4; ++p)
  {
    LagrangeBox mesh = MakeLagrangeBox(
      2, p, [strong](const double* c, std::int64_t, const double pc[3], double x[3]) {
        StraightPoint(c, pc, x);
        if (strong)
          CurveStrongly(x);
        else
          Curve(x);
      });
    hoembed::LagrangeEmbeddingMesh m;
    std::int64_t bad = -1;
    const std::string err = m.Build(mesh.Points, mesh.Connectivity, mesh.NodesPerCell, &bad);
    HOEMBED_CHECK(err.empty(), "order %d: %s", p, err.c_str());
    HOEMBED_CHECK(bad == mesh.NumberOfCells(), "order %d: cell %lld refused", p, (long long)bad);
    CheckFacePoints(m, p);
    const double diag = m.Diagonal;
    double worstExcess = 0, worstBelow = 0, worstResidual = 0, worstRigid = 0;
    int inside = 0, outside = 0, fallbacks = 0, uncertified = 0;
    // a rigid motion of the mesh: its nodal normals rotate with it
    const double ang = 0.7, ca = std::cos(ang), sa = std::sin(ang);
    const double R[3][3] = { { ca, -sa, 0 }, { sa * 0.6, ca * 0.6, 0.8 },
      { -sa * 0.8, -ca * 0.8, 0.6 } };
    const double t[3] = { 3.0, -1.0, 0.5 };
    std::vector<double> moved(mesh.Points.size());
    for (std::size_t i = 0; i < mesh.Points.size() / 3; ++i)
      for (int r = 0; r < 3; ++r)
        moved[3 * i + r] = t[r] + R[r][0] * mesh.Points[3 * i] + R[r][1] * mesh.Points[3 * i + 1] +
          R[r][2] * mesh.Points[3 * i + 2];
    hoembed::LagrangeEmbeddingMesh mm;
    HOEMBED_CHECK(mm.Build(moved, mesh.Connectivity, mesh.NodesPerCell).empty(), "moved mesh");
    for (int s = 0; s < 40; ++s)
    {
      const double v[3] = { box(rng), box(rng), box(rng) };
      hoembed::VertexEmbedding r;
      m.Embed(v, hoembed::EMBED_NORMAL_OFFSET, r);
      worstResidual = std::max(worstResidual, r.Residual / diag);
      fallbacks += r.Fallback;
      uncertified += r.Uncertified;
      if (r.Inside)
      {
        ++inside;
        HOEMBED_CHECK(r.ClosestDistance == 0.0, "inside point with a distance");
      }
      else
      {
        ++outside;
        // truly outside: v lies on the outer side of the boundary at its closest point
        // (a missed inside point would have its closest point facing away from it)
        double x[3], xu[3], xv[3];
        m.FacePoint(r.BoundaryFace, r.UV, x, xu, xv);
        const double n[3] = { xu[1] * xv[2] - xu[2] * xv[1], xu[2] * xv[0] - xu[0] * xv[2],
          xu[0] * xv[1] - xu[1] * xv[0] };
        const double side = (v[0] - x[0]) * n[0] + (v[1] - x[1]) * n[1] + (v[2] - x[2]) * n[2];
        HOEMBED_CHECK(side > 0 || r.ClosestDistance < 1e-12 * diag,
          "order %d: an outside point behind its closest face", p);
        const double brute = BruteDistance(m, v);
        worstExcess = std::max(worstExcess, (r.ClosestDistance - brute) / diag);
        worstBelow = std::max(worstBelow, (brute - r.ClosestDistance) / diag);
      }
      // the barycentric baseline: the same cell and coordinates inside; outside, the
      // closest cell's map extrapolated (near the mesh it reaches v)
      {
        hoembed::VertexEmbedding rb;
        m.Embed(v, hoembed::EMBED_BARYCENTRIC, rb);
        if (r.Inside)
          HOEMBED_CHECK(rb.Inside && rb.Cell == r.Cell && rb.PC[0] == r.PC[0] &&
              rb.PC[1] == r.PC[1] && rb.PC[2] == r.PC[2],
            "order %d: barycentric differs inside", p);
        else if (r.ClosestDistance < 0.05 * diag)
          HOEMBED_CHECK(rb.Residual <= 1e-10 * diag && rb.Distance == 0.0,
            "order %d: barycentric residual %g near the mesh", p, rb.Residual / diag);
      }
      // the transfer's formula on the moved mesh: x'(pc) + d n'(pc) / |n'| (or J' q)
      const hoembed::LagrangeTetBasis& b = *mm.Basis;
      double xn[3 * hoembed::MaxLagrangeTetNodes], nn[3 * hoembed::MaxLagrangeTetNodes];
      hoembed::GatherCell(mm.Points.data(), mm.Connectivity.data(), mm.NodesPerCell, r.Cell, xn);
      hoembed::GatherCell(
        mm.NodalNormals.data(), mm.Connectivity.data(), mm.NodesPerCell, r.Cell, nn);
      double x[3], n[3], J[3][3], Jn[3][3], q[3] = { 0, 0, 0 };
      hoembed::EvaluateLagrangeTet(b, xn, r.PC, x, J);
      hoembed::EvaluateLagrangeTet(b, nn, r.PC, n, Jn);
      if (r.Fallback)
        m.Offset(r.Cell, r.PC, v, q);
      const double nl = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
      for (int d = 0; d < 3; ++d)
      {
        const double got = x[d] + (r.Distance != 0 ? r.Distance * n[d] / nl : 0.0) +
          J[0][d] * q[0] + J[1][d] * q[1] + J[2][d] * q[2];
        const double want = t[d] + R[d][0] * v[0] + R[d][1] * v[1] + R[d][2] * v[2];
        worstRigid = std::max(worstRigid, std::abs(got - want) / diag);
      }
    }
    // points just inside and just outside the curved boundary (1e-3 along the face's
    // normal): located on the right side, at the right distance
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    int wrongSide = 0;
    double worstNear = 0.0;
    for (int s = 0; s < 40; ++s)
    {
      const std::int64_t f =
        static_cast<std::int64_t>(unit(rng) * m.Corners.GetNumberOfBoundaryFaces()) %
        m.Corners.GetNumberOfBoundaryFaces();
      double uv[2] = { unit(rng), unit(rng) };
      if (uv[0] + uv[1] > 1)
        uv[0] = 1 - uv[0], uv[1] = 1 - uv[1];
      double x[3], xu[3], xv[3];
      m.FacePoint(f, uv, x, xu, xv);
      double n[3] = { xu[1] * xv[2] - xu[2] * xv[1], xu[2] * xv[0] - xu[0] * xv[2],
        xu[0] * xv[1] - xu[1] * xv[0] };
      const double nl = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
      const double delta = (s % 2 ? 1e-3 : -1e-3) * diag;
      const double v[3] = { x[0] + delta * n[0] / nl, x[1] + delta * n[1] / nl,
        x[2] + delta * n[2] / nl };
      hoembed::VertexEmbedding r;
      m.Embed(v, hoembed::EMBED_NORMAL_OFFSET, r);
      wrongSide += (delta < 0) != r.Inside;
      if (delta > 0) // the foot of a short normal is the closest point
        worstNear = std::max(worstNear, std::abs(r.ClosestDistance - delta) / diag);
    }
    HOEMBED_CHECK(
      wrongSide == 0, "order %d: %d near-boundary points on the wrong side", p, wrongSide);
    HOEMBED_CHECK(worstNear <= 1e-8, "order %d: near-boundary distance off by %g", p, worstNear);
    std::printf("%s order %d: %d inside, %d outside, excess %.2e, below %.2e, residual %.2e, "
                "rigid %.2e, fallbacks %d, uncertified %d\n",
      strong ? "strongly curved" : "curved", p, inside, outside, worstExcess, worstBelow,
      worstResidual, worstRigid, fallbacks, uncertified);
    HOEMBED_CHECK(inside > 3 && outside > 10, "order %d: both kinds of points", p);
    HOEMBED_CHECK(worstExcess <= 1e-8, "order %d: excess %g", p, worstExcess);
    HOEMBED_CHECK(worstBelow <= 1e-8, "order %d: below the brute force by %g", p, worstBelow);
    HOEMBED_CHECK(worstResidual <= 1e-10, "order %d: residual %g", p, worstResidual);
    HOEMBED_CHECK(worstRigid <= 1e-9, "order %d: rigid motion off by %g", p, worstRigid);
    HOEMBED_CHECK(uncertified == 0, "order %d: %d uncertified", p, uncertified);
  }
}

// Embed `points` through the driver; closest distances out, or the error.
std::string DriverDistances(
  const PlainTetMesh& mesh, const std::vector<double>& points, std::vector<double>& closest)
{
  hoembed::EmbeddingDriver d;
  const std::int64_t n = static_cast<std::int64_t>(points.size() / 3);
  std::string e = d.SetSurface(points.data(), nullptr, n, {}, {});
  if (!e.empty())
    return e;
  const hoembed::TetMeshArrays view = mesh.View();
  e = d.PrepareAndOrder(&view, true, 0);
  if (!e.empty())
    return e;
  d.Embed(hoembed::EMBED_NORMAL_OFFSET, {});
  std::vector<std::int64_t> cell(n);
  std::vector<double> pc(3 * n), dist(n), res(n);
  std::vector<signed char> face(n);
  std::vector<int> its(n), vis(n);
  std::vector<unsigned char> fb(n);
  closest.assign(n, 0.0);
  hoembed::EmbeddingOutputArrays out;
  out.CellId = cell.data();
  out.ParametricCoords = pc.data();
  out.Distance = dist.data();
  out.Residual = res.data();
  out.ClosestDistance = closest.data();
  out.Face = face.data();
  out.Iterations = its.data();
  out.Visited = vis.data();
  out.Fallback = fb.data();
  hoembed::EmbeddingSummary summary;
  e = d.WriteArrays(out, summary);
  if (summary.Uncertified > 0 || summary.Inexact > 0)
    return "uncertified or inexact points";
  return e;
}

void TestTet10AsOrder3()
{
  // the tet10 mesh of the curved box, and the same cells re-expressed at order 3
  vtkSmartPointer<vtkUnstructuredGrid> tet10 = MakeBoxTetMesh(2, 2, 2, 2, 2, 2, 2, Curve);
  const PlainTetMesh quadratic(tet10);
  LagrangeBox cubic =
    MakeLagrangeBox(2, 3, [&](const double*, std::int64_t c, const double pc[3], double x[3]) {
      double nodes[30], N[10];
      for (int k = 0; k < 10; ++k)
        for (int d = 0; d < 3; ++d)
          nodes[3 * k + d] = quadratic.Points[3 * quadratic.Connectivity[10 * c + k] + d];
      hoembed::Tet10Shape(pc, N);
      hoembed::Interpolate(10, N, nodes, x);
    });
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> box(-0.6, 2.6);
  std::vector<double> points;
  for (int s = 0; s < 300; ++s)
    points.push_back(box(rng));
  std::vector<double> a, b;
  const std::string ea = DriverDistances(quadratic, points, a);
  const std::string eb = DriverDistances(AsPlainMesh(cubic), points, b);
  HOEMBED_CHECK(ea.empty() && eb.empty(), "%s / %s", ea.c_str(), eb.c_str());
  double worst = 0;
  for (std::size_t i = 0; i < a.size() && i < b.size(); ++i)
    worst = std::max(worst, std::abs(a[i] - b[i]));
  const double diag = std::sqrt(3.0) * 2.4; // about the curved box's diagonal
  std::printf("tet10 vs order 3: closest distances differ by %.2e of the diagonal\n", worst / diag);
  HOEMBED_CHECK(worst <= 1e-10 * diag, "tet10 vs order 3: %g", worst);
  HOEMBED_CHECK(a.size() == 100 && b.size() == 100, "points embedded");
}

void TestErrors()
{
  LagrangeBox cubic =
    MakeLagrangeBox(1, 3, [](const double* c, std::int64_t, const double pc[3], double x[3]) {
      StraightPoint(c, pc, x);
    });
  std::vector<double> points = { 0.2, 0.2, 0.2 }, closest;
  PlainTetMesh mixed = AsPlainMesh(cubic);
  mixed.Types[1] = 24;
  std::string e = DriverDistances(mixed, points, closest);
  HOEMBED_CHECK(e.find("mixes cell types") != std::string::npos, "mixed: %s", e.c_str());
  // the 15-node variant (no complete order)
  PlainTetMesh fifteen = AsPlainMesh(cubic);
  fifteen.Offsets.assign(1, 0);
  fifteen.Connectivity.clear();
  for (std::size_t c = 0; c < fifteen.Types.size(); ++c)
  {
    for (int k = 0; k < 15; ++k)
      fifteen.Connectivity.push_back(cubic.Connectivity[20 * c + k]);
    fifteen.Offsets.push_back(fifteen.Connectivity.size());
  }
  e = DriverDistances(fifteen, points, closest);
  HOEMBED_CHECK(e.find("only complete orders 1-4") != std::string::npos, "15 nodes: %s", e.c_str());
  // a folded cell
  PlainTetMesh folded = AsPlainMesh(cubic);
  folded.Points[3 * folded.Connectivity[4] + 0] += 3.0; // an edge node of cell 0, far out
  e = DriverDistances(folded, points, closest);
  HOEMBED_CHECK(e.find("cell 0 (VTK_LAGRANGE_TETRAHEDRON of order 3)") != std::string::npos,
    "folded: %s", e.c_str());
  // the stages that do not handle Lagrange cells still refuse them
  hoembed::TetMeshInput input;
  const PlainTetMesh plain = AsPlainMesh(cubic);
  e = input.Read(plain.View(), hoembed::TetMeshInput::KeepPoints);
  HOEMBED_CHECK(e.find("Unsupported cell type 71") != std::string::npos, "%s", e.c_str());
}
} // namespace

int main(int, char*[])
{
  TestAgainstVTKCell();
  TestClosestPerOrder(false);
  TestClosestPerOrder(true);
  TestTet10AsOrder3();
  TestErrors();
  return Report("TestLagrangeEmbedding");
}
