// Test helpers for the deformation transfer: embedded surfaces built by construction on a
// generated mesh (v = p + d n holds exactly), and an independent reference of the transfer
// (VTK's own vtkQuadraticTetra / vtkTetra interpolation + the Core normal field).
#ifndef hoembedTransferTestUtilities_h
#define hoembedTransferTestUtilities_h

#include "hoembedTestUtilities.h"
#include "hoembedBoundaryNormals.h"
#include "hoembedMeshFingerprint.h"
#include "hoembedShapeFunctions.h"
#include "hoembedTetMeshTopology.h"

#include "vtkCellArray.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkIdTypeArray.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkQuadraticTetra.h"
#include "vtkSignedCharArray.h"
#include "vtkSmartPointer.h"
#include "vtkStringArray.h"
#include "vtkTetra.h"
#include "vtkUnstructuredGrid.h"

#include <cmath>
#include <functional>
#include <random>
#include <string>
#include <vector>

namespace hoembed_test
{
/// What each surface vertex was built from (the truth the transfer must reproduce).
struct EmbeddedVertex
{
  vtkIdType Cell;
  double PC[3];
  double Distance;
  int LocalFace;      // -1 for interior points
  vtkIdType Boundary; // boundary face index, -1 for interior points
  double UV[2];
};

inline std::string Fingerprint(vtkUnstructuredGrid* mesh)
{
  int npc;
  auto conn = MeshConnectivity(mesh, npc);
  hoembed::MeshFingerprint fp(mesh->GetNumberOfPoints(), mesh->GetNumberOfCells());
  for (vtkIdType c = 0; c < mesh->GetNumberOfCells(); ++c)
    fp.AddCell(mesh->GetCellType(c), &conn[npc * c], npc);
  return fp.Hex();
}

/// Reference position: VTK's own cell interpolation of the mesh's cell at pc.
inline void ReferenceLocation(
  vtkUnstructuredGrid* mesh, vtkIdType cell, const double pc[3], double x[3])
{
  int sub = 0;
  double w[10];
  if (mesh->GetCellType(cell) == VTK_QUADRATIC_TETRA)
  {
    vtkNew<vtkQuadraticTetra> t;
    vtkNew<vtkIdList> ids;
    mesh->GetCellPoints(cell, ids);
    for (int a = 0; a < 10; ++a)
      t->GetPoints()->SetPoint(a, mesh->GetPoint(ids->GetId(a)));
    t->EvaluateLocation(sub, pc, x, w);
  }
  else
  {
    vtkNew<vtkTetra> t;
    vtkNew<vtkIdList> ids;
    mesh->GetCellPoints(cell, ids);
    for (int a = 0; a < 4; ++a)
      t->GetPoints()->SetPoint(a, mesh->GetPoint(ids->GetId(a)));
    t->EvaluateLocation(sub, pc, x, w);
  }
}

/**
 * A surface embedded in `mesh` by construction: on every boundary face, 6 points (a
 * shrunken tri6 lattice, 4 triangles) at distance d = offset(x) along the rest normal
 * field, plus `interior` points inside random cells (d = 0) as vertices. Method
 * "normal-offset"; `truth` receives what each vertex was built from.
 */
inline vtkSmartPointer<vtkPolyData> MakeEmbeddedSurface(vtkUnstructuredGrid* mesh,
  const std::function<double(const double*)>& offset, int interior,
  std::vector<EmbeddedVertex>& truth, bool barycentric = false)
{
  int npc;
  auto conn = MeshConnectivity(mesh, npc);
  hoembed::TetMeshTopology topo;
  topo.Build(conn.data(), mesh->GetNumberOfCells(), npc, mesh->GetNumberOfPoints());
  auto pts = PointsOf(mesh);
  std::vector<double> nodal(pts.size());
  hoembed::ComputeBoundaryNodeNormals(topo, pts.data(), nodal.data());

  auto surface = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  vtkNew<vtkCellArray> polys;
  vtkNew<vtkCellArray> verts;
  truth.clear();
  const double lattice[6][2] = { { 0, 0 }, { 1, 0 }, { 0, 1 }, { 0.5, 0 }, { 0.5, 0.5 },
    { 0, 0.5 } };
  const vtkIdType tris[4][3] = { { 0, 3, 5 }, { 3, 1, 4 }, { 5, 4, 2 }, { 3, 4, 5 } };
  for (vtkIdType b = 0; b < topo.GetNumberOfBoundaryFaces(); ++b)
  {
    const vtkIdType base = points->GetNumberOfPoints();
    for (int k = 0; k < 6; ++k)
    {
      EmbeddedVertex e;
      e.Cell = topo.BoundaryFaceCell[b];
      e.LocalFace = topo.BoundaryFaceLocal[b];
      e.Boundary = b;
      e.UV[0] = 0.1 + 0.8 * lattice[k][0];
      e.UV[1] = 0.1 + 0.8 * lattice[k][1];
      hoembed::TetFaceToTetParametric(e.LocalFace, e.UV, e.PC);
      double p[3], n[3];
      ReferenceLocation(mesh, e.Cell, e.PC, p);
      const double len = hoembed::InterpolateBoundaryNormal(topo, nodal.data(), b, e.UV, n);
      // Where the boundary folds back on itself (a knife edge; the nodal normals there
      // are zero) the smooth normal is short and its direction ill-conditioned: no offset
      // there (the vertex is p itself).
      e.Distance = len > 0.5 ? offset(p) : 0.0;
      double v[3];
      for (int d = 0; d < 3; ++d)
        v[d] = p[d] + e.Distance * n[d];
      if (barycentric)
      {
        // The point itself, p on the face: a barycentric embedding of p (not v).
        e.Distance = 0.0;
        e.LocalFace = -1;
        e.Boundary = -1;
        for (int d = 0; d < 3; ++d)
          v[d] = p[d];
      }
      points->InsertNextPoint(v);
      truth.push_back(e);
    }
    for (const auto& t : tris)
    {
      vtkIdType ids[3] = { base + t[0], base + t[1], base + t[2] };
      polys->InsertNextCell(3, ids);
    }
  }
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  for (int i = 0; i < interior; ++i)
  {
    EmbeddedVertex e;
    e.Cell = static_cast<vtkIdType>(uni(rng) * mesh->GetNumberOfCells()) % mesh->GetNumberOfCells();
    double l[4], s = 0;
    for (double& x : l)
      s += (x = 0.05 + uni(rng));
    e.PC[0] = l[1] / s;
    e.PC[1] = l[2] / s;
    e.PC[2] = l[3] / s;
    e.Distance = 0.0;
    e.LocalFace = -1;
    e.Boundary = -1;
    e.UV[0] = e.UV[1] = 0.0;
    double p[3];
    ReferenceLocation(mesh, e.Cell, e.PC, p);
    vtkIdType id = points->InsertNextPoint(p);
    verts->InsertNextCell(1, &id);
    truth.push_back(e);
  }
  surface->SetPoints(points);
  surface->SetPolys(polys);
  surface->SetVerts(verts);

  const vtkIdType n = points->GetNumberOfPoints();
  vtkNew<vtkIdTypeArray> cellId;
  cellId->SetName("EmbeddingCellId");
  cellId->SetNumberOfTuples(n);
  vtkNew<vtkDoubleArray> pcoords;
  pcoords->SetName("EmbeddingParametricCoords");
  pcoords->SetNumberOfComponents(3);
  pcoords->SetNumberOfTuples(n);
  vtkNew<vtkDoubleArray> dist;
  dist->SetName("EmbeddingDistance");
  dist->SetNumberOfTuples(n);
  vtkNew<vtkDoubleArray> residual;
  residual->SetName("EmbeddingResidual");
  residual->SetNumberOfTuples(n);
  vtkNew<vtkSignedCharArray> face;
  face->SetName("EmbeddingFace");
  face->SetNumberOfTuples(n);
  for (vtkIdType i = 0; i < n; ++i)
  {
    const auto& e = truth[i];
    cellId->SetValue(i, e.Cell);
    pcoords->SetTuple(i, e.PC);
    dist->SetValue(i, e.Distance);
    residual->SetValue(i, 0.0);
    face->SetValue(i, static_cast<signed char>(e.Distance != 0.0 ? e.LocalFace : -1));
  }
  surface->GetPointData()->AddArray(cellId);
  surface->GetPointData()->AddArray(pcoords);
  surface->GetPointData()->AddArray(dist);
  surface->GetPointData()->AddArray(residual);
  surface->GetPointData()->AddArray(face);
  vtkNew<vtkStringArray> method;
  method->SetName("EmbeddingMethod");
  method->InsertNextValue(barycentric ? "barycentric" : "normal-offset");
  vtkNew<vtkStringArray> fp;
  fp->SetName("EmbeddingMeshFingerprint");
  fp->InsertNextValue(Fingerprint(mesh));
  surface->GetFieldData()->AddArray(method);
  surface->GetFieldData()->AddArray(fp);
  return surface;
}

/**
 * Reference transfer, independent of the filter's kernels: VTK's cell interpolation for p'
 * and the Core normal field (from `nodal`, the deformed nodal normals, or recomputed when
 * empty) at the known face coordinates for n'.
 */
inline std::vector<double> ReferenceTransfer(vtkUnstructuredGrid* deformed,
  const std::vector<EmbeddedVertex>& truth, std::vector<double> nodal = std::vector<double>())
{
  int npc;
  auto conn = MeshConnectivity(deformed, npc);
  hoembed::TetMeshTopology topo;
  topo.Build(conn.data(), deformed->GetNumberOfCells(), npc, deformed->GetNumberOfPoints());
  auto pts = PointsOf(deformed);
  if (nodal.empty())
  {
    nodal.resize(pts.size());
    hoembed::ComputeBoundaryNodeNormals(topo, pts.data(), nodal.data());
  }
  std::vector<double> out(3 * truth.size());
  for (size_t i = 0; i < truth.size(); ++i)
  {
    const auto& e = truth[i];
    double p[3], n[3] = { 0, 0, 0 };
    ReferenceLocation(deformed, e.Cell, e.PC, p);
    if (e.Boundary >= 0 && e.Distance != 0.0)
      hoembed::InterpolateBoundaryNormal(topo, nodal.data(), e.Boundary, e.UV, n);
    for (int d = 0; d < 3; ++d)
      out[3 * i + d] = p[d] + e.Distance * n[d];
  }
  return out;
}

/// A copy of `mesh` (sharing its cells) with every point moved by `map`.
inline vtkSmartPointer<vtkUnstructuredGrid> Deformed(
  vtkUnstructuredGrid* mesh, const std::function<void(const double*, double*)>& map)
{
  auto out = vtkSmartPointer<vtkUnstructuredGrid>::New();
  out->CopyStructure(mesh);
  vtkNew<vtkPoints> pts;
  pts->SetDataTypeToDouble();
  pts->SetNumberOfPoints(mesh->GetNumberOfPoints());
  for (vtkIdType i = 0; i < mesh->GetNumberOfPoints(); ++i)
  {
    double x[3], y[3];
    mesh->GetPoint(i, x);
    map(x, y);
    pts->SetPoint(i, y);
  }
  out->SetPoints(pts);
  return out;
}

inline double Diagonal(vtkDataSet* ds)
{
  return ds->GetLength();
}
} // namespace hoembed_test

#endif
