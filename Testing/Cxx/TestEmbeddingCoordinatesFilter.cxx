// vtkEmbeddingCoordinatesFilter and its kernels against references nobody here wrote:
// dense sampling of curved elements, exhaustive (brute-force) search over every boundary
// face and every cell from several starts, VTK's own vtkQuadraticTetra / vtkTetra
// interpolation for the reconstruction v = p + d n, and VTK's XML writer/reader.
#include "hoembedEmbeddingTestUtilities.h"

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

// Smallest squared distance from v to the tet map m sampled on the lattice of n steps per
// edge of the reference tet.
double LatticeDistance2(const hoembed::QuadraticMap& m, const double v[3], int n)
{
  double best = std::numeric_limits<double>::infinity();
  for (int i = 0; i <= n; ++i)
    for (int j = 0; i + j <= n; ++j)
      for (int k = 0; i + j + k <= n; ++k)
      {
        const double pc[3] = { double(i) / n, double(j) / n, double(k) / n };
        double y[3];
        hoembed::EvaluateMap(m, pc, y);
        best = std::min(best, (y[0] - v[0]) * (y[0] - v[0]) + (y[1] - v[1]) * (y[1] - v[1]) +
            (y[2] - v[2]) * (y[2] - v[2]));
      }
  return best;
}

void TestKernels()
{
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  // tri6 patches: a flat triangle with perturbed mid-edge nodes
  int worse = 0, outside = 0, notLocal = 0, onEdge = 0;
  for (int trial = 0; trial < 40; ++trial)
  {
    double x[18] = { 0, 0, 0, 1, 0, 0, 0, 1, 0, 0.5, 0, 0, 0.5, 0.5, 0, 0, 0.5, 0 };
    for (int a = 3; a < 6; ++a)
      for (int d = 0; d < 3; ++d)
        x[3 * a + d] += 0.2 * U(rng);
    hoembed::QuadraticMap m;
    hoembed::MakeTriangleMap(x, 6, m);
    for (int q = 0; q < 10; ++q)
    {
      const double v[3] = { 0.5 + 1.2 * U(rng), 0.5 + 1.2 * U(rng), 0.8 * U(rng) };
      // best of the linear start and three starts near the corners (one start can end
      // in a local minimum of a strongly curved patch)
      const double starts[4][2] = { { 0, 0 }, { 0.8, 0.1 }, { 0.1, 0.8 }, { 0.1, 0.1 } };
      hoembed::ClosestPointResult r, rs;
      for (int k = 0; k < 4; ++k)
      {
        double st[2] = { starts[k][0], starts[k][1] };
        if (k == 0)
          hoembed::LinearStart(m, v, st);
        hoembed::ClosestPointOnMap(m, v, st, rs);
        if (rs.Param[0] < 0 || rs.Param[1] < 0 || rs.Param[0] + rs.Param[1] > 1.0 || !rs.Converged)
          ++outside;
        // every answer is a local minimum over the triangle: no nearer point around it
        // (this checks the multipliers of the edge and corner answers)
        const int bits = rs.Active & 7;
        onEdge += bits == 1 || bits == 2 || bits == 4;
        bool nearer = false;
        for (const double h : { 1e-5, 1e-4, 1e-3 })
          for (int a = 0; a < 16 && !nearer; ++a)
          {
            const double uv[2] = { rs.Param[0] + h * std::cos(0.3927 * a),
              rs.Param[1] + h * std::sin(0.3927 * a) };
            if (uv[0] < 0 || uv[1] < 0 || uv[0] + uv[1] > 1)
              continue;
            double y[3];
            hoembed::EvaluateMap(m, uv, y);
            const double d2 = (y[0] - v[0]) * (y[0] - v[0]) + (y[1] - v[1]) * (y[1] - v[1]) +
              (y[2] - v[2]) * (y[2] - v[2]);
            nearer = d2 < rs.Distance2 * (1.0 - 1e-12) - 1e-24;
          }
        notLocal += nearer;
        if (k == 0 || rs.Distance2 < r.Distance2)
          r = rs;
      }
      // dense sampling with the shared shape functions
      double best = 1e300;
      const int n = 200;
      for (int i = 0; i <= n; ++i)
        for (int j = 0; i + j <= n; ++j)
        {
          const double uv[2] = { double(i) / n, double(j) / n };
          double N[6], p[3];
          hoembed::Tri6Shape(uv, N);
          hoembed::Interpolate(6, N, x, p);
          const double d2 = (p[0] - v[0]) * (p[0] - v[0]) + (p[1] - v[1]) * (p[1] - v[1]) +
            (p[2] - v[2]) * (p[2] - v[2]);
          best = std::min(best, d2);
        }
      if (std::sqrt(r.Distance2) > std::sqrt(best) + 1e-12)
        ++worse;
    }
  }
  HOEMBED_CHECK(worse == 0, "tri6 closest point worse than dense sampling for %d queries", worse);
  HOEMBED_CHECK(outside == 0, "tri6 closest point left the triangle or did not converge %d times", outside);
  HOEMBED_CHECK(notLocal == 0, "tri6 closest point: %d answers with a nearer point around them",
    notLocal);
  HOEMBED_CHECK(onEdge >= 40, "tri6 closest point: only %d answers on an edge (test setup)", onEdge);
  std::printf("tri6 closest point: %d answers on an edge, %d not local minima\n", onEdge,
    notLocal);

  // tet10: the monomial map matches VTK's vtkQuadraticTetra; inside points are recovered;
  // outside points are no worse than dense sampling
  vtkNew<vtkQuadraticTetra> qt;
  int mapErr = 0, insideErr = 0, tetWorse = 0;
  for (int trial = 0; trial < 20; ++trial)
  {
    double x[30];
    for (int a = 0; a < 10; ++a)
    {
      for (int d = 0; d < 3; ++d)
        x[3 * a + d] = hoembed::Tet10NodeParametric[a][d] + (a >= 4 ? 0.06 * U(rng) : 0.0);
      qt->GetPoints()->SetPoint(a, x + 3 * a);
      qt->GetPointIds()->SetId(a, a);
    }
    hoembed::QuadraticMap m;
    hoembed::MakeTetMap(x, 10, m);
    for (int q = 0; q < 20; ++q)
    {
      double pc[3] = { 0.5 * (1 + U(rng)), 0.5 * (1 + U(rng)), 0.5 * (1 + U(rng)) };
      if (pc[0] + pc[1] + pc[2] > 0.999)
      {
        const double s = 0.999 / (pc[0] + pc[1] + pc[2]);
        pc[0] *= s;
        pc[1] *= s;
        pc[2] *= s;
      }
      double a[3], b[3], w[10];
      int sub;
      hoembed::EvaluateMap(m, pc, a);
      qt->EvaluateLocation(sub, pc, b, w);
      if (std::fabs(a[0] - b[0]) + std::fabs(a[1] - b[1]) + std::fabs(a[2] - b[2]) > 1e-13)
        ++mapErr;
      hoembed::ClosestPointResult r;
      hoembed::ClosestPointOnMap(m, a, nullptr, r);
      if (r.Distance2 > 1e-26 || std::fabs(r.Param[0] - pc[0]) > 1e-9)
        ++insideErr;
      const double v[3] = { 0.3 + 1.5 * U(rng), 0.3 + 1.5 * U(rng), 0.3 + 1.5 * U(rng) };
      hoembed::ClosestPointOnMap(m, v, nullptr, r);
      if (!r.Converged)
        ++tetWorse;
      const double best = LatticeDistance2(m, v, 40);
      if (std::sqrt(r.Distance2) > std::sqrt(best) + 1e-12)
        ++tetWorse;
    }
  }
  HOEMBED_CHECK(mapErr == 0, "tet10 monomial map differs from vtkQuadraticTetra %d times", mapErr);
  HOEMBED_CHECK(insideErr == 0, "inside points not recovered %d times", insideErr);
  HOEMBED_CHECK(tetWorse == 0, "tet10 closest point worse than sampling %d times", tetWorse);
}

vtkSmartPointer<vtkPolyData> RunFilter(vtkPolyData* surface, vtkUnstructuredGrid* mesh,
  int method, ErrorCatcher* errors = nullptr)
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
  HOEMBED_CHECK(cellId && pc && dist && res && face && closest && iters && visited,
    "%s: missing output arrays", label);
  if (!(cellId && pc && dist && res && face && closest && iters && visited))
    return;
  auto* m = vtkStringArray::SafeDownCast(out->GetFieldData()->GetAbstractArray("EmbeddingMethod"));
  auto* fp = vtkStringArray::SafeDownCast(
    out->GetFieldData()->GetAbstractArray("EmbeddingMeshFingerprint"));
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
    if (method == 0 && (r[0] < -1e-12 || r[1] < -1e-12 || r[2] < -1e-12 || r[0] + r[1] + r[2] > 1 + 1e-12))
      ++badPc;
    double q[3];
    for (int k = 0; k < 3; ++k)
      q[k] = v[k] - p[k] - d * n[k];
    const double rr = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]);
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
    HOEMBED_CHECK(maxAll <= 1e-10 * diag, "%s: EmbeddingResidual max %.3g diag", label, maxAll / diag);
  std::printf("%s: %d of %lld vertices checked (%d inside, %d outside), max |distance - brute "
              "force| = %.3g diag, max residual = %.3g diag (all vertices: %.3g)\n",
    label, checked, static_cast<long long>(surface->GetNumberOfPoints()), nInside, nOutside,
    maxDistErr, maxRes, maxAll / diag);
  HOEMBED_CHECK(badDist == 0, "%s: %d vertices differ from brute force", label, badDist);
  HOEMBED_CHECK(badRes == 0, "%s: %d vertices with reconstruction residual > 1e-10 diag", label, badRes);
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
    p->SetPoint(ids->GetId(3), (a[0] + b[0] + c[0]) / 3, (a[1] + b[1] + c[1]) / 3, (a[2] + b[2] + c[2]) / 3);
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
    vtkIdType ten[10] = { ids->GetId(0), ids->GetId(1), ids->GetId(2), ids->GetId(3), 4, 5, 6,
      7, 8, 9 };
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
  auto* fa = vtkStringArray::SafeDownCast(out->GetFieldData()->GetAbstractArray("EmbeddingMeshFingerprint"));
  auto* fb = vtkStringArray::SafeDownCast(back->GetFieldData()->GetAbstractArray("EmbeddingMeshFingerprint"));
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
  HOEMBED_CHECK(out->GetNumberOfPoints() == surface->GetNumberOfPoints(), "crossing: output size");
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
      in = qt->EvaluatePosition(v, cp, sub, pc, d2, w) == 1 && pc[0] > 1e-3 &&
        pc[1] > 1e-3 && pc[2] > 1e-3 && pc[0] + pc[1] + pc[2] < 1.0 - 1e-3;
    }
    if (in)
    {
      ++insideVtk;
      if (!closest || closest->GetValue(i) != 0.0)
        ++missed;
    }
  }
  HOEMBED_CHECK(insideVtk >= 5, "crossing: only %d gap points inside the bulge (test setup)", insideVtk);
  HOEMBED_CHECK(missed == 0, "crossing: %d of %d points inside a curved cell reported outside",
    missed, insideVtk);
  std::printf("crossing boundary%s: %d of %lld gap points inside the bulge\n",
    isolated ? " (isolated points)" : "", insideVtk,
    static_cast<long long>(surface->GetNumberOfPoints()));
  CheckEmbedding(isolated ? "crossing boundary, isolated points" : "crossing boundary", input,
    grid, out, 0, true);
  }
}
// The reference tet10's nodes (VTK order).
const double RefTet10[10][3] = { { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 },
  { 0.5, 0, 0 }, { 0.5, 0.5, 0 }, { 0, 0.5, 0 }, { 0, 0, 0.5 }, { 0.5, 0, 0.5 },
  { 0, 0.5, 0.5 } };

// Distance from v to the element of the tet map m by brute force: constrained solves from
// 5 starts and a dense sample (16 steps per edge) of the element.
double BruteDistanceToTetMap(const hoembed::QuadraticMap& m, const double v[3])
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

// The closed-form tet10 map (MakeTetMap from the corner Jacobians) against the shape
// functions, and the fast validity test (Bernstein coefficients of det J) against
// hoembed::Tet10IsValid and a dense sample of det J: it may only accept valid elements.
void TestTet10Validity()
{
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  int accepted = 0, rejected = 0, wrongAccept = 0, notFull = 0;
  double mapErr = 0.0;
  for (int trial = 0; trial < 400; ++trial)
  {
    const double amp = 0.05 + 0.4 * (trial % 8) / 7.0;
    double x[30];
    for (int a = 0; a < 10; ++a)
      for (int d = 0; d < 3; ++d)
        x[3 * a + d] = RefTet10[a][d] + (a < 4 ? 0.3 : 1.0) * amp * U(rng);
    hoembed::QuadraticMap m;
    hoembed::MakeTetMap(x, 10, m);
    double minDet = std::numeric_limits<double>::infinity();
    const int n = 12;
    for (int i = 0; i <= n; ++i)
      for (int j = 0; i + j <= n; ++j)
        for (int k = 0; i + j + k <= n; ++k)
        {
          const double pc[3] = { double(i) / n, double(j) / n, double(k) / n };
          double N[10], p[3] = { 0, 0, 0 }, q[3], J[3][3];
          hoembed::Tet10Shape(pc, N);
          for (int a = 0; a < 10; ++a)
            for (int d = 0; d < 3; ++d)
              p[d] += N[a] * x[3 * a + d];
          hoembed::EvaluateMap(m, pc, q, J);
          for (int d = 0; d < 3; ++d)
            mapErr = std::max(mapErr, std::fabs(p[d] - q[d]));
          const double det = J[0][0] * (J[1][1] * J[2][2] - J[1][2] * J[2][1]) -
            J[0][1] * (J[1][0] * J[2][2] - J[1][2] * J[2][0]) +
            J[0][2] * (J[1][0] * J[2][1] - J[1][1] * J[2][0]);
          minDet = std::min(minDet, det);
        }
    const bool fast = hoembed::Tet10JacobianProvablyPositive(x);
    (fast ? accepted : rejected)++;
    if (fast && !(minDet > 0.0))
      ++wrongAccept;
    if (fast && !hoembed::Tet10IsValid(x))
      ++notFull;
  }
  HOEMBED_CHECK(mapErr <= 1e-13, "tet10 map: max deviation from the shape functions %g", mapErr);
  HOEMBED_CHECK(wrongAccept == 0, "fast tet10 validity: %d elements with det J <= 0 accepted",
    wrongAccept);
  HOEMBED_CHECK(notFull == 0, "fast tet10 validity: %d accepted elements Tet10IsValid rejects",
    notFull);
  HOEMBED_CHECK(accepted > 50 && rejected > 50,
    "fast tet10 validity: %d accepted, %d rejected (test setup)", accepted, rejected);
  std::printf("tet10 validity: %d accepted, %d not proven by the fast test; map error %.2g\n",
    accepted, rejected, mapErr);
}

// The closed-form monomial maps (MakeTriangleMap for tri3/tri6, MakeTetMap for
// tet4/tet10) against the shape functions and their derivatives at random parametric
// points of randomly perturbed elements: value and Jacobian. A wrong node in one
// coefficient puts the error at O(1).
void TestMonomialMaps()
{
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> U(-1.0, 1.0), P(0.0, 1.0);
  double worst[4] = { 0, 0, 0, 0 }; // tri3, tri6, tet4, tet10
  for (int trial = 0; trial < 50; ++trial)
    for (int kind = 0; kind < 4; ++kind)
    {
      const int dim = kind < 2 ? 2 : 3;
      const int n = kind == 0 ? 3 : (kind == 1 ? 6 : (kind == 2 ? 4 : 10));
      double x[30];
      for (int k = 0; k < 3 * n; ++k)
        x[k] = 2.0 * U(rng);
      hoembed::QuadraticMap m;
      if (dim == 2)
        hoembed::MakeTriangleMap(x, n, m);
      else
        hoembed::MakeTetMap(x, n, m);
      HOEMBED_CHECK(m.Dim == dim, "monomial map of %d nodes: Dim %d", n, m.Dim);
      for (int q = 0; q < 10; ++q)
      {
        double xi[3] = { P(rng), P(rng), dim == 3 ? P(rng) : 0.0 };
        double N[10], dN[30];
        if (kind == 0)
        {
          hoembed::Tri3Shape(xi, N);
          hoembed::Tri3Derivs(xi, dN);
        }
        else if (kind == 1)
        {
          hoembed::Tri6Shape(xi, N);
          hoembed::Tri6Derivs(xi, dN);
        }
        else if (kind == 2)
        {
          hoembed::Tet4Shape(xi, N);
          hoembed::Tet4Derivs(xi, dN);
        }
        else
        {
          hoembed::Tet10Shape(xi, N);
          hoembed::Tet10Derivs(xi, dN);
        }
        double p[3] = { 0, 0, 0 }, Jref[3][3] = {}, y[3], J[3][3];
        for (int a = 0; a < n; ++a)
          for (int d = 0; d < 3; ++d)
          {
            p[d] += N[a] * x[3 * a + d];
            for (int i = 0; i < dim; ++i)
              Jref[i][d] += dN[i * n + a] * x[3 * a + d];
          }
        hoembed::EvaluateMap(m, xi, y, J);
        for (int d = 0; d < 3; ++d)
        {
          worst[kind] = std::max(worst[kind], std::fabs(p[d] - y[d]));
          for (int i = 0; i < dim; ++i)
            worst[kind] = std::max(worst[kind], std::fabs(Jref[i][d] - J[i][d]));
        }
      }
    }
  const char* names[4] = { "tri3", "tri6", "tet4", "tet10" };
  for (int kind = 0; kind < 4; ++kind)
    HOEMBED_CHECK(worst[kind] <= 1e-12, "%s monomial map: max deviation from the shape functions %g",
      names[kind], worst[kind]);
  std::printf("monomial maps: max deviation tri3 %.2g, tri6 %.2g, tet4 %.2g, tet10 %.2g\n",
    worst[0], worst[1], worst[2], worst[3]);
}

// hoembed::TetMapExcludes (the rule that rejects a cell for a point the pseudo-normal puts
// outside) against the distance from x(eta) to the element by brute force (constrained
// solves from 5 starts and a dense sample): it may only exclude when that distance exceeds
// the reach, for reaches on both sides of it. The same for the radius of
// TetMapExclusionRadius with the element's precomputed TetMapExclusionRate.
void TestTetMapExcludes()
{
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  int excluded = 0, wrong = 0, tried = 0, byRate = 0, wrongRadius = 0;
  for (int trial = 0; trial < 60; ++trial)
  {
    // anisotropic scales from 1/20 to 20: a rule with the wrong scaling fails here
    double scale[3];
    for (double& sc : scale)
      sc = std::pow(20.0, U(rng));
    double x[30];
    for (int a = 0; a < 10; ++a)
      for (int d = 0; d < 3; ++d)
        x[3 * a + d] = scale[d] * (RefTet10[a][d] + (a < 4 ? 0.05 : 0.12) * U(rng));
    if (!hoembed::Tet10JacobianProvablyPositive(x))
      continue;
    hoembed::QuadraticMap m;
    hoembed::MakeTetMap(x, 10, m);
    const double rate = hoembed::TetMapExclusionRate(m);
    for (int q = 0; q < 40; ++q)
    {
      // a parametric point outside the element, near one of its faces or corners (the
      // first 20), or just beyond a face, where the element's rate serves (the others)
      double eta[3] = { 0.3 + 0.6 * U(rng), 0.3 + 0.6 * U(rng), 0.3 + 0.6 * U(rng) };
      if (q >= 20)
      {
        double L[4], sum = 0.0;
        for (double& l : L)
          sum += (l = 0.5 * (1.0 + U(rng)));
        const int face = q % 4;
        L[face] = -0.05 * (1.0 + U(rng)) * sum; // beyond the face L_face = 0, up to 0.1
        sum = L[0] + L[1] + L[2] + L[3];
        for (int i = 0; i < 3; ++i)
          eta[i] = L[i + 1] / sum;
      }
      if (eta[0] >= 0 && eta[1] >= 0 && eta[2] >= 0 && eta[0] + eta[1] + eta[2] <= 1)
        continue;
      double v[3];
      hoembed::EvaluateMap(m, eta, v);
      const double dist = BruteDistanceToTetMap(m, v);
      const double lmin = std::min({ eta[0], eta[1], eta[2], 1.0 - eta[0] - eta[1] - eta[2] });
      if (rate > 0.0 && 1.0 - 2.0 * lmin <= hoembed::ExclusionRateScale)
        ++byRate;
      if (hoembed::TetMapExclusionRadius(m, eta, rate) > dist)
        ++wrongRadius;
      for (const double f : { 0.0, 0.3, 0.9, 1.1, 3.0 })
      {
        ++tried;
        if (hoembed::TetMapExcludes(m, eta, f * dist))
        {
          ++excluded;
          if (f * dist >= dist)
            ++wrong;
        }
      }
    }
  }
  HOEMBED_CHECK(wrong == 0, "TetMapExcludes: %d exclusions with a point of the element "
    "within reach", wrong);
  HOEMBED_CHECK(excluded > tried / 10, "TetMapExcludes: only %d of %d excluded (test setup)",
    excluded, tried);
  HOEMBED_CHECK(wrongRadius == 0, "TetMapExclusionRadius: %d radii beyond the element's distance",
    wrongRadius);
  HOEMBED_CHECK(byRate >= 20, "TetMapExclusionRadius: the element's rate served only %d points "
    "(test setup)", byRate);
  std::printf("cell exclusion: %d of %d (point, reach) pairs excluded, none wrongly; %d radii "
              "from the element's rate\n", excluded, tried, byRate);
}

// hoembed::TetBarycentricExcludes (the straight tet plus edge bumps, interval sweeps)
// against the distance from a point to the element by brute force (constrained solves
// from 5 starts and a dense sample), for reaches on both sides of it: it may only exclude
// when that distance exceeds the reach. Points inside the element (distance 0), just
// outside its faces, near its curved edges and farther away; strongly curved and
// anisotropic elements, and tet4s (no bumps).
void TestTetBarycentricExcludes()
{
  std::mt19937 rng(10);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  int excluded = 0, wrong = 0, tried = 0, excludedNear = 0, triedNear = 0;
  for (int trial = 0; trial < 80; ++trial)
  {
    const int npc = trial % 8 == 7 ? 4 : 10;
    double scale[3];
    for (double& sc : scale)
      sc = std::pow(20.0, U(rng));
    const double bend = trial % 2 ? 0.2 : 0.08; // midnode displacement
    double x[30];
    for (int a = 0; a < 10; ++a)
      for (int d = 0; d < 3; ++d)
        x[3 * a + d] = scale[d] * (RefTet10[a][d] + (a < 4 ? 0.05 : bend) * U(rng)) + 100.0;
    if (npc == 10 && !hoembed::Tet10JacobianProvablyPositive(x))
      continue;
    hoembed::QuadraticMap m;
    hoembed::MakeTetMap(x, npc, m);
    hoembed::TetBarycentricForm form;
    hoembed::MakeTetBarycentricForm(x, npc, form);
    for (int q = 0; q < 40; ++q)
    {
      // barycentric coordinates of a parametric point: inside (q < 5), beyond a face
      // (q < 25, up to 0.1), near an edge (both coordinates of its corners large), or
      // anywhere within 0.6 of the element
      double L[4], sum = 0.0;
      for (double& l : L)
        sum += (l = 0.5 * (1.0 + U(rng)));
      for (double& l : L)
        l /= sum;
      if (q >= 5 && q < 25)
        L[q % 4] = -0.05 * (1.0 + U(rng));
      else if (q >= 25 && q < 33)
      {
        const int e0 = q % 4, e1 = (q + 1 + (q / 4) % 3) % 4;
        for (int k = 0; k < 4; ++k)
          L[k] = (k == e0 || k == e1) ? 0.5 + 0.1 * U(rng) : 0.05 * U(rng);
      }
      else if (q >= 33)
        for (double& l : L)
          l += 0.3 * U(rng);
      const double eta[3] = { L[1], L[2], L[3] };
      double v[3];
      hoembed::EvaluateMap(m, eta, v);
      // a world-space offset too, so that v is not always on the map's extension
      if (q >= 33)
        for (int d = 0; d < 3; ++d)
          v[d] += 0.05 * scale[d] * U(rng);
      const double dist = BruteDistanceToTetMap(m, v);
      for (const double f : { 0.0, 0.3, 0.9, 1.1, 3.0 })
      {
        const bool near = q >= 25 && q < 33;
        ++tried;
        triedNear += near;
        if (hoembed::TetBarycentricExcludes(form, v, f * dist, 30))
        {
          ++excluded;
          excludedNear += near;
          if (f * dist >= dist)
            ++wrong;
        }
      }
    }
  }
  HOEMBED_CHECK(wrong == 0, "TetBarycentricExcludes: %d exclusions with a point of the element "
    "within reach", wrong);
  HOEMBED_CHECK(excluded > tried / 6 && excludedNear > triedNear / 10,
    "TetBarycentricExcludes: only %d of %d excluded, %d of %d near an edge (test setup)",
    excluded, tried, excludedNear, triedNear);
  // a degenerate (flat) straight tet gives a form that excludes nothing
  const double flat[12] = { 0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0 };
  hoembed::TetBarycentricForm form;
  hoembed::MakeTetBarycentricForm(flat, 4, form);
  const double far[3] = { 5, 5, 5 };
  HOEMBED_CHECK(!hoembed::TetBarycentricExcludes(form, far, 0.0),
    "TetBarycentricExcludes: a flat tet's form excluded a point");
  std::printf("straight tet + bumps: %d of %d (point, reach) pairs excluded (%d of %d near a "
              "curved edge), %d wrongly\n", excluded, tried, excludedNear, triedNear, wrong);
}

// EmbeddingMesh::FaceLowerBound2 (the pruning rule of the boundary search) against the
// distance to each curved boundary face by brute force (7 constrained solves and a dense
// sample of the face): it must never exceed it, and must prune (be positive) often. The
// map shears the faces strongly in their own planes, so a bound that ignored the
// tangential deviation of the curved face from its straight triangle would fail here.
void ShearMap(double x[3])
{
  const double X = x[0], Y = x[1], Z = x[2];
  x[0] = X + 0.25 * std::sin(M_PI * Y) + 0.1 * Z * Z;
  x[1] = Y + 0.25 * std::sin(M_PI * X) - 0.1 * Z;
  x[2] = Z + 0.15 * std::sin(M_PI * X) * std::sin(M_PI * Y);
}

// hoembed::BoxGrid::Containing (the cells whose boxes may hold a point) and VisitNearer
// (the boundary faces whose boxes are within a distance) against a scan of every box:
// clustered and flat boxes, points on box faces, outside the grid and far away, several
// tolerances and radii; each item once. NearItem: an item for every query of a grid
// that has any, one holding the point when a box does.
void TestBoxGrid()
{
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  int mismatches = 0, duplicates = 0, hits = 0, queries = 0, nearMismatches = 0, nearHits = 0;
  int nearItemMismatches = 0, boxDistanceMismatches = 0;
  {
    hoembed::BoxGrid empty;
    empty.Build({});
    const double origin[3] = { 0, 0, 0 };
    nearItemMismatches += empty.NearItem(origin) != -1;
  }
  for (int trial = 0; trial < 6; ++trial)
  {
    const int n = trial == 0 ? 1 : 40 * trial * trial;
    std::vector<double> boxes(6 * n);
    for (int i = 0; i < n; ++i)
    {
      // a cluster near the origin and a spread; some boxes flat in z
      const double c = i % 3 == 0 ? 0.1 : 1.0;
      for (int d = 0; d < 3; ++d)
      {
        const double a = c * U(rng), w = (trial == 3 && d == 2) ? 0.0 : 0.2 * U(rng);
        boxes[6 * i + d] = a;
        boxes[6 * i + 3 + d] = a + w;
      }
    }
    hoembed::BoxGrid grid;
    grid.Build(boxes);
    for (int q = 0; q < 400; ++q)
    {
      double v[3];
      for (int d = 0; d < 3; ++d)
        v[d] = -0.3 + 1.8 * U(rng);
      if (q % 4 == 1) // on a face of a box
      {
        const int i = static_cast<int>(U(rng) * n) % n;
        for (int d = 0; d < 3; ++d)
          v[d] = boxes[6 * i + d] + U(rng) * (boxes[6 * i + 3 + d] - boxes[6 * i + d]);
        v[q % 3] = boxes[6 * i + (q % 2 ? 3 : 0) + q % 3];
      }
      if (q == 7)
        v[0] = 1e6;
      for (const double tol : { 0.0, 1e-9, 0.05 })
      {
        ++queries;
        std::vector<hoembed::BoxGrid::Id> got, want;
        grid.Containing(v, tol, got);
        for (int i = 0; i < n; ++i)
        {
          bool in = true;
          for (int d = 0; d < 3; ++d)
            in = in && v[d] >= boxes[6 * i + d] - tol && v[d] <= boxes[6 * i + 3 + d] + tol;
          if (in)
            want.push_back(i);
        }
        std::sort(got.begin(), got.end());
        duplicates += std::adjacent_find(got.begin(), got.end()) != got.end();
        got.erase(std::unique(got.begin(), got.end()), got.end());
        mismatches += got != want;
        hits += static_cast<int>(want.size());
        if (tol == 0.0)
        {
          // NearItem: some item, and one whose box holds v when any box does (such a box
          // is listed in v's own bin, the first shell scanned)
          const hoembed::BoxGrid::Id near = grid.NearItem(v);
          if (near < 0 || near >= n ||
            (!want.empty() && hoembed::AabbTree::BoxDistance2(&boxes[6 * near], v) != 0.0))
            ++nearItemMismatches;
        }
      }
      // BoxDistance2 against the distance to the point clamped into the box (the same
      // roundings: equal bit for bit), for every box: inside, on faces, beyond each side
      for (int i = 0; i < n; ++i)
      {
        double s = 0.0;
        for (int d = 0; d < 3; ++d)
        {
          const double c = std::min(std::max(v[d], boxes[6 * i + d]), boxes[6 * i + 3 + d]);
          s += (v[d] - c) * (v[d] - c);
        }
        boxDistanceMismatches += hoembed::AabbTree::BoxDistance2(&boxes[6 * i], v) != s;
      }
      // VisitNearer: every box nearer than the radius (as it stands when the box is
      // reached: a visit may lower it, here to 1.2 times the visited box's distance), once
      for (const double radius : { 0.01, 0.1, 0.3 })
      {
        double best2 = radius * radius;
        std::vector<hoembed::BoxGrid::Id> got;
        if (!grid.VisitNearer(v, best2, 1 << 30, [&](hoembed::BoxGrid::Id item) {
              got.push_back(item);
              const double d2 = hoembed::AabbTree::BoxDistance2(&boxes[6 * item], v);
              if (q % 2)
                best2 = std::min(best2, 1.44 * d2);
            }))
        {
          ++nearMismatches;
          continue;
        }
        ++queries;
        std::sort(got.begin(), got.end());
        duplicates += std::adjacent_find(got.begin(), got.end()) != got.end();
        for (int i = 0; i < n; ++i)
        {
          const double d2 = hoembed::AabbTree::BoxDistance2(&boxes[6 * i], v);
          const bool visited = std::binary_search(got.begin(), got.end(), i);
          // a box nearer than the final radius must be visited; none beyond the first
          if ((d2 < best2 && !visited) || (visited && !(d2 < radius * radius)))
            ++nearMismatches;
        }
        nearHits += static_cast<int>(got.size());
      }
    }
  }
  HOEMBED_CHECK(mismatches == 0, "BoxGrid: %d of %d queries differ from a scan of the boxes",
    mismatches, queries);
  HOEMBED_CHECK(duplicates == 0, "BoxGrid: %d queries report an item twice", duplicates);
  HOEMBED_CHECK(hits > queries, "BoxGrid: only %d hits in %d queries (test setup)", hits, queries);
  HOEMBED_CHECK(nearMismatches == 0, "BoxGrid::VisitNearer: %d boxes missed or visited beyond "
    "the radius", nearMismatches);
  HOEMBED_CHECK(nearHits > 1000, "BoxGrid::VisitNearer: only %d visits (test setup)", nearHits);
  HOEMBED_CHECK(boxDistanceMismatches == 0, "AabbTree::BoxDistance2: %d of the point-box "
    "distances differ from the clamped point's", boxDistanceMismatches);
  HOEMBED_CHECK(nearItemMismatches == 0, "BoxGrid::NearItem: %d queries without an item, or "
    "with one whose box misses a point some box holds", nearItemMismatches);
  std::printf("box grid: %d queries, %d + %d hits, as a scan of every box\n", queries, hits,
    nearHits);
}

void TestFaceLowerBound()
{
  auto grid = MakeBoxTetMesh(2, 2, 2, 1.0, 1.0, 1.0, 2, ShearMap);
  int npc = 0;
  const auto conn = hoembed_test::MeshConnectivity(grid, npc);
  const auto pts = hoembed_test::PointsOf(grid);
  hoembed::EmbeddingMesh em;
  const std::string err = em.Build(pts.data(), grid->GetNumberOfPoints(),
    reinterpret_cast<const hoembed::EmbeddingMesh::Id*>(conn.data()), grid->GetNumberOfCells(), npc);
  HOEMBED_CHECK(err.empty(), "face bound: mesh build: %s", err.c_str());
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  const double starts[7][2] = { { 1.0 / 3, 1.0 / 3 }, { 0.8, 0.1 }, { 0.1, 0.8 }, { 0.1, 0.1 },
    { 0.45, 0.45 }, { 0.45, 0.1 }, { 0.1, 0.45 } };
  int over = 0, positive = 0, tight = 0, total = 0;
  double worst = 0.0;
  const hoembed::EmbeddingMesh::Id nbf = em.Topology.GetNumberOfBoundaryFaces();
  for (hoembed::EmbeddingMesh::Id f = 0; f < nbf; ++f)
  {
    const hoembed::QuadraticMap& m = em.FaceMaps[f];
    double c[3];
    const double centroid[2] = { 1.0 / 3, 1.0 / 3 };
    hoembed::EvaluateMap(m, centroid, c);
    for (int q = 0; q < 40; ++q)
    {
      // points around the face at distances from 0 to ~1 (near its edges too)
      double v[3];
      const double r = q < 20 ? 0.15 * U(rng) : 0.8 * U(rng);
      for (int d = 0; d < 3; ++d)
        v[d] = c[d] + r * (2.0 * U(rng) - 1.0) + 0.3 * (U(rng) - 0.5);
      double best = std::numeric_limits<double>::infinity();
      for (const auto& s0 : starts)
      {
        hoembed::ClosestPointResult res;
        hoembed::ClosestPointOnMap(m, v, s0, res, 200);
        best = std::min(best, res.Distance2);
      }
      for (int i = 0; i <= 60; ++i)
        for (int j = 0; i + j <= 60; ++j)
        {
          const double uv[2] = { i / 60.0, j / 60.0 };
          double x[3];
          hoembed::EvaluateMap(m, uv, x);
          const double e2 = (x[0] - v[0]) * (x[0] - v[0]) + (x[1] - v[1]) * (x[1] - v[1]) +
            (x[2] - v[2]) * (x[2] - v[2]);
          best = std::min(best, e2);
        }
      const double bound = em.FaceLowerBound2(f, v);
      ++total;
      if (bound > best * (1.0 + 1e-9) + 1e-24)
      {
        if (over < 5)
          std::fprintf(stderr, "face bound: face %lld bound %.17g > distance^2 %.17g\n",
            static_cast<long long>(f), bound, best);
        ++over;
      }
      if (best > 0.0)
        worst = std::max(worst, bound / best);
      positive += bound > 0.0;
      tight += bound > 0.5 * best;
    }
  }
  HOEMBED_CHECK(over == 0, "face bound: %d of %d bounds exceed the distance (max ratio %.17g)",
    over, total, worst);
  HOEMBED_CHECK(positive > total / 2, "face bound: only %d of %d bounds positive", positive, total);
  std::printf("face lower bound: %d samples, %d positive, %d above half the distance^2, max "
              "bound/distance^2 %.6f\n",
    total, positive, tight, worst);
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
      a.Distance == b.Distance && a.ClosestDistance == b.ClosestDistance &&
      a.Face == b.Face && a.Inside == b.Inside;
  };
  auto* closest = vtkDoubleArray::SafeDownCast(
    filterOut->GetPointData()->GetArray("EmbeddingClosestDistance"));
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
    auto* a = vtkDoubleArray::SafeDownCast(out->GetPointData()->GetArray("EmbeddingClosestDistance"));
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
      static_cast<long long>(f->GetNumberOfMeshPreparations()), static_cast<long long>(preparations));
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
  TestKernels();
  TestFaceLowerBound();
  TestBoxGrid();
  TestTet10Validity();
  TestMonomialMaps();
  TestTetMapExcludes();
  TestTetBarycentricExcludes();

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
