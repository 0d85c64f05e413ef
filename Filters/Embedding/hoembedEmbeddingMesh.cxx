#include "hoembedEmbeddingMesh.h"
#include "hoembedVector3.h"
#include "hoembedBoundaryNormals.h"
#include "hoembedElementGeometry.h"
#include "hoembedShapeFunctions.h"

#include "hoembedParallel.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <utility>

namespace hoembed
{
namespace
{
// Box of the Bezier control points of a quadratic Lagrange simplex: corners as they are,
// edge controls 2 m - (a + b) / 2.
void ControlBox(const double* pts, const EmbeddingMesh::Id* ids, int ncorner, const int (*edges)[2],
  int nedges, bool quadratic, double* box)
{
  for (int d = 0; d < 3; ++d)
  {
    box[d] = std::numeric_limits<double>::max();
    box[d + 3] = -std::numeric_limits<double>::max();
  }
  auto add = [&](const double* x) {
    for (int d = 0; d < 3; ++d)
    {
      box[d] = std::min(box[d], x[d]);
      box[d + 3] = std::max(box[d + 3], x[d]);
    }
  };
  for (int a = 0; a < ncorner; ++a)
    add(pts + 3 * ids[a]);
  if (!quadratic)
    return;
  for (int e = 0; e < nedges; ++e)
  {
    const double* a = pts + 3 * ids[edges[e][0]];
    const double* b = pts + 3 * ids[edges[e][1]];
    const double* m = pts + 3 * ids[ncorner + e];
    double c[3];
    for (int d = 0; d < 3; ++d)
      c[d] = 2.0 * m[d] - 0.5 * (a[d] + b[d]);
    add(c);
  }
  // a hair of slack for round-off in the callers' distance comparisons
  const double pad =
    1e-12 * std::max({ box[3] - box[0], box[4] - box[1], box[5] - box[2], 1e-300 });
  for (int d = 0; d < 3; ++d)
  {
    box[d] -= pad;
    box[d + 3] += pad;
  }
}

const int TriEdges[3][2] = { { 0, 1 }, { 1, 2 }, { 2, 0 } };

// Squared distance from p to the triangle (a, b, c); 0 (no bound) when degenerate.
double PointTriangleDistance2(const double* p, const double* a, const double* b, const double* c)
{
  double ab[3], ac[3], ap[3], st[2];
  for (int d = 0; d < 3; ++d)
  {
    ab[d] = b[d] - a[d];
    ac[d] = c[d] - a[d];
    ap[d] = p[d] - a[d];
  }
  if (!ClosestPointOnTriangle(ap, ab, ac, st))
    return 0.0;
  double q[3];
  for (int d = 0; d < 3; ++d)
    q[d] = st[0] * ab[d] + st[1] * ac[d] - ap[d];
  return Dot(q, q);
}

// Bezier control points of a cell from its node coordinates x (VTK order): corners as
// they are, edge controls 2 m - (a + b) / 2 (ControlBox's expression); returns their
// number (4 or 10).
int CellControlPoints(const double* x, bool quadratic, double cp[10][3])
{
  int n = 4;
  for (int a = 0; a < 4; ++a)
    for (int d = 0; d < 3; ++d)
      cp[a][d] = x[3 * a + d];
  if (quadratic)
    for (int e = 0; e < 6; ++e, ++n)
      for (int d = 0; d < 3; ++d)
        cp[n][d] = 2.0 * x[3 * (4 + e) + d] -
          0.5 * (x[3 * TetEdgeCorners[e][0] + d] + x[3 * TetEdgeCorners[e][1] + d]);
  return n;
}

// ControlBox of a cell from its control points (the same minima, maxima and pad).
void CellControlBox(const double cp[10][3], int n, double* box)
{
  for (int d = 0; d < 3; ++d)
  {
    box[d] = std::numeric_limits<double>::max();
    box[d + 3] = -std::numeric_limits<double>::max();
  }
  for (int k = 0; k < n; ++k)
    for (int d = 0; d < 3; ++d)
    {
      box[d] = std::min(box[d], cp[k][d]);
      box[d + 3] = std::max(box[d + 3], cp[k][d]);
    }
  const double pad =
    1e-12 * std::max({ box[3] - box[0], box[4] - box[1], box[5] - box[2], 1e-300 });
  for (int d = 0; d < 3; ++d)
  {
    box[d] -= pad;
    box[d + 3] += pad;
  }
}

using Id = EmbeddingMesh::Id;

// Cell maps, boxes, barycentric forms and the cell grid of `mesh` (node ids in range);
// with `firstInvalid`, the lowest cell that fails TetIsValid (the one validity proof)
// (numberOfCells if none).
void BuildCellData(EmbeddingMesh& mesh, const double* points, const Id* conn, Id numberOfCells,
  int nodesPerCell, Id* firstInvalid)
{
  const bool quadratic = nodesPerCell == 10;
  mesh.CellMaps.resize(numberOfCells);
  mesh.CellForms.resize(numberOfCells);
  std::vector<double>& boxes = mesh.Scratch.CellBoxes;
  boxes.resize(6 * numberOfCells);
  std::atomic<Id> lowestInvalid(numberOfCells);
  ParallelLoop(Id(0), numberOfCells, [&](Id cb, Id ce) {
    double x[30];
    for (Id c = cb; c < ce; ++c)
    {
      const Id* ids = conn + nodesPerCell * c;
      for (int a = 0; a < nodesPerCell; ++a)
        for (int d = 0; d < 3; ++d)
          x[3 * a + d] = points[3 * ids[a] + d];
      MakeTetMap(x, nodesPerCell, mesh.CellMaps[c]);
      if (firstInvalid && !TetIsValid(x, nodesPerCell, mesh.CellMaps[c]))
      {
        Id cur = lowestInvalid.load();
        while (c < cur && !lowestInvalid.compare_exchange_weak(cur, c))
        {
        }
      }
      MakeTetBarycentricForm(x, nodesPerCell, mesh.CellForms[c]);
      double cp[10][3];
      const int ncp = CellControlPoints(x, quadratic, cp);
      CellControlBox(cp, ncp, &boxes[6 * c]);
    }
  });
  mesh.CellGrid.Build(boxes);
  if (firstInvalid)
    *firstInvalid = lowestInvalid.load();
}

// Topology, nodal normals, face maps, slabs and the face tree of `mesh`; "" or the problem.
std::string BuildBoundaryData(EmbeddingMesh& mesh, const double* points, const Id* conn,
  Id numberOfPoints, Id numberOfCells, int nodesPerCell, double diagonal)
{
  const bool quadratic = nodesPerCell == 10;
  std::string err = mesh.Topology.Build(conn, numberOfCells, nodesPerCell, numberOfPoints);
  if (!err.empty())
    return err;
  const Id nbf = mesh.Topology.GetNumberOfBoundaryFaces();
  if (nbf == 0)
    return "the mesh has no boundary faces";
  mesh.NodalNormals.assign(3 * numberOfPoints, 0.0);
  ComputeBoundaryNodeNormals(mesh.Topology, points, mesh.NodalNormals.data());

  const int npf = mesh.Topology.GetNodesPerFace();
  mesh.FaceMaps.resize(nbf);
  mesh.FaceSlabs.assign(6 * nbf, 0.0);
  mesh.FaceFlat.assign(10 * nbf, 0.0);
  mesh.NormalMaps.resize(nbf);
  std::vector<double>& boxes = mesh.Scratch.FaceBoxes;
  boxes.resize(6 * nbf);
  auto faceData = [&](Id f, double* x) {
    const Id* ids = &mesh.Topology.BoundaryFaceNodes[npf * f];
    double nx[18];
    for (int a = 0; a < npf; ++a)
      for (int d = 0; d < 3; ++d)
      {
        x[3 * a + d] = points[3 * ids[a] + d];
        nx[3 * a + d] = mesh.NodalNormals[3 * ids[a] + d];
      }
    MakeTriangleMap(x, npf, mesh.FaceMaps[f]);
    MakeTriangleMap(nx, npf, mesh.NormalMaps[f]);
    ControlBox(points, ids, 3, TriEdges, 3, quadratic, &boxes[6 * f]);
    // slab of the corner plane
    double* slab = &mesh.FaceSlabs[6 * f];
    const double* a = x;
    const double* b = x + 3;
    const double* c = x + 6;
    double e1[3], e2[3], n[3];
    for (int d = 0; d < 3; ++d)
    {
      e1[d] = b[d] - a[d];
      e2[d] = c[d] - a[d];
    }
    n[0] = e1[1] * e2[2] - e1[2] * e2[1];
    n[1] = e1[2] * e2[0] - e1[0] * e2[2];
    n[2] = e1[0] * e2[1] - e1[1] * e2[0];
    const double ln = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    double* flat = &mesh.FaceFlat[10 * f];
    for (int k = 0; k < 9; ++k)
      flat[k] = x[k];
    flat[9] = std::numeric_limits<double>::infinity();
    if (!(ln > 0.0))
    {
      slab[0] = slab[1] = slab[2] = 0.0; // no bound from a degenerate plane
      slab[3] = slab[4] = slab[5] = 0.0;
      return;
    }
    for (int d = 0; d < 3; ++d)
      slab[d] = n[d] / ln;
    slab[3] = slab[0] * a[0] + slab[1] * a[1] + slab[2] * a[2];
    double lo = 0.0, hi = 0.0, tmax2 = 0.0;
    if (quadratic)
    {
      for (int e = 0; e < 3; ++e)
      {
        const double* p = x + 3 * TriEdges[e][0];
        const double* q = x + 3 * TriEdges[e][1];
        const double* m = x + 3 * (3 + e);
        double h = -slab[3];
        for (int d = 0; d < 3; ++d)
          h += slab[d] * (2.0 * m[d] - 0.5 * (p[d] + q[d]));
        lo = std::min(lo, h);
        hi = std::max(hi, h);
        // deviation control point 2 (m - (p + q) / 2), its in-plane part
        double dev[3];
        for (int d = 0; d < 3; ++d)
          dev[d] = 2.0 * m[d] - (p[d] + q[d]);
        const double hn = Dot(dev, slab);
        tmax2 = std::max(tmax2, std::max(0.0, Dot(dev, dev) - hn * hn));
      }
    }
    const double pad = 1e-12 * diagonal;
    slab[4] = lo - pad;
    slab[5] = hi + pad;
    flat[9] = std::sqrt(tmax2) * (1.0 + 1e-12) + pad;
  };
  ParallelLoop(Id(0), nbf, [&](Id fb, Id fe) {
    double x[30];
    for (Id f = fb; f < fe; ++f)
      faceData(f, x);
  });
  mesh.FaceGrid.Build(boxes, 32.0); // the tree over the same boxes waits for its first use
  return std::string();
}
} // namespace

bool EmbeddingMesh::CellMayContain(Id c, const double v[3], double tol) const
{
  return this->CellExitFace(c, v, tol) < 0;
}

int EmbeddingMesh::CellExitFace(Id c, const double v[3], double tol) const
{
  const int corner = TetBarycentricBeyond(this->CellForms[c], v, tol);
  return corner < 0 ? -1 : TetCornerOppositeFace[corner];
}

std::string EmbeddingMesh::Build(
  const double* points, Id numberOfPoints, const Id* conn, Id numberOfCells, int nodesPerCell)
{
  if (numberOfPoints < 0 || numberOfCells < 0 || nodesPerCell < 0)
    return this->Topology.Build(conn, numberOfCells, nodesPerCell, numberOfPoints);
  this->Points.assign(points, points + 3 * numberOfPoints);
  this->Connectivity.assign(conn, conn + nodesPerCell * numberOfCells);
  return this->Prepare(nodesPerCell);
}

std::string EmbeddingMesh::Build(
  std::vector<double> pointsIn, std::vector<Id> connIn, int nodesPerCell)
{
  this->Points = std::move(pointsIn);
  this->Connectivity = std::move(connIn);
  return this->Prepare(nodesPerCell);
}

const AabbTree& EmbeddingMesh::GetFaceTree() const
{
  if (!this->FaceTreeBuilt.load(std::memory_order_acquire))
  {
    std::lock_guard<std::mutex> lock(this->FaceTreeMutex);
    if (!this->FaceTreeBuilt.load(std::memory_order_relaxed))
    {
      this->FaceTree.Build(this->Scratch.FaceBoxes);
      this->FaceTreeBuilt.store(true, std::memory_order_release);
    }
  }
  return this->FaceTree;
}

std::string EmbeddingMesh::Prepare(int nodesPerCell, Id* firstInvalidCell)
{
  this->FaceTreeBuilt.store(false);
  const Id numberOfPoints = static_cast<Id>(this->Points.size() / 3);
  const Id numberOfCells =
    nodesPerCell > 0 ? static_cast<Id>(this->Connectivity.size() / nodesPerCell) : Id(0);
  const double* points = this->Points.data();
  const Id* conn = this->Connectivity.data();

  double lo[3] = { std::numeric_limits<double>::max(), std::numeric_limits<double>::max(),
    std::numeric_limits<double>::max() };
  double hi[3] = { -lo[0], -lo[1], -lo[2] };
  for (Id i = 0; i < numberOfPoints; ++i)
    for (int d = 0; d < 3; ++d)
    {
      lo[d] = std::min(lo[d], points[3 * i + d]);
      hi[d] = std::max(hi[d], points[3 * i + d]);
    }
  const double diagonal = std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) +
    (hi[1] - lo[1]) * (hi[1] - lo[1]) + (hi[2] - lo[2]) * (hi[2] - lo[2]));

  // the cell part reads the nodes of every cell: only with ids in range (the topology
  // reports the problem otherwise)
  bool idsInRange = nodesPerCell == 4 || nodesPerCell == 10;
  for (size_t i = 0; i < this->Connectivity.size() && idsInRange; ++i)
    idsInRange = conn[i] >= 0 && conn[i] < numberOfPoints;
  // The cell data (maps, boxes, barycentric forms, cell grid) and the boundary data (topology,
  // normals, face maps, face tree) do not depend on each other: two tasks, each parallel
  // inside (per cell, per face).
  std::string err;
  if (firstInvalidCell)
    *firstInvalidCell = numberOfCells; // none found (or not looked at: see the error)
  if (!idsInRange)
    err = this->Topology.Build(conn, numberOfCells, nodesPerCell, numberOfPoints); // says why
  else
  {
    ParallelLoop(0, 2, 1, [&](int b, int e) {
      for (int task = b; task < e; ++task)
      {
        if (task == 0)
          err = BuildBoundaryData(
            *this, points, conn, numberOfPoints, numberOfCells, nodesPerCell, diagonal);
        else
          BuildCellData(*this, points, conn, numberOfCells, nodesPerCell, firstInvalidCell);
      }
    });
  }
  if (!err.empty())
  {
    // nothing half-built left behind (the topology has reset itself, or is complete)
    this->Points.clear();
    this->Connectivity.clear();
    this->CellMaps.clear();
    this->CellForms.clear();
    this->CellGrid = BoxGrid();
    this->Diagonal = 0.0;
    return err;
  }
  this->Diagonal = diagonal;
  return std::string();
}

double EmbeddingMesh::FaceLowerBound2(Id f, const double v[3]) const
{
  const double* s = &this->FaceSlabs[6 * f];
  const double h = s[0] * v[0] + s[1] * v[1] + s[2] * v[2] - s[3];
  const double out = h > s[5] ? h - s[5] : (h < s[4] ? s[4] - h : 0.0);
  const double* t = &this->FaceFlat[10 * f];
  if (!(t[9] < std::numeric_limits<double>::infinity()))
    return out * out;
  // in-plane distance from the projection of v to the straight triangle, less the
  // tangential deviation (round-off: relative 1e-12 of the distances kept as slack)
  const double d2 = PointTriangleDistance2(v, t, t + 3, t + 6);
  const double tang = std::sqrt(std::max(0.0, d2 - h * h)) * (1.0 - 1e-12) - t[9];
  return out * out + (tang > 0.0 ? tang * tang : 0.0);
}

void EmbeddingMesh::CellPoint(Id c, const double pc[3], double x[3]) const
{
  const int npc = this->NodesPerCell();
  double N[10];
  if (npc == 10)
    Tet10Shape(pc, N);
  else
    Tet4Shape(pc, N);
  const Id* ids = &this->Connectivity[npc * c];
  x[0] = x[1] = x[2] = 0.0;
  for (int a = 0; a < npc; ++a)
  {
    const double* p = &this->Points[3 * ids[a]];
    x[0] += N[a] * p[0];
    x[1] += N[a] * p[1];
    x[2] += N[a] * p[2];
  }
}
} // namespace hoembed
