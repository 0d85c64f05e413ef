// The Ceres reference (Benchmarks/Cxx/hoembedCeresReference: the paper's bounded
// Levenberg–Marquardt, written by others, on faces evaluated by VTK's own cells) checked
// against the certified brute force, and the embedding filter checked against it, on
// every cell type the reference knows.
//
// One geometry, many cell types: a box under a global map phi of total degree <= 2 is
// described exactly by any cell whose map space holds the quadratic polynomials
// (VTK_QUADRATIC_TETRA, Lagrange tetrahedra of order 2-4, VTK_QUADRATIC_HEXAHEDRON's
// serendipity space, VTK_TRIQUADRATIC_HEXAHEDRON, Lagrange hexahedra of order 2-3), and a
// box under an affine map by every linear cell too. Nodes are placed with each VTK cell's
// own parametric coordinates (GetParametricCoords) and phi, so the node order is VTK's.
// The distance from a point to that shape is then one number, whatever the cell type:
// - the certified brute force (hoembed_exact, tet10 / tet4, its own shape functions and
//   bounds) gives it;
// - the Ceres reference on each cell type must equal it to 1e-10 of the diagonal;
// - vtkEmbeddingCoordinatesFilter's EmbeddingClosestDistance on each cell type it accepts
//   must equal the reference's to 1e-10 of the diagonal.
#include "hoembedCeresReference.h"
#include "hoembedEmbeddingTestUtilities.h"
#include "hoembedExactDistance.h"

#include "vtkCellType.h"
#include "vtkDoubleArray.h"
#include "vtkHexahedron.h"
#include "vtkHigherOrderHexahedron.h"
#include "vtkLagrangeHexahedron.h"
#include "vtkLagrangeTetra.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkQuadraticHexahedron.h"
#include "vtkQuadraticTetra.h"
#include "vtkSphereSource.h"
#include "vtkTetra.h"
#include "vtkTransform.h"
#include "vtkTransformPolyDataFilter.h"
#include "vtkTriQuadraticHexahedron.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

namespace
{
const int NX = 3, NY = 2, NZ = 2;
const double L[3] = { 2.0, 1.0, 1.0 };

struct CellKind
{
  const char* Name;
  int Type;
  int
    Order; ///< lattice steps per cell edge (the nodes' parametric coordinates * Order are integers)
  int Points;
};

// The map of the box: quadratic (curved) or affine.
void Phi(bool curved, const double X[3], double x[3])
{
  x[0] = X[0] + 0.1 * X[1];
  x[1] = X[1] + 0.05 * X[2];
  x[2] = X[2] - 0.08 * X[0];
  if (curved)
  {
    x[0] += 0.06 * X[1] * X[1] - 0.05 * X[2] * X[2];
    x[1] += 0.12 * X[0] * X[0] - 0.2 * X[0] + 0.04 * X[0] * X[2];
    x[2] += 0.1 * X[0] * X[1] - 0.05 * X[1] * X[1];
  }
}

vtkSmartPointer<vtkCell> NewCell(const CellKind& kind)
{
  vtkSmartPointer<vtkCell> cell;
  switch (kind.Type)
  {
    case VTK_TETRA:
      cell = vtkSmartPointer<vtkTetra>::New();
      break;
    case VTK_QUADRATIC_TETRA:
      cell = vtkSmartPointer<vtkQuadraticTetra>::New();
      break;
    case VTK_LAGRANGE_TETRAHEDRON:
      cell = vtkSmartPointer<vtkLagrangeTetra>::New();
      break;
    case VTK_HEXAHEDRON:
      cell = vtkSmartPointer<vtkHexahedron>::New();
      break;
    case VTK_QUADRATIC_HEXAHEDRON:
      cell = vtkSmartPointer<vtkQuadraticHexahedron>::New();
      break;
    case VTK_TRIQUADRATIC_HEXAHEDRON:
      cell = vtkSmartPointer<vtkTriQuadraticHexahedron>::New();
      break;
    default:
      cell = vtkSmartPointer<vtkLagrangeHexahedron>::New();
  }
  cell->GetPointIds()->SetNumberOfIds(kind.Points);
  cell->GetPoints()->SetNumberOfPoints(kind.Points);
  cell->Initialize(); // higher-order tetrahedra take their order from the number of points
  if (auto* hex = vtkHigherOrderHexahedron::SafeDownCast(cell))
    hex->SetUniformOrderFromNumPoints(kind.Points);
  return cell;
}

/// The box [0,L] in NX*NY*NZ hexahedra (or 6 Kuhn tetrahedra each) of `kind`, nodes at
/// phi of the reference positions given by VTK's parametric coordinates. Nodes are merged
/// by their reference position on the integer lattice of step 1/Order per cell.
vtkSmartPointer<vtkUnstructuredGrid> MakeMesh(const CellKind& kind, bool curved)
{
  vtkSmartPointer<vtkCell> proto = NewCell(kind);
  const double* pc = proto->GetParametricCoords();
  const bool tet = proto->GetNumberOfFaces() == 4;
  const int p = kind.Order;
  std::map<std::array<long, 3>, vtkIdType> ids;
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  auto node = [&](const std::array<long, 3>& I) {
    auto it = ids.find(I);
    if (it != ids.end())
      return it->second;
    const double X[3] = { L[0] * I[0] / (double(p) * NX), L[1] * I[1] / (double(p) * NY),
      L[2] * I[2] / (double(p) * NZ) };
    double x[3];
    Phi(curved, X, x);
    const vtkIdType id = points->InsertNextPoint(x);
    ids.emplace(I, id);
    return id;
  };
  auto grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
  grid->SetPoints(points);
  std::vector<vtkIdType> conn(kind.Points);
  for (int k = 0; k < NZ; ++k)
    for (int j = 0; j < NY; ++j)
      for (int i = 0; i < NX; ++i)
      {
        const long o[3] = { long(i) * p, long(j) * p, long(k) * p };
        if (!tet)
        {
          for (int a = 0; a < kind.Points; ++a)
          {
            std::array<long, 3> I;
            for (int d = 0; d < 3; ++d)
              I[d] = o[d] + std::lround(pc[3 * a + d] * p);
            conn[a] = node(I);
          }
          grid->InsertNextCell(kind.Type, kind.Points, conn.data());
          continue;
        }
        const int perms[6][3] = { { 0, 1, 2 }, { 0, 2, 1 }, { 1, 0, 2 }, { 1, 2, 0 }, { 2, 0, 1 },
          { 2, 1, 0 } };
        for (const auto& perm : perms)
        {
          // Kuhn tetrahedron: corners on the cube's lattice, walking one axis at a time.
          std::array<std::array<long, 3>, 4> c;
          c[0] = { o[0], o[1], o[2] };
          for (int s = 0; s < 3; ++s)
          {
            c[s + 1] = c[s];
            c[s + 1][perm[s]] += p;
          }
          // a left-handed corner order: swap two corners
          long e[3][3];
          for (int r = 0; r < 3; ++r)
            for (int d = 0; d < 3; ++d)
              e[r][d] = c[r + 1][d] - c[0][d];
          const long det = e[0][0] * (e[1][1] * e[2][2] - e[1][2] * e[2][1]) -
            e[0][1] * (e[1][0] * e[2][2] - e[1][2] * e[2][0]) +
            e[0][2] * (e[1][0] * e[2][1] - e[1][1] * e[2][0]);
          if (det < 0)
            std::swap(c[1], c[2]);
          for (int a = 0; a < kind.Points; ++a)
          {
            const double r = pc[3 * a], s = pc[3 * a + 1], t = pc[3 * a + 2];
            const long b[4] = { std::lround((1 - r - s - t) * p), std::lround(r * p),
              std::lround(s * p), std::lround(t * p) };
            std::array<long, 3> I = { 0, 0, 0 };
            for (int v = 0; v < 4; ++v)
              for (int d = 0; d < 3; ++d)
                I[d] += b[v] * c[v][d];
            for (int d = 0; d < 3; ++d)
              I[d] /= p; // corners are multiples of p: exact
            conn[a] = node(I);
          }
          grid->InsertNextCell(kind.Type, kind.Points, conn.data());
        }
      }
  return grid;
}

/// A sphere around the box's middle, half in and half out, with extra far points.
vtkSmartPointer<vtkPolyData> MakeSurface()
{
  vtkNew<vtkSphereSource> sphere;
  sphere->SetThetaResolution(14);
  sphere->SetPhiResolution(10);
  sphere->SetRadius(1.0);
  vtkNew<vtkTransform> t;
  t->Translate(1.1, 0.55, 0.45);
  t->Scale(0.95, 0.62, 0.6);
  vtkNew<vtkTransformPolyDataFilter> f;
  f->SetInputConnection(sphere->GetOutputPort());
  f->SetTransform(t);
  f->Update();
  auto out = vtkSmartPointer<vtkPolyData>::New();
  out->DeepCopy(f->GetOutput());
  return out;
}

/// Whether vtkEmbeddingCoordinatesFilter takes this cell type (the types the filter's
/// driver accepts; the others are checked on the reference alone).
bool FilterTakes(const CellKind& kind)
{
  return kind.Type == VTK_TETRA || kind.Type == VTK_QUADRATIC_TETRA ||
    kind.Type == VTK_LAGRANGE_TETRAHEDRON || kind.Type == VTK_LAGRANGE_HEXAHEDRON ||
    kind.Type == VTK_TRIQUADRATIC_HEXAHEDRON || kind.Type == VTK_QUADRATIC_HEXAHEDRON;
}
} // namespace

int main(int, char*[])
{
  const CellKind kinds[] = {
    { "tet4", VTK_TETRA, 1, 4 },
    { "tet10", VTK_QUADRATIC_TETRA, 2, 10 },
    { "lagrange-tet-1", VTK_LAGRANGE_TETRAHEDRON, 1, 4 },
    { "lagrange-tet-2", VTK_LAGRANGE_TETRAHEDRON, 2, 10 },
    { "lagrange-tet-3", VTK_LAGRANGE_TETRAHEDRON, 3, 20 },
    { "lagrange-tet-4", VTK_LAGRANGE_TETRAHEDRON, 4, 35 },
    { "hex8", VTK_HEXAHEDRON, 1, 8 },
    { "hex20", VTK_QUADRATIC_HEXAHEDRON, 2, 20 },
    { "hex27", VTK_TRIQUADRATIC_HEXAHEDRON, 2, 27 },
    { "lagrange-hex-1", VTK_LAGRANGE_HEXAHEDRON, 1, 8 },
    { "lagrange-hex-2", VTK_LAGRANGE_HEXAHEDRON, 2, 27 },
    { "lagrange-hex-3", VTK_LAGRANGE_HEXAHEDRON, 3, 64 },
  };
  vtkSmartPointer<vtkPolyData> surface = MakeSurface();
  const vtkIdType nv = surface->GetNumberOfPoints();

  for (int curved = 0; curved < 2; ++curved)
  {
    // The certified brute force on the tet10 (curved) or tet4 (affine) mesh.
    const CellKind& refKind = curved ? kinds[1] : kinds[0];
    vtkSmartPointer<vtkUnstructuredGrid> refMesh = MakeMesh(refKind, curved != 0);
    hoembed_exact::ExactMesh exact;
    {
      int npc = 0;
      std::vector<std::int64_t> conn = hoembed_test::MeshConnectivity(refMesh, npc);
      std::vector<double> pts = hoembed_test::PointsOf(refMesh);
      const std::string err = exact.Build(
        pts.data(), refMesh->GetNumberOfPoints(), conn.data(), refMesh->GetNumberOfCells(), npc);
      HOEMBED_CHECK(err.empty(), "exact mesh: %s", err.c_str());
    }
    const double diag = exact.Diagonal;
    std::vector<double> truth(nv);
    hoembed_exact::ExactOptions eo;
    hoembed_exact::ExactScratch scratch;
    int inside = 0;
    for (vtkIdType v = 0; v < nv; ++v)
    {
      hoembed_exact::ExactResult r;
      hoembed_exact::ExactDistance(exact, surface->GetPoint(v), eo, scratch, r);
      HOEMBED_CHECK(r.Inside || r.Upper - r.Lower <= 1e-11 * diag,
        "brute force not certified at %lld", static_cast<long long>(v));
      truth[v] = r.Distance();
      inside += r.Inside;
    }
    // the surface must test both sides
    HOEMBED_CHECK(inside > nv / 5 && inside < 4 * nv / 5, "%d of %lld points inside", inside,
      static_cast<long long>(nv));

    for (const CellKind& kind : kinds)
    {
      if (curved && kind.Order < 2)
        continue; // a linear cell cannot describe the curved box
      vtkSmartPointer<vtkUnstructuredGrid> mesh = MakeMesh(kind, curved != 0);
      hoembed_ceres::CeresOptions co;
      hoembed_ceres::CeresMesh cm;
      const std::string err = cm.Build(mesh, co);
      HOEMBED_CHECK(err.empty(), "%s: %s", kind.Name, err.c_str());
      const std::size_t boundaryFaces = (kind.Points == 4 || kind.Type == VTK_QUADRATIC_TETRA ||
                                          kind.Type == VTK_LAGRANGE_TETRAHEDRON)
        ? 4u * (NX * NY + NY * NZ + NX * NZ)
        : 2u * (NX * NY + NY * NZ + NX * NZ);
      HOEMBED_CHECK(cm.Faces.size() == boundaryFaces, "%s: %zu boundary faces, expected %zu",
        kind.Name, cm.Faces.size(), boundaryFaces);
      std::vector<double> ref(nv);
      double worst = 0.0;
      long faces = 0, iterations = 0;
      for (vtkIdType v = 0; v < nv; ++v)
      {
        hoembed_ceres::CeresResult r;
        hoembed_ceres::CeresDistance(cm, surface->GetPoint(v), co, r);
        ref[v] = r.Distance;
        faces += r.FacesSolved;
        iterations += r.Iterations;
        if (std::fabs(r.Distance - truth[v]) / diag > worst)
        {
          worst = std::fabs(r.Distance - truth[v]) / diag;
          if (worst > 1e-10)
            std::printf(
              "  point %lld: Ceres %.17g (inside %d, %d cells, %d faces) brute force %.17g\n",
              static_cast<long long>(v), r.Distance, int(r.Inside), r.CellsSolved, r.FacesSolved,
              truth[v]);
        }
      }
      std::printf("%-16s %s: Ceres vs certified brute force, max |diff| %.2e of the diagonal "
                  "(%lld points, %.1f faces and %.0f LM iterations per point)\n",
        kind.Name, curved ? "curved" : "affine", worst, static_cast<long long>(nv),
        double(faces) / nv, double(iterations) / nv);
      HOEMBED_CHECK(
        worst <= 1e-10, "%s: Ceres reference off the brute force by %.3e", kind.Name, worst);
      if (!FilterTakes(kind))
        continue;
      vtkSmartPointer<vtkPolyData> out = RunEmbeddingFilter(surface, mesh);
      auto* closest =
        vtkDoubleArray::SafeDownCast(out->GetPointData()->GetArray("EmbeddingClosestDistance"));
      HOEMBED_CHECK(closest, "%s: no EmbeddingClosestDistance", kind.Name);
      if (!closest)
        continue;
      double worstFilter = 0.0;
      for (vtkIdType v = 0; v < nv; ++v)
        worstFilter = std::max(worstFilter, std::fabs(closest->GetValue(v) - ref[v]) / diag);
      std::printf("%-16s %s: filter vs Ceres, max |diff| %.2e of the diagonal\n", kind.Name,
        curved ? "curved" : "affine", worstFilter);
      HOEMBED_CHECK(
        worstFilter <= 1e-10, "%s: filter off the Ceres reference by %.3e", kind.Name, worstFilter);
    }
  }
  return hoembed_test::Report("TestCeresReference");
}
