// vtkEmbeddingCoordinatesFilter (its kernels have their own tests: TestClosestPoint,
// TestTetBarycentric, TestBoxGrid, TestEmbeddingMesh) against references nobody here wrote:
// dense sampling of curved elements, exhaustive (brute-force) search over every boundary
// face and every cell from several starts, VTK's own vtkQuadraticTetra / vtkTetra
// interpolation for the reconstruction v = p + d n, and VTK's XML writer/reader.
#include "hoembedEmbeddingTestUtilities.h"
#include "hoembedQuadraticMapTestUtilities.h"

#include "hoembedBoundaryNormals.h"
#include "hoembedClosestPoint.h"
#include "hoembedElementGeometry.h"
#include "hoembedEmbeddingFlood.h"
#include "hoembedBoxGrid.h"
#include "hoembedEmbeddingSearch.h"
#include "hoembedShapeFunctions.h"
#include "hoembedTetBarycentric.h"
#include "vtkEmbeddingCoordinatesFilter.h"
#include "vtkTet10Mesher.h"

#include "vtkAppendPolyData.h"
#include "vtkCallbackCommand.h"
#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkCommand.h"
#include "vtkDoubleArray.h"
#include "vtkExecutive.h"
#include "vtkFieldData.h"
#include "vtkIdTypeArray.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkOBJReader.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkQuadraticTetra.h"
#include "vtkSMPTools.h"
#include "vtkSignedCharArray.h"
#include "vtkSphereSource.h"
#include "vtkStringArray.h"
#include "vtkTetra.h"
#include "vtkUnsignedCharArray.h"
#include "vtkTransform.h"
#include "vtkTransformPolyDataFilter.h"
#include "vtkXMLPolyDataReader.h"
#include "vtkXMLPolyDataWriter.h"

#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>

using hoembed_test::MakeBoxTetMesh;

namespace
{
// Bends and bulges the box [0,2]x[0,1]x[0,1] (keeps elements valid).
void CurveMap(double x[3])
{
  const double X = x[0], Y = x[1], Z = x[2];
  x[0] = X + 0.05 * std::sin(M_PI * Y);
  x[1] = Y + 0.12 * std::sin(0.5 * M_PI * X) + 0.04 * std::sin(M_PI * Z);
  x[2] = Z + 0.08 * std::cos(M_PI * X) * Y;
}

struct ErrorCatcher
{
  std::string Text;
  int Count = 0;
  static void Callback(vtkObject*, unsigned long, void* cd, void* calldata)
  {
    auto* self = static_cast<ErrorCatcher*>(cd);
    ++self->Count;
    if (calldata)
      self->Text += static_cast<const char*>(calldata);
  }
};

// Sphere surfaces: one through the curved beam (inside and outside points), one far away.
vtkSmartPointer<vtkPolyData> MakeSurface(bool withFarComponent, bool withIsolated)
{
  vtkNew<vtkSphereSource> s1;
  s1->SetThetaResolution(48);
  s1->SetPhiResolution(36);
  vtkNew<vtkTransform> t1;
  t1->Translate(1.0, 0.55, 0.5);
  t1->Scale(2.3, 1.05, 1.0);
  vtkNew<vtkTransformPolyDataFilter> f1;
  f1->SetInputConnection(s1->GetOutputPort());
  f1->SetTransform(t1);
  vtkNew<vtkAppendPolyData> app;
  app->AddInputConnection(f1->GetOutputPort());
  vtkNew<vtkSphereSource> s2;
  s2->SetThetaResolution(16);
  s2->SetPhiResolution(12);
  s2->SetCenter(1.0, 0.5, 0.5);
  s2->SetRadius(0.3); // fully inside the beam
  app->AddInputConnection(s2->GetOutputPort());
  vtkNew<vtkSphereSource> s3;
  s3->SetThetaResolution(12);
  s3->SetPhiResolution(10);
  s3->SetCenter(30.0, -20.0, 12.0);
  s3->SetRadius(3.0);
  if (withFarComponent)
    app->AddInputConnection(s3->GetOutputPort());
  app->Update();
  auto out = vtkSmartPointer<vtkPolyData>::New();
  out->DeepCopy(app->GetOutput());
  out->GetPointData()->Initialize(); // the isolated points below have no normals
  // duplicate vertices (same coordinates, own triangle) and a degenerate triangle
  {
    const vtkIdType n = out->GetNumberOfPoints();
    double p[3];
    vtkIdType dup[3];
    for (int k = 0; k < 3; ++k)
    {
      out->GetPoint(100 + 7 * k, p);
      dup[k] = out->GetPoints()->InsertNextPoint(p);
    }
    out->GetPolys()->InsertNextCell(3, dup);
    const vtkIdType degenerate[3] = { 5, 5, n - 1 };
    out->GetPolys()->InsertNextCell(3, degenerate);
  }
  if (withIsolated)
  {
    // points in no triangle: two inside, two outside, one on a boundary corner
    const double extra[5][3] = { { 0.5, 0.5, 0.5 }, { 1.5, 0.4, 0.6 }, { -0.7, 0.2, 0.3 },
      { 1.0, 3.0, -2.0 }, { 0.0, 0.0, 0.0 } };
    for (const auto& e : extra)
    {
      double p[3] = { e[0], e[1], e[2] };
      CurveMap(p);
      out->GetPoints()->InsertNextPoint(p);
    }
  }
  return out;
}

vtkSmartPointer<vtkPolyData> RunFilter(
  vtkPolyData* surface, vtkUnstructuredGrid* mesh, int method, ErrorCatcher* errors = nullptr)
{
  vtkNew<vtkCallbackCommand> cb;
  ErrorCatcher local;
  cb->SetClientData(errors ? errors : &local);
  cb->SetCallback(ErrorCatcher::Callback);
  return RunEmbeddingFilter(surface, mesh, method, cb);
}

// The filter's output with `partitions` flood partitions (normal-offset).
vtkSmartPointer<vtkPolyData> RunFilterWithPartitions(
  vtkPolyData* surface, vtkUnstructuredGrid* mesh, int partitions)
{
  vtkNew<vtkEmbeddingCoordinatesFilter> f;
  f->SetInputData(0, surface);
  f->SetMeshData(mesh);
  f->SetNumberOfPartitions(partitions);
  f->Update();
  auto out = vtkSmartPointer<vtkPolyData>::New();
  out->ShallowCopy(f->GetOutput());
  return out;
}

// How many values of point-data array `name` differ by more than `tol` (or are NaN)
// between two outputs; -1 when either lacks the array.
int CountDiffering(vtkPolyData* x, vtkPolyData* y, const char* name, double tol)
{
  auto* a = vtkDoubleArray::SafeDownCast(x->GetPointData()->GetArray(name));
  auto* b = vtkDoubleArray::SafeDownCast(y->GetPointData()->GetArray(name));
  if (!a || !b)
    return -1;
  int differ = 0;
  for (vtkIdType i = 0; i < a->GetNumberOfTuples(); ++i)
    differ += !(std::fabs(a->GetValue(i) - b->GetValue(i)) <= tol);
  return differ;
}

// Checks one embedding against brute force and VTK's interpolation of the mesh.
void CheckEmbedding(const char* label, vtkPolyData* surface, vtkUnstructuredGrid* grid,
  vtkPolyData* out, int method, bool checkAllResiduals, vtkIdType stride = 1)
{
  const int npc = grid->GetCellType(0) == VTK_QUADRATIC_TETRA ? 10 : 4;
  hoembed::EmbeddingMesh em;
  std::vector<double> pts(3 * grid->GetNumberOfPoints());
  for (vtkIdType i = 0; i < grid->GetNumberOfPoints(); ++i)
    grid->GetPoint(i, &pts[3 * i]);
  std::vector<hoembed::EmbeddingMesh::Id> conn;
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c)
  {
    grid->GetCellPoints(c, ids);
    for (int a = 0; a < npc; ++a)
      conn.push_back(ids->GetId(a));
  }
  const std::string err =
    em.Build(pts.data(), grid->GetNumberOfPoints(), conn.data(), grid->GetNumberOfCells(), npc);
  HOEMBED_CHECK(err.empty(), "%s: mesh build: %s", label, err.c_str());
  const double diag = em.Diagonal;

  vtkPointData* pd = out->GetPointData();
  auto* cellId = vtkIdTypeArray::SafeDownCast(pd->GetArray("EmbeddingCellId"));
  auto* pc = vtkDoubleArray::SafeDownCast(pd->GetArray("EmbeddingParametricCoords"));
  auto* dist = vtkDoubleArray::SafeDownCast(pd->GetArray("EmbeddingDistance"));
  auto* res = vtkDoubleArray::SafeDownCast(pd->GetArray("EmbeddingResidual"));
  auto* face = vtkSignedCharArray::SafeDownCast(pd->GetArray("EmbeddingFace"));
  auto* closest = vtkDoubleArray::SafeDownCast(pd->GetArray("EmbeddingClosestDistance"));
  auto* iters = vtkIntArray::SafeDownCast(pd->GetArray("EmbeddingIterations"));
  auto* visited = vtkIntArray::SafeDownCast(pd->GetArray("EmbeddingElementsVisited"));
  // 1 where v = p + d n has no solution with a near foot: p is then the closest point and
  // v = p + J q (EmbeddingFallbackOffset)
  auto* fallback = vtkUnsignedCharArray::SafeDownCast(pd->GetArray("EmbeddingFallback"));
  HOEMBED_CHECK(cellId && pc && dist && res && face && closest && iters && visited,
    "%s: missing output arrays", label);
  if (!(cellId && pc && dist && res && face && closest && iters && visited))
    return;
  auto* m = vtkStringArray::SafeDownCast(out->GetFieldData()->GetAbstractArray("EmbeddingMethod"));
  auto* fp =
    vtkStringArray::SafeDownCast(out->GetFieldData()->GetAbstractArray("EmbeddingMeshFingerprint"));
  HOEMBED_CHECK(m && m->GetValue(0) == (method ? "barycentric" : "normal-offset"),
    "%s: EmbeddingMethod field data", label);
  HOEMBED_CHECK(fp && fp->GetValue(0).size() == 16, "%s: fingerprint", label);

  vtkNew<vtkQuadraticTetra> qt;
  vtkNew<vtkTetra> t4;
  vtkCell* cell = npc == 10 ? static_cast<vtkCell*>(qt) : static_cast<vtkCell*>(t4);
  int badDist = 0, badRes = 0, badFace = 0, badPc = 0, nInside = 0, nOutside = 0;
  double maxDistErr = 0, maxRes = 0;
  int checked = 0;
  for (vtkIdType i = 0; i < surface->GetNumberOfPoints(); i += stride)
  {
    ++checked;
    double v[3];
    surface->GetPoint(i, v);
    const double ref = hoembed::BruteForceDistance(em, v);
    const double e = std::fabs(closest->GetValue(i) - ref);
    maxDistErr = std::max(maxDistErr, e / diag);
    if (e > 1e-8 * diag)
    {
      if (badDist < 5)
        std::fprintf(stderr, "%s: vertex %lld distance %.17g, brute force %.17g\n", label,
          static_cast<long long>(i), closest->GetValue(i), ref);
      ++badDist;
    }
    (ref == 0.0 ? nInside : nOutside)++;
    // reconstruction with VTK's own cell interpolation and the shared normal field
    const vtkIdType c = cellId->GetValue(i);
    grid->GetCellPoints(c, ids);
    for (int a = 0; a < npc; ++a)
    {
      cell->GetPoints()->SetPoint(a, grid->GetPoint(ids->GetId(a)));
      cell->GetPointIds()->SetId(a, a);
    }
    double r[3], p[3], w[10];
    pc->GetTypedTuple(i, r);
    int sub;
    cell->EvaluateLocation(sub, r, p, w);
    const int fc = face->GetValue(i);
    double n[3] = { 0, 0, 0 };
    const double d = dist->GetValue(i);
    if (fc >= 0)
    {
      const hoembed::EmbeddingMesh::Id bf = em.Topology.CellBoundaryFace[4 * c + fc];
      const double L[4] = { 1 - r[0] - r[1] - r[2], r[0], r[1], r[2] };
      const double uv[2] = { L[hoembed::TetFaceNodes[fc][1]], L[hoembed::TetFaceNodes[fc][2]] };
      const double onFace = L[hoembed::TetFaceOpposite[fc]];
      if (bf < 0 || std::fabs(onFace) > 1e-12)
        ++badFace;
      else
        hoembed::InterpolateBoundaryNormal(em.Topology, em.NodalNormals.data(), bf, uv, n);
    }
    if ((fc < 0) != (d == 0.0) || (method == 1 && fc != -1))
      ++badFace;
    if (method == 0 &&
      (r[0] < -1e-12 || r[1] < -1e-12 || r[2] < -1e-12 || r[0] + r[1] + r[2] > 1 + 1e-12))
      ++badPc;
    double q[3];
    for (int k = 0; k < 3; ++k)
      q[k] = v[k] - p[k] - d * n[k];
    double rr = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]);
    if (method == 0 && fallback && fallback->GetValue(i) != 0)
    {
      // a fallback point's p, by VTK's interpolation, is its closest point: |v - p| is
      // the brute-force distance (to its tolerance), and the driver's p + J q residual
      // must hold
      rr = std::fabs(rr - ref) <= 1e-8 * diag ? res->GetValue(i) : std::fabs(rr - ref);
    }
    const bool mustHold = checkAllResiduals || ref <= 0.5;
    if (mustHold)
    {
      maxRes = std::max(maxRes, rr / diag);
      if (rr > 1e-10 * diag || std::fabs(rr - res->GetValue(i)) > 1e-10 * diag)
        ++badRes;
    }
  }
  double maxAll = 0.0;
  for (vtkIdType i = 0; i < res->GetNumberOfTuples(); ++i)
    maxAll = std::max(maxAll, res->GetValue(i));
  if (checkAllResiduals)
    HOEMBED_CHECK(
      maxAll <= 1e-10 * diag, "%s: EmbeddingResidual max %.3g diag", label, maxAll / diag);
  std::printf("%s: %d of %lld vertices checked (%d inside, %d outside), max |distance - brute "
              "force| = %.3g diag, max residual = %.3g diag (all vertices: %.3g)\n",
    label, checked, static_cast<long long>(surface->GetNumberOfPoints()), nInside, nOutside,
    maxDistErr, maxRes, maxAll / diag);
  HOEMBED_CHECK(badDist == 0, "%s: %d vertices differ from brute force", label, badDist);
  HOEMBED_CHECK(
    badRes == 0, "%s: %d vertices with reconstruction residual > 1e-10 diag", label, badRes);
  HOEMBED_CHECK(badFace == 0, "%s: %d vertices with inconsistent EmbeddingFace", label, badFace);
  HOEMBED_CHECK(badPc == 0, "%s: %d parametric coordinates outside the cell", label, badPc);
  HOEMBED_CHECK(nInside > 0 && nOutside > 0, "%s: want both inside and outside points", label);
}

void TestErrors(vtkPolyData* surface, vtkUnstructuredGrid* grid)
{
  auto expectError = [&](const char* what, vtkPolyData* s, vtkUnstructuredGrid* g,
                       const char* needle) {
    ErrorCatcher ec;
    auto out = RunFilter(s, g, 0, &ec);
    HOEMBED_CHECK(ec.Count > 0, "%s: no error reported", what);
    HOEMBED_CHECK(ec.Text.find(needle) != std::string::npos, "%s: message lacks '%s': %s", what,
      needle, ec.Text.c_str());
    HOEMBED_CHECK(out->GetNumberOfPoints() == 0, "%s: output not empty", what);
  };
  vtkNew<vtkPolyData> empty;
  expectError("empty surface", empty, grid, "surface (input port 0) is empty");
  vtkNew<vtkUnstructuredGrid> emptyGrid;
  expectError("empty mesh", surface, emptyGrid, "FE mesh (input port 1) is empty");

  vtkNew<vtkPolyData> nanSurface;
  nanSurface->DeepCopy(surface);
  nanSurface->GetPoints()->SetPoint(3, std::nan(""), 0, 0);
  expectError("NaN surface", nanSurface, grid, "non-finite");
  vtkNew<vtkUnstructuredGrid> nanGrid;
  nanGrid->DeepCopy(grid);
  nanGrid->GetPoints()->SetPoint(1, 0, std::nan(""), 0);
  expectError("NaN mesh", surface, nanGrid, "non-finite");

  // inverted element: swap two corners of cell 0
  vtkNew<vtkUnstructuredGrid> inv;
  inv->DeepCopy(grid);
  {
    vtkNew<vtkIdList> ids;
    inv->GetCellPoints(0, ids);
    std::vector<vtkIdType> v(ids->begin(), ids->end());
    std::swap(v[1], v[2]);
    if (v.size() == 10)
    {
      std::swap(v[4], v[6]); // edges 01 <-> 20 follow the swap 1 <-> 2
      std::swap(v[8], v[9]);
    }
    inv->ReplaceCell(0, static_cast<int>(v.size()), v.data());
  }
  expectError("inverted element", surface, inv, "inverted or degenerate");

  // degenerate (flat) element: collapse a corner onto another one's position
  vtkNew<vtkUnstructuredGrid> flat;
  flat->DeepCopy(grid);
  {
    vtkNew<vtkIdList> ids;
    flat->GetCellPoints(0, ids);
    vtkNew<vtkPoints> p;
    p->DeepCopy(flat->GetPoints());
    double a[3], b[3], c[3];
    p->GetPoint(ids->GetId(0), a);
    p->GetPoint(ids->GetId(1), b);
    p->GetPoint(ids->GetId(2), c);
    // put node 3 into the plane of 0, 1, 2
    p->SetPoint(
      ids->GetId(3), (a[0] + b[0] + c[0]) / 3, (a[1] + b[1] + c[1]) / 3, (a[2] + b[2] + c[2]) / 3);
    flat->SetPoints(p);
  }
  expectError("degenerate element", surface, flat, "inverted or degenerate");

  // a cell type other than tet4/tet10
  vtkNew<vtkUnstructuredGrid> hex;
  {
    vtkNew<vtkPoints> p;
    for (int k = 0; k < 8; ++k)
      p->InsertNextPoint(k & 1, (k >> 1) & 1, (k >> 2) & 1);
    hex->SetPoints(p);
    vtkIdType ids[8] = { 0, 1, 3, 2, 4, 5, 7, 6 };
    hex->InsertNextCell(VTK_HEXAHEDRON, 8, ids);
  }
  expectError("hexahedron", surface, hex, "only VTK_TETRA");
  // mixed tet4 and tet10
  vtkNew<vtkUnstructuredGrid> mixed;
  mixed->SetPoints(grid->GetPoints());
  mixed->Allocate(grid->GetNumberOfCells() + 1);
  {
    vtkNew<vtkIdList> ids;
    for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c)
    {
      grid->GetCellPoints(c, ids);
      mixed->InsertNextCell(grid->GetCellType(c), ids);
    }
    grid->GetCellPoints(0, ids);
    // a cell of the other type on the corners of cell 0 (the mid nodes: any nodes)
    vtkIdType ten[10] = { ids->GetId(0), ids->GetId(1), ids->GetId(2), ids->GetId(3), 4, 5, 6, 7, 8,
      9 };
    const bool is10 = grid->GetCellType(0) == VTK_QUADRATIC_TETRA;
    mixed->InsertNextCell(is10 ? VTK_TETRA : VTK_QUADRATIC_TETRA, is10 ? 4 : 10, ten);
  }
  expectError("mixed cells", surface, mixed, "mixes cell types");
}

void TestSaveLoad(vtkPolyData* out)
{
  const std::string file = "TestEmbeddingCoordinatesFilter.vtp";
  vtkNew<vtkXMLPolyDataWriter> w;
  w->SetFileName(file.c_str());
  w->SetInputData(out);
  HOEMBED_CHECK(w->Write() == 1, "writing %s", file.c_str());
  vtkNew<vtkXMLPolyDataReader> r;
  r->SetFileName(file.c_str());
  r->Update();
  vtkPolyData* back = r->GetOutput();
  int diff = 0;
  for (const char* name : { "EmbeddingCellId", "EmbeddingParametricCoords", "EmbeddingDistance",
         "EmbeddingResidual", "EmbeddingFace" })
  {
    vtkDataArray* a = out->GetPointData()->GetArray(name);
    vtkDataArray* b = back->GetPointData()->GetArray(name);
    if (!a || !b || a->GetDataType() != b->GetDataType() ||
      a->GetNumberOfTuples() != b->GetNumberOfTuples())
    {
      ++diff;
      continue;
    }
    for (vtkIdType i = 0; i < a->GetNumberOfTuples(); ++i)
      for (int c = 0; c < a->GetNumberOfComponents(); ++c)
        if (a->GetComponent(i, c) != b->GetComponent(i, c))
          ++diff;
  }
  auto* fa =
    vtkStringArray::SafeDownCast(out->GetFieldData()->GetAbstractArray("EmbeddingMeshFingerprint"));
  auto* fb = vtkStringArray::SafeDownCast(
    back->GetFieldData()->GetAbstractArray("EmbeddingMeshFingerprint"));
  HOEMBED_CHECK(fa && fb && fa->GetValue(0) == fb->GetValue(0), "fingerprint lost in .vtp");
  HOEMBED_CHECK(diff == 0, "%d values differ after .vtp round trip", diff);
  std::remove(file.c_str());
}
// Regression: a curved cell that pokes through a boundary face of another part of the
// mesh (as TetGen -Y meshes of thin regions can have after curving). Two unit cubes
// (6 tet10 each) with a gap of 0.1 along x; the mid-edge node of the face diagonal of the
// left cube's face x = 1 is pushed to x = 1.2, so its bulge crosses the right cube's face
// x = 1.1. Points in the gap under the bulge lie inside a left cell but on the outer side
// of their closest boundary face (the right cube's, 0.02-0.05 away): the pseudo-normal
// alone calls them outside. Brute force and VTK's own vtkQuadraticTetra decide.
void TestCrossingBoundary()
{
  auto a = MakeBoxTetMesh(1, 1, 1, 1.0, 1.0, 1.0, 2, [](double x[3]) {
    if (std::fabs(x[0] - 1.0) < 1e-12 && std::fabs(x[1] - 0.5) < 1e-12 &&
      std::fabs(x[2] - 0.5) < 1e-12)
      x[0] = 1.2;
  });
  auto b = MakeBoxTetMesh(1, 1, 1, 1.0, 1.0, 1.0, 2, [](double x[3]) { x[0] += 1.1; });
  vtkNew<vtkUnstructuredGrid> grid;
  vtkNew<vtkPoints> pts;
  pts->SetDataTypeToDouble();
  for (vtkUnstructuredGrid* g : { a.GetPointer(), b.GetPointer() })
  {
    const vtkIdType off = pts->GetNumberOfPoints();
    for (vtkIdType i = 0; i < g->GetNumberOfPoints(); ++i)
      pts->InsertNextPoint(g->GetPoint(i));
    vtkNew<vtkIdList> ids;
    for (vtkIdType c = 0; c < g->GetNumberOfCells(); ++c)
    {
      g->GetCellPoints(c, ids);
      for (vtkIdType k = 0; k < ids->GetNumberOfIds(); ++k)
        ids->SetId(k, ids->GetId(k) + off);
      grid->InsertNextCell(VTK_QUADRATIC_TETRA, ids);
    }
  }
  grid->SetPoints(pts);
  // a small triangulated patch in the gap (x in [1.02, 1.09]) around the bulge, plus
  // points inside the bulge beyond x = 1.1 (inside both cubes) and far away
  vtkNew<vtkPolyData> surface;
  vtkNew<vtkPoints> sp;
  sp->SetDataTypeToDouble();
  vtkNew<vtkCellArray> tris;
  const int n = 9;
  for (int j = 0; j < n; ++j)
    for (int k = 0; k < n; ++k)
    {
      const double y = 0.3 + 0.4 * j / (n - 1), z = 0.3 + 0.4 * k / (n - 1);
      sp->InsertNextPoint(1.02 + 0.07 * std::fabs(std::sin(3.0 * j + 5.0 * k)), y, z);
      if (j > 0 && k > 0)
      {
        const vtkIdType p00 = (j - 1) * n + k - 1, p01 = (j - 1) * n + k, p10 = j * n + k - 1,
                        p11 = j * n + k;
        const vtkIdType t1[3] = { p00, p10, p11 }, t2[3] = { p00, p11, p01 };
        tris->InsertNextCell(3, t1);
        tris->InsertNextCell(3, t2);
      }
    }
  surface->SetPoints(sp);
  surface->SetPolys(tris);
  // the same points alone (no triangles: no neighbour starts, so no point is located
  // from an inside neighbour's cell): each gap point's closest boundary point lies on
  // the right cube's face x = 1.1 with the point on its outer side, the case the
  // outside proof of the search (OutsideByFace) must hand over to the cell test
  vtkNew<vtkPolyData> alone;
  alone->SetPoints(sp);
  for (const bool isolated : { false, true })
  {
    vtkPolyData* input = isolated ? alone.GetPointer() : surface.GetPointer();
    auto out = RunFilter(input, grid, 0);
    HOEMBED_CHECK(
      out->GetNumberOfPoints() == surface->GetNumberOfPoints(), "crossing: output size");
    // the case must actually occur: gap points clearly inside a left cell (VTK's own test)
    vtkNew<vtkQuadraticTetra> qt;
    int insideVtk = 0;
    auto* closest =
      vtkDoubleArray::SafeDownCast(out->GetPointData()->GetArray("EmbeddingClosestDistance"));
    int missed = 0;
    for (vtkIdType i = 0; i < surface->GetNumberOfPoints(); ++i)
    {
      double v[3];
      surface->GetPoint(i, v);
      bool in = false;
      for (vtkIdType c = 0; c < a->GetNumberOfCells() && !in; ++c)
      {
        vtkNew<vtkIdList> ids;
        grid->GetCellPoints(c, ids);
        for (int k = 0; k < 10; ++k)
        {
          qt->GetPoints()->SetPoint(k, grid->GetPoint(ids->GetId(k)));
          qt->GetPointIds()->SetId(k, k);
        }
        double cp[3], pc[3], d2, w[10];
        int sub;
        // clearly inside (VTK accepts parametric coordinates up to 1e-3 outside)
        in = qt->EvaluatePosition(v, cp, sub, pc, d2, w) == 1 && pc[0] > 1e-3 && pc[1] > 1e-3 &&
          pc[2] > 1e-3 && pc[0] + pc[1] + pc[2] < 1.0 - 1e-3;
      }
      if (in)
      {
        ++insideVtk;
        if (!closest || closest->GetValue(i) != 0.0)
          ++missed;
      }
    }
    HOEMBED_CHECK(
      insideVtk >= 5, "crossing: only %d gap points inside the bulge (test setup)", insideVtk);
    HOEMBED_CHECK(missed == 0, "crossing: %d of %d points inside a curved cell reported outside",
      missed, insideVtk);
    std::printf("crossing boundary%s: %d of %lld gap points inside the bulge\n",
      isolated ? " (isolated points)" : "", insideVtk,
      static_cast<long long>(surface->GetNumberOfPoints()));
    CheckEmbedding(isolated ? "crossing boundary, isolated points" : "crossing boundary", input,
      grid, out, 0, true);
  }
}

// Real surfaces on vtkTet10Mesher meshes of ~1000 elements, tet10 and tet4: brute force
// on every k-th vertex (about 1500 per surface), residuals on all of them.
void TestRealMeshes(const std::string& dir)
{
  for (const char* name : { "bunny_watertight", "fertility", "rocker-arm" })
  {
    const std::string file = dir + "/" + name + ".obj";
    struct stat st;
    if (stat(file.c_str(), &st) != 0)
      continue;
    vtkNew<vtkOBJReader> reader;
    reader->SetFileName(file.c_str());
    reader->Update();
    vtkNew<vtkPolyData> surface;
    surface->SetPoints(reader->GetOutput()->GetPoints());
    surface->SetPolys(reader->GetOutput()->GetPolys());
    // tet10 and tet4 with the mesher's default; on fertility also tet10 with
    // PreserveBoundary on and off explicitly (its surface vertex 438 lies inside a curved
    // cell that pokes through another boundary face: see TestCrossingBoundary)
    const bool fert = std::string(name) == "fertility";
    for (int config = 0; config < (fert ? 4 : 2); ++config)
    {
      const int order = config == 1 ? 1 : 2;
      vtkNew<vtkTet10Mesher> mesher;
      mesher->SetInputData(surface);
      mesher->SetTargetNumberOfElements(1000);
      mesher->SetElementOrder(order);
      if (config >= 2)
        mesher->SetPreserveBoundary(config == 3);
      mesher->Update();
      vtkUnstructuredGrid* grid = mesher->GetOutput();
      HOEMBED_CHECK(grid->GetNumberOfCells() > 500, "%s: mesher gave %lld cells", name,
        static_cast<long long>(grid->GetNumberOfCells()));
      if (grid->GetNumberOfCells() == 0)
        continue;
      auto out = RunFilter(surface, grid, 0);
      const vtkIdType stride = std::max<vtkIdType>(1, surface->GetNumberOfPoints() / 700);
      const std::string label = std::string(name) + (order == 2 ? " tet10" : " tet4") +
        (config == 2 ? " PreserveBoundary off" : (config == 3 ? " PreserveBoundary on" : ""));
      CheckEmbedding(label.c_str(), surface, grid, out, 0, true, stride);
      if (config == 0)
      {
        // Other flood partitions give other starting points, not other results: where
        // v = p + d n has several solutions (on bunny, vertex 20749 beyond the normal
        // field's focal distance: d 2.836 or 2.305), the correction starts from the
        // lowest-numbered face at the closest point, whichever face the search named.
        const int differ = CountDiffering(out, RunFilterWithPartitions(surface, grid, 4),
          "EmbeddingDistance", 1e-9 * grid->GetLength());
        HOEMBED_CHECK(differ == 0,
          "%s: 4 flood partitions instead of the default change %d normal-offset distances",
          label.c_str(), differ);
      }
    }
  }
}
} // namespace

// EmbedSurface with and without a workspace, with and without the vertex order, one
// workspace reused across two meshes, and in its two steps: the same results, and the
// filter's distances.
void TestEmbedSurfaceWorkspace(vtkPolyData* surface, vtkUnstructuredGrid* grid10,
  vtkUnstructuredGrid* grid4, vtkPolyData* filterOut)
{
  using Id = hoembed::EmbeddingMesh::Id;
  auto prepare = [](vtkUnstructuredGrid* grid, hoembed::EmbeddingMesh& em) {
    const int npc = grid->GetCellType(0) == VTK_QUADRATIC_TETRA ? 10 : 4;
    std::vector<double> pts(3 * grid->GetNumberOfPoints());
    for (vtkIdType i = 0; i < grid->GetNumberOfPoints(); ++i)
      grid->GetPoint(i, &pts[3 * i]);
    std::vector<Id> conn;
    vtkNew<vtkIdList> ids;
    for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c)
    {
      grid->GetCellPoints(c, ids);
      for (int a = 0; a < npc; ++a)
        conn.push_back(ids->GetId(a));
    }
    return em.Build(std::move(pts), std::move(conn), npc);
  };
  hoembed::EmbeddingMesh m10, m4;
  HOEMBED_CHECK(prepare(grid10, m10).empty() && prepare(grid4, m4).empty(), "mesh build");
  const Id n = surface->GetNumberOfPoints();
  std::vector<double> v(3 * n);
  for (Id i = 0; i < n; ++i)
    surface->GetPoint(i, &v[3 * i]);
  std::vector<Id> tris;
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < surface->GetPolys()->GetNumberOfCells(); ++c)
  {
    surface->GetPolys()->GetCellAtId(c, ids);
    for (vtkIdType k = 1; k + 1 < ids->GetNumberOfIds(); ++k)
      tris.insert(tris.end(), { ids->GetId(0), ids->GetId(k), ids->GetId(k + 1) });
  }
  const int method = hoembed::EMBED_NORMAL_OFFSET;
  std::vector<hoembed::VertexEmbedding> plain, reused, ordered, other;
  hoembed::EmbedSurface(m10, method, v.data(), n, tris, plain);
  hoembed::EmbedWorkspace ws;
  hoembed::EmbedSurface(m4, method, v.data(), n, tris, other, 0, {}, nullptr, nullptr, &ws);
  hoembed::EmbedSurface(m10, method, v.data(), n, tris, reused, 0, {}, nullptr, nullptr, &ws);
  std::vector<Id> order;
  hoembed::EmbedSurface(m10, method, v.data(), n, tris, ordered, 0, {}, nullptr, &order, &ws);
  HOEMBED_CHECK(ws.GetCapacityInBytes() > 0, "workspace kept nothing");
  auto same = [](const hoembed::VertexEmbedding& a, const hoembed::VertexEmbedding& b) {
    return a.Cell == b.Cell && a.PC[0] == b.PC[0] && a.PC[1] == b.PC[1] && a.PC[2] == b.PC[2] &&
      a.Distance == b.Distance && a.ClosestDistance == b.ClosestDistance && a.Face == b.Face &&
      a.Inside == b.Inside;
  };
  auto* closest =
    vtkDoubleArray::SafeDownCast(filterOut->GetPointData()->GetArray("EmbeddingClosestDistance"));
  int differ = 0, differOrdered = 0, differFilter = 0, differMesh = 0;
  HOEMBED_CHECK(plain.size() == size_t(n) && reused.size() == size_t(n) &&
      ordered.size() == size_t(n) && order.size() == size_t(n),
    "result sizes");
  for (Id k = 0; k < n && order.size() == size_t(n); ++k)
  {
    differ += !same(plain[k], reused[k]);
    differOrdered += !same(plain[order[k]], ordered[k]);
    differFilter += closest && closest->GetValue(k) != plain[k].ClosestDistance;
    differMesh += other[k].ClosestDistance != plain[k].ClosestDistance;
  }
  HOEMBED_CHECK(differ == 0 && differOrdered == 0 && differFilter == 0,
    "EmbedSurface: %d differ with a reused workspace, %d in vertex order, %d from the filter",
    differ, differOrdered, differFilter);
  HOEMBED_CHECK(differMesh > 0, "the tet4 and tet10 meshes gave the same distances");

  // the two steps apart (OrderSurface, then FloodSurface) give EmbedSurface's results; a
  // FloodSurface without its own OrderSurface is refused
  std::vector<hoembed::VertexEmbedding> split;
  hoembed::OrderSurface(v.data(), n, tris, 0, nullptr, ws);
  hoembed::FloodSurface(m10, method, split, {}, nullptr, ws);
  int differSplit = split.size() == size_t(n) ? 0 : -1;
  for (Id k = 0; k < n && differSplit >= 0; ++k)
    differSplit += !same(plain[k], split[k]);
  HOEMBED_CHECK(differSplit == 0, "OrderSurface + FloodSurface: %d results differ", differSplit);
  bool refused = false;
  try
  {
    hoembed::FloodSurface(m10, method, split, {}, nullptr, ws);
  }
  catch (const std::logic_error&)
  {
    refused = true;
  }
  HOEMBED_CHECK(refused, "a second FloodSurface without OrderSurface was not refused");
}

// ReuseMeshPreparation: the prepared mesh is kept while the mesh input is unmodified (a
// new surface, or the filter's own Modified(), does not prepare again) and prepared anew
// after any modification of the mesh: its points, its connectivity array edited in place,
// another grid, validation asked for after an unvalidated preparation. Every output equals
// a fresh filter's.
void TestMeshReuse(vtkPolyData* surface, vtkUnstructuredGrid* grid10, vtkUnstructuredGrid* grid4)
{
  auto distances = [](vtkPolyData* out) {
    std::vector<double> d;
    auto* a =
      vtkDoubleArray::SafeDownCast(out->GetPointData()->GetArray("EmbeddingClosestDistance"));
    for (vtkIdType i = 0; a && i < a->GetNumberOfTuples(); ++i)
      d.push_back(a->GetValue(i));
    return d;
  };
  vtkNew<vtkUnstructuredGrid> g;
  g->DeepCopy(grid10);
  vtkNew<vtkEmbeddingCoordinatesFilter> f;
  vtkNew<vtkCallbackCommand> cb;
  ErrorCatcher errors;
  cb->SetClientData(&errors);
  cb->SetCallback(ErrorCatcher::Callback);
  f->AddObserver(vtkCommand::ErrorEvent, cb);
  f->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, cb);
  f->SetInputData(0, surface);
  f->SetMeshData(g);
  auto update = [&](const char* what, vtkPolyData* s, vtkUnstructuredGrid* mesh,
                  vtkIdType preparations) {
    errors.Count = 0;
    f->SetInputData(0, s);
    f->SetMeshData(mesh);
    f->Modified();
    f->Update();
    HOEMBED_CHECK(errors.Count == 0, "mesh reuse, %s: error %s", what, errors.Text.c_str());
    HOEMBED_CHECK(f->GetNumberOfMeshPreparations() == preparations,
      "mesh reuse, %s: %lld preparations, expected %lld", what,
      static_cast<long long>(f->GetNumberOfMeshPreparations()),
      static_cast<long long>(preparations));
    auto fresh = RunFilter(s, mesh, 0);
    HOEMBED_CHECK(distances(f->GetOutput()) == distances(fresh) && !distances(fresh).empty(),
      "mesh reuse, %s: distances differ from a fresh filter's", what);
  };
  HOEMBED_CHECK(f->GetReuseMeshPreparation(), "ReuseMeshPreparation is on by default");
  update("first Update", surface, g, 1);
  update("filter modified", surface, g, 1);
  auto other = MakeSurface(false, false);
  update("another surface", other, g, 1);

  // points moved in place: the points' Modified() is the grid's
  for (vtkIdType i = 0; i < g->GetNumberOfPoints(); ++i)
  {
    double x[3];
    g->GetPoint(i, x);
    g->GetPoints()->SetPoint(i, 1.1 * x[0], x[1] - 0.05, x[2]);
  }
  g->GetPoints()->Modified();
  update("points moved", surface, g, 2);

  // connectivity edited in place, only the array told: cell 0 inverted (corners 1, 2
  // and the mid-edge nodes that follow them swapped), then restored
  vtkDataArray* conn = g->GetCells()->GetConnectivityArray();
  const vtkIdType base = g->GetCells()->GetOffsetsArray()->GetTuple1(0);
  auto swapIds = [&](int a, int b) {
    const double t = conn->GetTuple1(base + a);
    conn->SetTuple1(base + a, conn->GetTuple1(base + b));
    conn->SetTuple1(base + b, t);
  };
  auto invert = [&]() {
    swapIds(1, 2);
    swapIds(4, 6);
    swapIds(8, 9);
    conn->Modified();
  };
  invert();
  errors.Count = 0;
  f->Modified();
  f->Update();
  HOEMBED_CHECK(errors.Count > 0 && errors.Text.find("inverted or degenerate") != std::string::npos,
    "mesh reuse: connectivity edited in place not noticed (%d errors: %s)", errors.Count,
    errors.Text.c_str());
  HOEMBED_CHECK(f->GetNumberOfMeshPreparations() == 2, "mesh reuse: a failed preparation counted");
  // unvalidated, the inverted mesh is prepared; asking for validation again prepares anew
  f->ValidateElementsOff();
  errors.Count = 0;
  f->Modified();
  f->Update();
  HOEMBED_CHECK(errors.Count == 0 && f->GetNumberOfMeshPreparations() == 3,
    "mesh reuse: unvalidated preparation (%d errors, %lld preparations)", errors.Count,
    static_cast<long long>(f->GetNumberOfMeshPreparations()));
  f->ValidateElementsOn();
  errors.Count = 0;
  f->Modified();
  f->Update();
  HOEMBED_CHECK(errors.Count > 0 && errors.Text.find("inverted or degenerate") != std::string::npos,
    "mesh reuse: validation after an unvalidated preparation skipped");
  invert(); // back to the valid cell
  update("connectivity restored", surface, g, 4);
  update("another grid", surface, grid4, 5);
  update("back to the first grid", surface, g, 6);
  f->ReuseMeshPreparationOff();
  update("reuse off", surface, g, 7);
  update("reuse off, again", surface, g, 8);
  std::printf("mesh reuse: 8 preparations over 12 Updates, as expected\n");
}

int main(int argc, char* argv[])
{
  const std::string dataDir = hoembed_test::DataDir(argc, argv);

  auto surface = MakeSurface(true, true);
  auto grid10 = MakeBoxTetMesh(4, 2, 2, 2.0, 1.0, 1.0, 2, CurveMap);
  auto grid4 = MakeBoxTetMesh(4, 2, 2, 2.0, 1.0, 1.0, 1, CurveMap);

  auto out10 = RunFilter(surface, grid10, 0);
  HOEMBED_CHECK(out10->GetNumberOfPoints() == surface->GetNumberOfPoints(), "tet10 output size");
  CheckEmbedding("tet10 normal-offset", surface, grid10, out10, 0, true);
  auto bary10 = RunFilter(surface, grid10, 1);
  CheckEmbedding("tet10 barycentric", surface, grid10, bary10, 1, false);
  auto out4 = RunFilter(surface, grid4, 0);
  CheckEmbedding("tet4 normal-offset", surface, grid4, out4, 0, true);
  auto bary4 = RunFilter(surface, grid4, 1);
  CheckEmbedding("tet4 barycentric", surface, grid4, bary4, 1, true);

  // one thread and two threads, many partitions: identical distances
  vtkSMPTools::Initialize(1);
  auto seq = RunFilter(surface, grid10, 0);
  vtkSMPTools::Initialize(2);
  {
    const int diff = CountDiffering(
      seq, RunFilterWithPartitions(surface, grid10, 37), "EmbeddingClosestDistance", 1e-12);
    HOEMBED_CHECK(diff == 0, "1 vs 2 threads / 37 partitions: %d distances differ", diff);
  }

  TestErrors(surface, grid10);
  {
    auto s4 = MakeSurface(false, false);
    TestErrors(s4, grid4);
  }
  TestSaveLoad(out10);
  TestEmbedSurfaceWorkspace(surface, grid10, grid4, out10);
  TestMeshReuse(surface, grid10, grid4);
  TestCrossingBoundary();
  if (!dataDir.empty())
    TestRealMeshes(dataDir);
  else
    std::printf("real meshes skipped: no data folder\n");
  return hoembed_test::Report("TestEmbeddingCoordinatesFilter");
}
