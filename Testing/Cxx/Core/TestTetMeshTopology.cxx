// TetMeshTopology on generated box meshes (tet4 and tet10, straight and curved) against
// brute force and VTK's surface filters: face neighbours, boundary faces and their
// orientation (divergence theorem), boundary-edge neighbours, node -> face lists, error
// messages, and the run time on a 200k-cell box.
#include "hoembedElementGeometry.h"
#include "hoembedShapeFunctions.h"
#include "hoembedSpatialOrder.h"
#include "hoembedTestUtilities.h"
#include "hoembedTetMeshTopology.h"

#include "vtkCellData.h"
#include "vtkDataSetSurfaceFilter.h"
#include "vtkGeometryFilter.h"
#include "vtkIdTypeArray.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <numeric>
#include <random>
#include <set>
#include <string>
#include <vector>

namespace
{
using Id = hoembed::TetMeshTopology::Id;

struct Mesh
{
  std::vector<Id> Conn;
  std::vector<double> Points;
  Id NumberOfCells = 0;
  int NodesPerCell = 4;
  Id NumberOfPoints() const
  {
    return static_cast<Id>(Points.size() / 3);
  }
};

Mesh FromGrid(vtkUnstructuredGrid* grid)
{
  Mesh m;
  m.NumberOfCells = grid->GetNumberOfCells();
  const auto conn = hoembed_test::MeshConnectivity(grid, m.NodesPerCell);
  m.Conn.assign(conn.begin(), conn.end());
  m.Points = hoembed_test::PointsOf(grid);
  return m;
}

std::array<Id, 3> SortedCorners(const Id* cell, int f)
{
  std::array<Id, 3> k = { cell[hoembed::TetFaceNodes[f][0]], cell[hoembed::TetFaceNodes[f][1]],
    cell[hoembed::TetFaceNodes[f][2]] };
  std::sort(k.begin(), k.end());
  return k;
}

void Cross(const double a[3], const double b[3], double c[3])
{
  c[0] = a[1] * b[2] - a[2] * b[1];
  c[1] = a[2] * b[0] - a[0] * b[2];
  c[2] = a[0] * b[1] - a[1] * b[0];
}

// Integrals over a boundary face of n dA and of x.n dA / 3 (Duffy-collapsed Gauss rule,
// exact for the polynomial integrands of tri3 and tri6 patches).
void FaceIntegrals(
  const Mesh& m, const hoembed::TetMeshTopology& topo, Id b, double area[3], double& flux)
{
  static const double g[4] = { -0.8611363115940526, -0.3399810435848563, 0.3399810435848563,
    0.8611363115940526 };
  static const double w[4] = { 0.3478548451374538, 0.6521451548625461, 0.6521451548625461,
    0.3478548451374538 };
  const int npf = topo.GetNodesPerFace();
  const Id* fn = &topo.BoundaryFaceNodes[b * npf];
  area[0] = area[1] = area[2] = flux = 0.0;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
    {
      const double a = 0.5 * (g[i] + 1), c = 0.5 * (g[j] + 1);
      const double uv[2] = { a, (1 - a) * c };
      const double wt = w[i] * w[j] / 4.0 * (1 - a);
      double N[6], dN[12];
      if (npf == 6)
      {
        hoembed::Tri6Shape(uv, N);
        hoembed::Tri6Derivs(uv, dN);
      }
      else
      {
        hoembed::Tri3Shape(uv, N);
        hoembed::Tri3Derivs(uv, dN);
      }
      double x[3] = { 0, 0, 0 }, xu[3] = { 0, 0, 0 }, xv[3] = { 0, 0, 0 };
      for (int k = 0; k < npf; ++k)
        for (int d = 0; d < 3; ++d)
        {
          const double p = m.Points[3 * fn[k] + d];
          x[d] += N[k] * p;
          xu[d] += dN[k] * p;
          xv[d] += dN[npf + k] * p;
        }
      double n[3];
      Cross(xu, xv, n);
      for (int d = 0; d < 3; ++d)
        area[d] += wt * n[d];
      flux += wt * (x[0] * n[0] + x[1] * n[1] + x[2] * n[2]) / 3.0;
    }
}

double CellVolume(const Mesh& m, Id c)
{
  double x[30];
  for (int a = 0; a < m.NodesPerCell; ++a)
    for (int d = 0; d < 3; ++d)
      x[3 * a + d] = m.Points[3 * m.Conn[c * m.NodesPerCell + a] + d];
  return m.NodesPerCell == 10 ? hoembed::Tet10Volume(x) : hoembed::Tet4Volume(x);
}

void CheckMesh(vtkUnstructuredGrid* grid, const char* name)
{
  const Mesh m = FromGrid(grid);
  const int npc = m.NodesPerCell;
  hoembed::TetMeshTopology topo;
  const std::string err = topo.Build(m.Conn.data(), m.NumberOfCells, npc, m.NumberOfPoints());
  HOEMBED_CHECK(err.empty(), "%s: Build failed: %s", name, err.c_str());
  if (!err.empty())
    return;
  const int npf = topo.GetNodesPerFace();
  HOEMBED_CHECK(npf == (npc == 10 ? 6 : 3), "%s: nodes per face %d", name, npf);

  // Brute force: every face keyed by its sorted corners.
  std::map<std::array<Id, 3>, std::vector<std::pair<Id, int>>> faces;
  for (Id c = 0; c < m.NumberOfCells; ++c)
    for (int f = 0; f < 4; ++f)
      faces[SortedCorners(&m.Conn[c * npc], f)].push_back({ c, f });
  Id brute = 0;
  for (const auto& kv : faces)
    brute += kv.second.size() == 1;

  // Face neighbours: symmetric, the right cells, sharing the three corners (and mids).
  for (Id c = 0; c < m.NumberOfCells; ++c)
    for (int f = 0; f < 4; ++f)
    {
      const Id n = topo.FaceNeighbor[4 * c + f];
      const auto& owners = faces[SortedCorners(&m.Conn[c * npc], f)];
      if (owners.size() == 1)
      {
        HOEMBED_CHECK(n == -1, "%s: cell %lld face %d has no neighbour but got %lld", name,
          (long long)c, f, (long long)n);
        HOEMBED_CHECK(topo.CellBoundaryFace[4 * c + f] >= 0, "%s: boundary face not indexed", name);
        continue;
      }
      const Id other = owners[0].first == c ? owners[1].first : owners[0].first;
      const int otherFace = owners[0].first == c ? owners[1].second : owners[0].second;
      HOEMBED_CHECK(n == other, "%s: cell %lld face %d neighbour %lld, expected %lld", name,
        (long long)c, f, (long long)n, (long long)other);
      HOEMBED_CHECK(topo.FaceNeighbor[4 * other + otherFace] == c, "%s: not symmetric", name);
      HOEMBED_CHECK(topo.CellBoundaryFace[4 * c + f] == -1, "%s: interior face indexed", name);
      if (npc == 10)
      {
        std::set<Id> a, b;
        for (int k = 0; k < 6; ++k)
        {
          a.insert(m.Conn[c * npc + hoembed::TetFaceNodes[f][k]]);
          b.insert(m.Conn[other * npc + hoembed::TetFaceNodes[otherFace][k]]);
        }
        HOEMBED_CHECK(a == b, "%s: neighbours do not share the face's six nodes", name);
      }
    }

  // Boundary faces: count against brute force and VTK's surface filters.
  const Id nbf = topo.GetNumberOfBoundaryFaces();
  HOEMBED_CHECK(nbf == brute, "%s: %lld boundary faces, brute force %lld", name, (long long)nbf,
    (long long)brute);
  vtkNew<vtkDataSetSurfaceFilter> surf;
  surf->SetInputData(grid);
  surf->PassThroughCellIdsOn();
  surf->SetNonlinearSubdivisionLevel(0);
  surf->Update();
  vtkNew<vtkGeometryFilter> geom;
  geom->SetInputData(grid);
  geom->Update();
  std::printf("%s: %lld cells, %lld boundary faces (brute force %lld, "
              "vtkDataSetSurfaceFilter %lld, vtkGeometryFilter %lld)\n",
    name, (long long)m.NumberOfCells, (long long)nbf, (long long)brute,
    (long long)surf->GetOutput()->GetNumberOfCells(),
    (long long)geom->GetOutput()->GetNumberOfCells());
  HOEMBED_CHECK(surf->GetOutput()->GetNumberOfCells() == nbf,
    "%s: vtkDataSetSurfaceFilter has %lld faces", name,
    (long long)surf->GetOutput()->GetNumberOfCells());
  HOEMBED_CHECK(geom->GetOutput()->GetNumberOfCells() == (npc == 10 ? 4 : 1) * nbf,
    "%s: vtkGeometryFilter has %lld faces", name, (long long)geom->GetOutput()->GetNumberOfCells());
  // The same faces (sorted corner triples; VTK's output points are mapped to the nearest
  // mesh node, as VTK 9.1 outputs them in single precision) and, for tet4, the same
  // owning cells. (vtkDataSetSurfaceFilter takes a different path for quadratic cells,
  // where vtkOriginalCellIds holds face indices, and vtkGeometryFilter splits each
  // quadratic triangle into 4 linear ones.)
  auto* origCells = vtkIdTypeArray::SafeDownCast(
    surf->GetOutput()->GetCellData()->GetArray(surf->GetOriginalCellIdsName()));
  HOEMBED_CHECK(origCells, "%s: no original cell ids", name);
  {
    vtkPolyData* out = surf->GetOutput();
    std::vector<Id> nearest(out->GetNumberOfPoints());
    for (vtkIdType i = 0; i < out->GetNumberOfPoints(); ++i)
    {
      double y[3], best = 1e300;
      out->GetPoint(i, y);
      for (Id j = 0; j < m.NumberOfPoints(); ++j)
      {
        const double* x = &m.Points[3 * j];
        const double d2 = (x[0] - y[0]) * (x[0] - y[0]) + (x[1] - y[1]) * (x[1] - y[1]) +
          (x[2] - y[2]) * (x[2] - y[2]);
        if (d2 < best)
        {
          best = d2;
          nearest[i] = j;
        }
      }
    }
    std::vector<std::array<Id, 3>> vtkFaces, ourFaces;
    for (vtkIdType i = 0; i < out->GetNumberOfCells(); ++i)
    {
      vtkIdType npts;
      const vtkIdType* pts;
      out->GetCellPoints(i, npts, pts);
      std::array<Id, 3> k = { nearest[pts[0]], nearest[pts[1]], nearest[pts[2]] };
      std::sort(k.begin(), k.end());
      vtkFaces.push_back(k);
    }
    for (Id b = 0; b < nbf; ++b)
    {
      std::array<Id, 3> k = { topo.BoundaryFaceNodes[b * npf], topo.BoundaryFaceNodes[b * npf + 1],
        topo.BoundaryFaceNodes[b * npf + 2] };
      std::sort(k.begin(), k.end());
      ourFaces.push_back(k);
    }
    std::sort(vtkFaces.begin(), vtkFaces.end());
    std::sort(ourFaces.begin(), ourFaces.end());
    HOEMBED_CHECK(vtkFaces == ourFaces, "%s: boundary faces differ from VTK's", name);
    if (npc == 4 && origCells)
    {
      std::vector<Id> a(topo.BoundaryFaceCell.begin(), topo.BoundaryFaceCell.end()), b;
      for (vtkIdType i = 0; i < origCells->GetNumberOfTuples(); ++i)
        b.push_back(origCells->GetValue(i));
      std::sort(a.begin(), a.end());
      std::sort(b.begin(), b.end());
      HOEMBED_CHECK(a == b, "%s: boundary face cells differ from VTK's", name);
    }
  }

  // Each boundary face: its cell and local face agree, the nodes are the cell's face nodes.
  for (Id b = 0; b < nbf; ++b)
  {
    const Id c = topo.BoundaryFaceCell[b];
    const int f = topo.BoundaryFaceLocal[b];
    HOEMBED_CHECK(topo.CellBoundaryFace[4 * c + f] == b, "%s: CellBoundaryFace mismatch", name);
    for (int k = 0; k < npf; ++k)
      HOEMBED_CHECK(
        topo.BoundaryFaceNodes[b * npf + k] == m.Conn[c * npc + hoembed::TetFaceNodes[f][k]],
        "%s: boundary face %lld node %d", name, (long long)b, k);
  }

  // Orientation: closed surface (sum of n dA = 0) and the divergence theorem gives the
  // volume of the cells (positive, so the faces point out).
  double areaSum[3] = { 0, 0, 0 }, flux = 0.0, totalArea = 0.0, volume = 0.0;
  for (Id b = 0; b < nbf; ++b)
  {
    double a[3], fl;
    FaceIntegrals(m, topo, b, a, fl);
    for (int d = 0; d < 3; ++d)
      areaSum[d] += a[d];
    totalArea += std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
    flux += fl;
  }
  for (Id c = 0; c < m.NumberOfCells; ++c)
    volume += CellVolume(m, c);
  const double areaErr =
    std::sqrt(areaSum[0] * areaSum[0] + areaSum[1] * areaSum[1] + areaSum[2] * areaSum[2]);
  std::printf("%s: |sum n dA| / area = %.3g, divergence-theorem volume %.15g, cell volumes %.15g\n",
    name, areaErr / totalArea, flux, volume);
  HOEMBED_CHECK(areaErr < 1e-12 * totalArea, "%s: boundary not closed (%g)", name, areaErr);
  HOEMBED_CHECK(volume > 0 && std::abs(flux - volume) < 1e-11 * volume,
    "%s: boundary flux %.17g != volume %.17g (inward faces?)", name, flux, volume);

  // Boundary-face neighbours across edges: symmetric, sharing the edge in opposite
  // directions (consistent orientation), the box surface is a closed manifold.
  HOEMBED_CHECK(topo.NumberOfNonManifoldBoundaryEdges == 0, "%s: non-manifold edges", name);
  for (Id b = 0; b < nbf; ++b)
    for (int e = 0; e < 3; ++e)
    {
      const Id n = topo.BoundaryFaceNeighbor[3 * b + e];
      HOEMBED_CHECK(n >= 0 && n != b, "%s: face %lld edge %d has neighbour %lld", name,
        (long long)b, e, (long long)n);
      if (n < 0)
        continue;
      const Id p = topo.BoundaryFaceNodes[b * npf + e];
      const Id q = topo.BoundaryFaceNodes[b * npf + (e + 1) % 3];
      int found = 0;
      for (int e2 = 0; e2 < 3; ++e2)
      {
        const Id p2 = topo.BoundaryFaceNodes[n * npf + e2];
        const Id q2 = topo.BoundaryFaceNodes[n * npf + (e2 + 1) % 3];
        if (p2 == q && q2 == p)
        {
          ++found;
          HOEMBED_CHECK(topo.BoundaryFaceNeighbor[3 * n + e2] == b,
            "%s: edge neighbours not "
            "symmetric",
            name);
          if (npf == 6)
            HOEMBED_CHECK(
              topo.BoundaryFaceNodes[n * npf + 3 + e2] == topo.BoundaryFaceNodes[b * npf + 3 + e],
              "%s: edge mid nodes differ", name);
        }
      }
      HOEMBED_CHECK(found == 1, "%s: neighbour does not share edge reversed (%d)", name, found);
    }

  // Boundary edges: unique, 3/2 per face, with the right mid node; Euler characteristic 2.
  const Id nbe = topo.GetNumberOfBoundaryEdges();
  HOEMBED_CHECK(2 * nbe == 3 * nbf, "%s: %lld boundary edges for %lld faces", name, (long long)nbe,
    (long long)nbf);
  std::map<std::pair<Id, Id>, Id> edgeMid;
  for (Id b = 0; b < nbf; ++b)
    for (int e = 0; e < 3; ++e)
    {
      Id p = topo.BoundaryFaceNodes[b * npf + e], q = topo.BoundaryFaceNodes[b * npf + (e + 1) % 3];
      edgeMid[{ std::min(p, q), std::max(p, q) }] =
        npf == 6 ? topo.BoundaryFaceNodes[b * npf + 3 + e] : -1;
    }
  HOEMBED_CHECK(static_cast<Id>(edgeMid.size()) == nbe, "%s: %lld unique edges, topology %lld",
    name, (long long)edgeMid.size(), (long long)nbe);
  std::set<std::pair<Id, Id>> seen;
  for (Id i = 0; i < nbe; ++i)
  {
    const Id* en = &topo.BoundaryEdgeNodes[3 * i];
    HOEMBED_CHECK(en[0] < en[1], "%s: edge not sorted", name);
    auto it = edgeMid.find({ en[0], en[1] });
    HOEMBED_CHECK(it != edgeMid.end() && it->second == en[2], "%s: boundary edge %lld wrong", name,
      (long long)i);
    HOEMBED_CHECK(seen.insert({ en[0], en[1] }).second, "%s: boundary edge repeated", name);
  }
  std::set<Id> cornerNodes;
  for (Id b = 0; b < nbf; ++b)
    for (int k = 0; k < 3; ++k)
      cornerNodes.insert(topo.BoundaryFaceNodes[b * npf + k]);
  const long long euler = (long long)cornerNodes.size() - (long long)nbe + (long long)nbf;
  HOEMBED_CHECK(euler == 2, "%s: Euler characteristic %lld", name, euler);

  // Node -> boundary faces (CSR) against brute force.
  std::vector<std::vector<Id>> nodeFaces(m.NumberOfPoints());
  for (Id b = 0; b < nbf; ++b)
    for (int k = 0; k < npf; ++k)
      nodeFaces[topo.BoundaryFaceNodes[b * npf + k]].push_back(b);
  HOEMBED_CHECK(static_cast<Id>(topo.NodeFaceOffsets.size()) == m.NumberOfPoints() + 1,
    "%s: offsets size", name);
  for (Id i = 0; i < m.NumberOfPoints(); ++i)
  {
    std::vector<Id> got(topo.NodeFaces.begin() + topo.NodeFaceOffsets[i],
      topo.NodeFaces.begin() + topo.NodeFaceOffsets[i + 1]);
    std::sort(got.begin(), got.end());
    HOEMBED_CHECK(got == nodeFaces[i], "%s: faces of node %lld", name, (long long)i);
    HOEMBED_CHECK(topo.IsBoundaryNode(i) == !nodeFaces[i].empty(), "%s: IsBoundaryNode(%lld)", name,
      (long long)i);
  }
}

bool Contains(const std::string& s, const char* what)
{
  return s.find(what) != std::string::npos;
}

void TestErrors()
{
  hoembed::TetMeshTopology topo;
  // Two tets sharing face (0, 1, 2).
  std::vector<Id> conn = { 0, 1, 2, 3, 0, 2, 1, 4 };
  HOEMBED_CHECK(topo.Build(conn.data(), 2, 4, 5).empty(), "valid input rejected");
  HOEMBED_CHECK(topo.GetNumberOfBoundaryFaces() == 6, "two tets: %lld boundary faces",
    (long long)topo.GetNumberOfBoundaryFaces());

  std::string err = topo.Build(conn.data(), 2, 4, 4);
  std::printf("out of range: %s\n", err.c_str());
  HOEMBED_CHECK(Contains(err, "point 4") && Contains(err, "outside"), "message: %s", err.c_str());
  conn[5] = -1;
  err = topo.Build(conn.data(), 2, 4, 5);
  std::printf("negative id: %s\n", err.c_str());
  HOEMBED_CHECK(Contains(err, "cell 1") && Contains(err, "-1"), "message: %s", err.c_str());
  conn[5] = 2;

  conn[7] = 0;
  err = topo.Build(conn.data(), 2, 4, 5);
  std::printf("repeated node: %s\n", err.c_str());
  HOEMBED_CHECK(
    Contains(err, "cell 1") && Contains(err, "repeats point 0"), "message: %s", err.c_str());
  conn[7] = 4;

  // A third tet on face (0, 1, 2).
  std::vector<Id> three = { 0, 1, 2, 3, 0, 2, 1, 4, 0, 1, 2, 5 };
  err = topo.Build(three.data(), 3, 4, 6);
  std::printf("face in 3 cells: %s\n", err.c_str());
  HOEMBED_CHECK(
    Contains(err, "(0, 1, 2)") && Contains(err, "more than two"), "message: %s", err.c_str());

  HOEMBED_CHECK(
    topo.FaceNeighbor.empty() && topo.GetNumberOfBoundaryFaces() == 0 && topo.NodeFaces.empty(),
    "a failed Build left a half-built topology");

  err = topo.Build(conn.data(), 1, 8, 5);
  std::printf("8 nodes per cell: %s\n", err.c_str());
  HOEMBED_CHECK(!err.empty(), "8 nodes per cell accepted");

  err = topo.Build(conn.data(), -2, 4, 5);
  std::printf("negative cell count: %s\n", err.c_str());
  HOEMBED_CHECK(!err.empty(), "negative cell count accepted");
  err = topo.Build(conn.data(), 2, 4, -5);
  std::printf("negative point count: %s\n", err.c_str());
  HOEMBED_CHECK(!err.empty(), "negative point count accepted");

  // tet10 neighbours that share the corners but not the mid-edge nodes (a crack).
  std::vector<Id> q = { 0, 1, 2, 3, 5, 6, 7, 8, 9, 10, 0, 2, 1, 4, 7, 6, 5, 11, 12, 13 };
  HOEMBED_CHECK(topo.Build(q.data(), 2, 10, 14).empty(), "conforming tet10 pair rejected");
  q[15] = 14; // mid node of edge 21 in the second cell differs from node 6
  err = topo.Build(q.data(), 2, 10, 15);
  std::printf("non-conforming tet10: %s\n", err.c_str());
  HOEMBED_CHECK(Contains(err, "mid-edge"), "message: %s", err.c_str());

  // Non-manifold boundary edge: two tets touching along edge (0, 1) only.
  std::vector<Id> bow = { 0, 1, 2, 3, 1, 0, 4, 5 };
  HOEMBED_CHECK(topo.Build(bow.data(), 2, 4, 6).empty(), "bow tie rejected");
  HOEMBED_CHECK(topo.NumberOfNonManifoldBoundaryEdges == 1, "bow tie: %lld non-manifold edges",
    (long long)topo.NumberOfNonManifoldBoundaryEdges);
  int minusOne = 0;
  for (Id n : topo.BoundaryFaceNeighbor)
    minusOne += n < 0;
  HOEMBED_CHECK(minusOne == 4, "bow tie: %d face edges without a neighbour", minusOne);

  // Empty mesh.
  HOEMBED_CHECK(
    topo.Build(nullptr, 0, 10, 0).empty() && topo.GetNumberOfBoundaryFaces() == 0, "empty mesh");
}

void TestTiming()
{
  for (int order = 1; order <= 2; ++order)
  {
    for (int n : { 16, 32 })
    {
      auto grid = hoembed_test::MakeBoxTetMesh(n, n, n + 1, 1, 1, 1, order);
      const Mesh m = FromGrid(grid);
      hoembed::TetMeshTopology topo;
      const auto t0 = std::chrono::steady_clock::now();
      const std::string err =
        topo.Build(m.Conn.data(), m.NumberOfCells, m.NodesPerCell, m.NumberOfPoints());
      const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      HOEMBED_CHECK(err.empty(), "%s", err.c_str());
      const Id expect = 2 * 2 * (Id(n) * n + 2 * Id(n) * (n + 1)); // 2 triangles per square
      HOEMBED_CHECK(topo.GetNumberOfBoundaryFaces() == expect,
        "box %d: %lld boundary faces, "
        "expected %lld",
        n, (long long)topo.GetNumberOfBoundaryFaces(), (long long)expect);
      // VTK's own boundary extraction on the same grid, for a ratio (not asserted).
      vtkNew<vtkDataSetSurfaceFilter> surf;
      surf->SetInputData(grid);
      const auto t1 = std::chrono::steady_clock::now();
      surf->Update();
      const double sv =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
      std::printf("timing: tet%d box %dx%dx%d: %lld cells, %lld points, Build %.3f s "
                  "(%.0f ns/cell); vtkDataSetSurfaceFilter %.3f s (ratio %.2f)\n",
        order == 2 ? 10 : 4, n, n, n + 1, (long long)m.NumberOfCells, (long long)m.NumberOfPoints(),
        s, 1e9 * s / m.NumberOfCells, sv, s / sv);
    }
  }
}

// A fan: every tet shares node 0 (the centre of a triangulated sphere, node 0 has the
// smallest id). Bucketing faces by their smallest node id puts nearly all faces in one
// bucket: matching inside a bucket must not be quadratic.
void TestFan()
{
  const int nu = 160, nv = 80; // latitude-longitude sphere: 2 * nu * (nv - 1) triangles
  std::vector<double> pts = { 0, 0, 0, 0, 0, 1, 0, 0, -1 };
  auto ring = [&](int i, int j) { return Id(3 + (j - 1) * nu + (i % nu)); };
  for (int j = 1; j < nv; ++j)
    for (int i = 0; i < nu; ++i)
    {
      const double th = M_PI * j / nv, ph = 2 * M_PI * i / nu;
      pts.insert(
        pts.end(), { std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th) });
    }
  std::vector<std::array<Id, 3>> tris;
  for (int i = 0; i < nu; ++i)
  {
    tris.push_back({ 1, ring(i, 1), ring(i + 1, 1) });
    tris.push_back({ 2, ring(i + 1, nv - 1), ring(i, nv - 1) });
    for (int j = 1; j + 1 < nv; ++j)
    {
      tris.push_back({ ring(i, j), ring(i, j + 1), ring(i + 1, j + 1) });
      tris.push_back({ ring(i, j), ring(i + 1, j + 1), ring(i + 1, j) });
    }
  }
  std::vector<Id> conn;
  for (const auto& t : tris)
    conn.insert(conn.end(), { 0, t[0], t[1], t[2] });
  Mesh m;
  m.Conn = conn;
  m.Points = pts;
  m.NumberOfCells = static_cast<Id>(tris.size());
  double volume = 0;
  for (Id c = 0; c < m.NumberOfCells; ++c)
    volume += CellVolume(m, c);
  hoembed::TetMeshTopology topo;
  const auto t0 = std::chrono::steady_clock::now();
  const std::string err = topo.Build(conn.data(), m.NumberOfCells, 4, m.NumberOfPoints());
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  HOEMBED_CHECK(err.empty(), "fan: %s", err.c_str());
  HOEMBED_CHECK(volume > 0, "fan tets are not positive");
  HOEMBED_CHECK(topo.GetNumberOfBoundaryFaces() == m.NumberOfCells, "fan: %lld boundary faces",
    (long long)topo.GetNumberOfBoundaryFaces());
  HOEMBED_CHECK(topo.NumberOfNonManifoldBoundaryEdges == 0, "fan: non-manifold edges");
  Id interior = 0;
  for (Id n : topo.FaceNeighbor)
    interior += n >= 0;
  HOEMBED_CHECK(
    interior == 3 * m.NumberOfCells, "fan: %lld interior face sides", (long long)interior);
  std::printf("timing: fan of %lld tets around node 0: Build %.3f s (%.0f ns/cell)\n",
    (long long)m.NumberOfCells, s, 1e9 * s / m.NumberOfCells);
}
// SpatialOrder on a tet10 box whose cells and nodes were shuffled: both orders are
// permutations, the cell order sorts a Morton key computed bit by bit here (the
// interleaving of the quantised centroid coordinates), nodes come in order of first use
// (corners, then mid-edge nodes),
// and face neighbours end up close in memory (their mean id distance drops well below the
// shuffled mesh's). The reordered mesh has the same topology (boundary faces).
void TestSpatialOrder()
{
  auto grid = hoembed_test::MakeBoxTetMesh(10, 8, 6, 1, 1, 1, 2);
  Mesh m = FromGrid(grid);
  const int npc = m.NodesPerCell;
  const Id nc = m.NumberOfCells, np = m.NumberOfPoints();
  std::mt19937 rng(3);
  std::vector<Id> shuffle(nc), relabel(np);
  std::iota(shuffle.begin(), shuffle.end(), Id(0));
  std::iota(relabel.begin(), relabel.end(), Id(0));
  std::shuffle(shuffle.begin(), shuffle.end(), rng);
  std::shuffle(relabel.begin(), relabel.end(), rng);
  Mesh s;
  s.NodesPerCell = npc;
  s.NumberOfCells = nc;
  s.Points.resize(3 * np);
  for (Id i = 0; i < np; ++i)
    for (int d = 0; d < 3; ++d)
      s.Points[3 * relabel[i] + d] = m.Points[3 * i + d];
  for (Id c = 0; c < nc; ++c)
    for (int a = 0; a < npc; ++a)
      s.Conn.push_back(relabel[m.Conn[npc * shuffle[c] + a]]);

  std::vector<Id> cellOrder, pointOrder;
  hoembed::SpatialOrder(s.Points, s.Conn, npc, cellOrder, pointOrder);
  auto isPermutation = [](std::vector<Id> v, Id n) {
    std::sort(v.begin(), v.end());
    for (Id i = 0; i < n; ++i)
      if (v.size() != static_cast<size_t>(n) || v[i] != i)
        return false;
    return true;
  };
  HOEMBED_CHECK(isPermutation(cellOrder, nc), "spatial order: cell order is not a permutation");
  HOEMBED_CHECK(isPermutation(pointOrder, np), "spatial order: node order is not a permutation");

  // reference Morton key, bit by bit
  std::vector<double> centre(3 * nc);
  double lo[3] = { 1e300, 1e300, 1e300 }, hi[3] = { -1e300, -1e300, -1e300 };
  for (Id c = 0; c < nc; ++c)
    for (int d = 0; d < 3; ++d)
    {
      double sum = 0.0;
      for (int a = 0; a < 4; ++a)
        sum += s.Points[3 * s.Conn[npc * c + a] + d];
      centre[3 * c + d] = sum / 4.0;
      lo[d] = std::min(lo[d], centre[3 * c + d]);
      hi[d] = std::max(hi[d], centre[3 * c + d]);
    }
  const double ext = std::max({ hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2] });
  auto key = [&](Id c) {
    std::uint64_t k = 0;
    for (int d = 0; d < 3; ++d)
    {
      const double q =
        std::min(2097151.0, std::max(0.0, (centre[3 * c + d] - lo[d]) * 2097151.0 / ext));
      const auto v = static_cast<std::uint64_t>(q);
      for (int b = 0; b < 21; ++b)
        k |= ((v >> b) & 1u) << (3 * b + d);
    }
    return k;
  };
  int unsorted = 0;
  for (Id k = 1; k < nc; ++k)
  {
    const std::uint64_t a = key(cellOrder[k - 1]), b = key(cellOrder[k]);
    unsorted += a > b || (a == b && cellOrder[k - 1] > cellOrder[k]);
  }
  HOEMBED_CHECK(unsorted == 0, "spatial order: %d cells out of Morton order", unsorted);
  // corner nodes in order of first use, then the mid-edge nodes
  std::vector<Id> firstUse;
  std::vector<char> seen(np, 0);
  for (int mids = 0; mids < 2; ++mids)
    for (Id k = 0; k < nc; ++k)
      for (int a = 0; a < npc; ++a)
      {
        const Id i = s.Conn[npc * cellOrder[k] + a];
        if ((a >= 4) == (mids == 1) && !seen[i])
        {
          seen[i] = 1;
          firstUse.push_back(i);
        }
      }
  HOEMBED_CHECK(firstUse == pointOrder, "spatial order: nodes not in order of first use");

  // the reordered mesh: same boundary, neighbours close in memory
  std::vector<Id> newId(np);
  for (Id k = 0; k < np; ++k)
    newId[pointOrder[k]] = k;
  std::vector<Id> conn;
  for (Id k = 0; k < nc; ++k)
    for (int a = 0; a < npc; ++a)
      conn.push_back(newId[s.Conn[npc * cellOrder[k] + a]]);
  hoembed::TetMeshTopology before, after;
  HOEMBED_CHECK(before.Build(s.Conn.data(), nc, npc, np).empty() &&
      after.Build(conn.data(), nc, npc, np).empty(),
    "spatial order: topology failed");
  HOEMBED_CHECK(before.GetNumberOfBoundaryFaces() == after.GetNumberOfBoundaryFaces(),
    "spatial order: %lld boundary faces before, %lld after",
    (long long)before.GetNumberOfBoundaryFaces(), (long long)after.GetNumberOfBoundaryFaces());
  auto spread = [&](const hoembed::TetMeshTopology& t) {
    double sum = 0.0;
    Id n = 0;
    for (Id i = 0; i < 4 * nc; ++i)
      if (t.FaceNeighbor[i] >= 0)
      {
        sum += std::fabs(double(t.FaceNeighbor[i] - i / 4));
        ++n;
      }
    return sum / std::max<Id>(n, 1);
  };
  const double sb = spread(before), sa = spread(after);
  HOEMBED_CHECK(
    sa < 0.2 * sb, "spatial order: mean neighbour id distance %.1f, shuffled %.1f", sa, sb);
  std::printf("spatial order: %lld cells, mean neighbour id distance %.1f (shuffled %.1f)\n",
    (long long)nc, sa, sb);
}
} // namespace

int main(int, char*[])
{
  for (int order = 1; order <= 2; ++order)
  {
    const std::string o = order == 2 ? "tet10" : "tet4";
    CheckMesh(hoembed_test::MakeBoxTetMesh(1, 1, 1, 1, 1, 1, order), (o + " cube").c_str());
    CheckMesh(hoembed_test::MakeBoxTetMesh(4, 3, 2, 4, 3, 2, order), (o + " box").c_str());
    // Curved: the box mapped onto a ball (nodes pushed radially), and a twisted bar.
    auto ball = [](double p[3]) {
      double c[3] = { 2 * p[0] - 1, 2 * p[1] - 1, 2 * p[2] - 1 };
      const double inf = std::max({ std::abs(c[0]), std::abs(c[1]), std::abs(c[2]) });
      const double r = std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
      for (int d = 0; d < 3; ++d)
        p[d] = r > 0 ? c[d] * inf / r : 0.0;
    };
    CheckMesh(hoembed_test::MakeBoxTetMesh(4, 4, 4, 1, 1, 1, order, ball), (o + " ball").c_str());
    auto twist = [](double p[3]) {
      const double a = 0.3 * p[0];
      const double y = p[1] - 0.5, z = p[2] - 0.5;
      p[1] = std::cos(a) * y - std::sin(a) * z;
      p[2] = std::sin(a) * y + std::cos(a) * z;
    };
    CheckMesh(
      hoembed_test::MakeBoxTetMesh(6, 2, 2, 3, 1, 1, order, twist), (o + " twisted bar").c_str());
  }
  TestErrors();
  TestTiming();
  TestFan();
  TestSpatialOrder();
  return hoembed_test::Report("TestTetMeshTopology");
}
