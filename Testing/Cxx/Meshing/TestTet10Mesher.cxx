// vtkTet10Mesher: generated shapes (sphere, bumpy blob), validity checked independently
// (VTK's quadratic tetra Jacobian at sample points and vtkCellValidator), boundary nodes
// on the surface (vtkCellLocator), curved volume closer than straight (vtkMassProperties),
// element order 1, bad input.
#include "hoembedSpatialOrder.h"
#include "hoembedTestUtilities.h"

#include "vtkTet10Mesher.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkCellLocator.h"
#include "vtkCellValidator.h"
#include "vtkCommand.h"
#include "vtkExecutive.h"
#include "vtkDataArray.h"
#include "vtkFieldData.h"
#include "vtkGenericCell.h"
#include "vtkIdList.h"
#include "vtkMassProperties.h"
#include "vtkMath.h"
#include "vtkMeshQuality.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkQuadraticTetra.h"
#include "vtkSphereSource.h"
#include "vtkTetra.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnstructuredGrid.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <vector>

namespace
{
struct ErrorCatcher : public vtkCommand
{
  static ErrorCatcher* New()
  {
    return new ErrorCatcher;
  }
  void Execute(vtkObject*, unsigned long, void* data) override
  {
    this->Text += static_cast<const char*>(data);
  }
  std::string Text;
};

vtkSmartPointer<vtkPolyData> Sphere(bool bumpy)
{
  vtkNew<vtkSphereSource> src;
  src->SetRadius(1.0);
  src->SetThetaResolution(140);
  src->SetPhiResolution(140);
  src->Update();
  auto pd = vtkSmartPointer<vtkPolyData>::New();
  pd->DeepCopy(src->GetOutput());
  if (bumpy)
  {
    for (vtkIdType i = 0; i < pd->GetNumberOfPoints(); ++i)
    {
      double x[3];
      pd->GetPoint(i, x);
      vtkMath::Normalize(x);
      const double r =
        1.0 + 0.12 * std::sin(5 * x[0]) * std::cos(4 * x[1]) + 0.05 * std::sin(9 * x[2]);
      pd->GetPoints()->SetPoint(i, r * x[0], r * x[1], r * x[2]);
    }
  }
  return pd;
}

// det J of a quadratic tetra from VTK's own derivatives.
double VtkDetJ(vtkUnstructuredGrid* g, vtkIdType c, const double pc[3])
{
  double derivs[30];
  vtkQuadraticTetra::InterpolationDerivs(pc, derivs);
  vtkIdType npts;
  const vtkIdType* ids;
  g->GetCellPoints(c, npts, ids);
  double J[3][3] = { { 0 } };
  for (int n = 0; n < 10; ++n)
  {
    double x[3];
    g->GetPoint(ids[n], x);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        J[i][j] += x[i] * derivs[10 * j + n];
  }
  return vtkMath::Determinant3x3(J);
}

double Volume(vtkPolyData* pd)
{
  vtkNew<vtkMassProperties> mp;
  mp->SetInputData(pd);
  mp->Update();
  return mp->GetVolume();
}

// `target`: CurvedQualityTarget (< 0: the default). With 0 the curving puts nearly every
// boundary mid-edge node on the surface; with a target it blends some back (quality for
// fidelity), never a cell below min(target, its straight quality).
void CheckShape(const char* name, vtkPolyData* surface, double target)
{
  vtkNew<vtkTet10Mesher> mesher;
  mesher->SetInputData(surface);
  mesher->SetTargetNumberOfElements(1000);
  if (target >= 0.0)
    mesher->SetCurvedQualityTarget(target);
  target = mesher->GetCurvedQualityTarget();
  const double floor = std::max(0.05, target);
  mesher->Update();
  vtkUnstructuredGrid* g = mesher->GetOutput();
  const vtkIdType nc = g->GetNumberOfCells();
  HOEMBED_CHECK(nc > 500 && nc < 2000, "%s: %lld cells for a target of 1000", name, (long long)nc);

  // Memory order: the output is already in hoembed::SpatialOrder (ordering it again
  // changes nothing: cells along the Morton curve, nodes by first use).
  {
    int npc = 0;
    const std::vector<std::int64_t> conn = hoembed_test::MeshConnectivity(g, npc);
    std::vector<std::int64_t> cellOrder, pointOrder;
    hoembed::SpatialOrder(hoembed_test::PointsOf(g), conn, npc, cellOrder, pointOrder);
    std::int64_t movedCells = 0, movedPoints = 0;
    for (std::int64_t k = 0; k < static_cast<std::int64_t>(cellOrder.size()); ++k)
      movedCells += cellOrder[k] != k;
    for (std::int64_t k = 0; k < static_cast<std::int64_t>(pointOrder.size()); ++k)
      movedPoints += pointOrder[k] != k;
    HOEMBED_CHECK(movedCells == 0 && movedPoints == 0,
      "%s: output not in memory order (%lld cells, %lld nodes move)", name, (long long)movedCells,
      (long long)movedPoints);
  }

  // Validity: VTK's Jacobian at the corners, the 20 cubic lattice points and random points.
  vtkMath::RandomSeed(7);
  vtkIdType invalid = 0;
  for (vtkIdType c = 0; c < nc; ++c)
  {
    HOEMBED_CHECK(g->GetCellType(c) == VTK_QUADRATIC_TETRA, "%s: cell type", name);
    for (int s = 0; s < 60; ++s)
    {
      double pc[3];
      if (s < 20)
      {
        int k = s, i = 0, j = 0, l = 0;
        // enumerate (i, j, l) with i + j + l <= 3
        for (i = 0; i <= 3; ++i)
          for (j = 0; j <= 3 - i; ++j)
            for (l = 0; l <= 3 - i - j; ++l)
              if (k-- == 0)
                goto found;
      found:
        pc[0] = i / 3.0;
        pc[1] = j / 3.0;
        pc[2] = l / 3.0;
      }
      else
      {
        do
        {
          pc[0] = vtkMath::Random();
          pc[1] = vtkMath::Random();
          pc[2] = vtkMath::Random();
        } while (pc[0] + pc[1] + pc[2] > 1.0);
      }
      if (!(VtkDetJ(g, c, pc) > 0.0))
      {
        ++invalid;
        break;
      }
    }
  }
  HOEMBED_CHECK(invalid == 0, "%s: %lld cells with det J <= 0", name, (long long)invalid);
  vtkNew<vtkCellValidator> validator;
  validator->SetInputData(g);
  validator->Update();
  vtkDataArray* states = vtkUnstructuredGrid::SafeDownCast(validator->GetOutput())
                           ->GetCellData()
                           ->GetArray("ValidityState");
  vtkIdType flagged = 0;
  for (vtkIdType c = 0; c < nc; ++c)
    flagged += states->GetTuple1(c) != 0 ? 1 : 0;
  HOEMBED_CHECK(
    flagged == 0, "%s: %lld cells flagged by vtkCellValidator", name, (long long)flagged);
  vtkDataArray* q = g->GetCellData()->GetArray("MinScaledJacobian");
  HOEMBED_CHECK(q && q->GetRange()[0] > 0.0, "%s: MinScaledJacobian", name);
  // The quality floor (MinimumQuality, default 0.05): every cell at the floor, or as good
  // as its straight shape (VTK's own tet scaled Jacobian of its corners) where that is
  // worse; the field data's count and distribution agree with the cells.
  if (q)
  {
    std::vector<double> all(nc);
    vtkIdType below = 0, failing = 0;
    vtkNew<vtkTetra> tet;
    for (vtkIdType c = 0; c < nc; ++c)
    {
      all[c] = q->GetTuple1(c);
      below += all[c] < 0.05 ? 1 : 0;
      vtkIdType npts;
      const vtkIdType* ids;
      g->GetCellPoints(c, npts, ids);
      for (int a = 0; a < 4; ++a)
      {
        tet->GetPoints()->SetPoint(a, g->GetPoint(ids[a]));
        tet->GetPointIds()->SetId(a, a);
      }
      const double straight = vtkMeshQuality::TetScaledJacobian(tet);
      failing += all[c] >= std::min(floor, 0.999 * straight) - 1e-9 ? 0 : 1;
    }
    HOEMBED_CHECK(failing == 0,
      "%s (target %g): %lld cells below the floor and their straight shape", name, target,
      (long long)failing);
    std::sort(all.begin(), all.end());
    vtkDataArray* poor = g->GetFieldData()->GetArray("PoorElementCount");
    vtkDataArray* quantiles = g->GetFieldData()->GetArray("MinScaledJacobianQuantiles");
    HOEMBED_CHECK(poor && poor->GetTuple1(0) == static_cast<double>(below),
      "%s: PoorElementCount %g, %lld cells below 0.05", name, poor ? poor->GetTuple1(0) : -1.0,
      (long long)below);
    HOEMBED_CHECK(quantiles && quantiles->GetNumberOfComponents() == 3 &&
        quantiles->GetComponent(0, 0) == all[0] &&
        quantiles->GetComponent(0, 2) == all[(all.size() - 1) / 2],
      "%s: MinScaledJacobianQuantiles", name);
    std::printf("%s: min scaled Jacobian %g, median %g, %lld below 0.05\n", name, all[0],
      all[(all.size() - 1) / 2], (long long)below);
  }

  // Boundary mid-edge nodes on the surface: boundary faces are faces of one cell.
  std::map<std::set<vtkIdType>, int> faces;
  static const int F[4][3] = { { 0, 1, 3 }, { 1, 2, 3 }, { 2, 0, 3 }, { 0, 2, 1 } };
  static const int E[6][2] = { { 0, 1 }, { 1, 2 }, { 2, 0 }, { 0, 3 }, { 1, 3 }, { 2, 3 } };
  for (vtkIdType c = 0; c < nc; ++c)
  {
    vtkIdType npts;
    const vtkIdType* ids;
    g->GetCellPoints(c, npts, ids);
    for (auto& f : F)
      faces[{ ids[f[0]], ids[f[1]], ids[f[2]] }]++;
  }
  std::set<vtkIdType> mids;
  for (vtkIdType c = 0; c < nc; ++c)
  {
    vtkIdType npts;
    const vtkIdType* ids;
    g->GetCellPoints(c, npts, ids);
    for (auto& f : F)
    {
      if (faces[{ ids[f[0]], ids[f[1]], ids[f[2]] }] != 1)
        continue;
      for (int e = 0; e < 6; ++e)
      {
        const std::set<int> fs = { f[0], f[1], f[2] };
        if (fs.count(E[e][0]) && fs.count(E[e][1]))
          mids.insert(ids[4 + e]);
      }
    }
  }
  vtkNew<vtkCellLocator> loc;
  loc->SetDataSet(surface);
  loc->BuildLocator();
  const double diag = surface->GetLength();
  vtkIdType on = 0;
  for (vtkIdType m : mids)
  {
    double x[3], cp[3], d2;
    vtkIdType cellId;
    int subId;
    g->GetPoint(m, x);
    loc->FindClosestPoint(x, cp, cellId, subId, d2);
    on += std::sqrt(d2) <= 1e-6 * diag ? 1 : 0;
  }
  const double frac = static_cast<double>(on) / static_cast<double>(mids.size());
  HOEMBED_CHECK(frac >= (target > 0.0 ? 0.85 : 0.95),
    "%s (target %g): %.3f of boundary mid-edge nodes on the surface", name, target, frac);
  vtkDataArray* relaxed = g->GetFieldData()->GetArray("RelaxedNodeCount");
  HOEMBED_CHECK(relaxed && relaxed->GetTuple1(0) >= static_cast<double>(mids.size() - on),
    "%s: RelaxedNodeCount", name);

  // Volume: curved (quadrature of det J, VTK derivatives, degree-7 conical rule) vs straight.
  static const double g4[4] = { -0.8611363115940526, -0.3399810435848563, 0.3399810435848563,
    0.8611363115940526 };
  static const double w4[4] = { 0.3478548451374538, 0.6521451548625461, 0.6521451548625461,
    0.3478548451374538 };
  double vCurved = 0, vStraight = 0;
  for (vtkIdType c = 0; c < nc; ++c)
  {
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j)
        for (int k = 0; k < 4; ++k)
        {
          const double a = (g4[i] + 1) / 2, b = (g4[j] + 1) / 2, cc = (g4[k] + 1) / 2;
          const double pc[3] = { a, b * (1 - a), cc * (1 - a) * (1 - b) };
          const double w = w4[i] * w4[j] * w4[k] / 8.0 * (1 - a) * (1 - a) * (1 - b);
          vCurved += w * VtkDetJ(g, c, pc);
        }
    vtkIdType npts;
    const vtkIdType* ids;
    g->GetCellPoints(c, npts, ids);
    double x[4][3], e[3][3];
    for (int a = 0; a < 4; ++a)
      g->GetPoint(ids[a], x[a]);
    for (int r = 0; r < 3; ++r)
      for (int d = 0; d < 3; ++d)
        e[r][d] = x[r + 1][d] - x[0][d];
    vStraight += vtkMath::Determinant3x3(e) / 6.0;
  }
  const double vFine = Volume(surface);
  HOEMBED_CHECK(std::fabs(vCurved - vFine) < std::fabs(vStraight - vFine),
    "%s: curved volume %g not closer to %g than straight %g", name, vCurved, vFine, vStraight);
  std::printf(
    "%s (target %g): %lld cells, %.4f of boundary mid-edge nodes on the surface, volume error "
    "curved %.2e straight %.2e\n",
    name, target, (long long)nc, frac, (vCurved - vFine) / vFine, (vStraight - vFine) / vFine);
}

std::string ExpectError(vtkPolyData* input, const char* what)
{
  vtkNew<vtkTet10Mesher> mesher;
  vtkNew<ErrorCatcher> catcher;
  mesher->AddObserver(vtkCommand::ErrorEvent, catcher);
  mesher->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, catcher);
  mesher->SetInputData(input);
  mesher->SetTargetNumberOfElements(200);
  mesher->Update();
  HOEMBED_CHECK(catcher->Text.find(what) != std::string::npos, "expected '%s' in '%s'", what,
    catcher->Text.c_str());
  HOEMBED_CHECK(mesher->GetOutput()->GetNumberOfCells() == 0, "output not empty after '%s'", what);
  return catcher->Text;
}
} // namespace

int main(int, char*[])
{
  for (double target : { -1.0, 0.0 })
  {
    CheckShape("sphere", Sphere(false), target);
    CheckShape("bumpy", Sphere(true), target);
  }

  // Element order 1: tet4 on the same corner nodes.
  {
    vtkSmartPointer<vtkPolyData> s = Sphere(false);
    vtkNew<vtkTet10Mesher> m2, m1;
    m2->SetInputData(s);
    m2->SetTargetNumberOfElements(400);
    m1->SetInputData(s);
    m1->SetTargetNumberOfElements(400);
    m1->SetElementOrder(1);
    m2->Update();
    m1->Update();
    HOEMBED_CHECK(m1->GetOutput()->GetNumberOfCells() == m2->GetOutput()->GetNumberOfCells(),
      "order 1 and 2 have different cell counts");
    HOEMBED_CHECK(m1->GetOutput()->GetCellType(0) == VTK_TETRA, "order 1 cell type");
    std::ostringstream os;
    m1->Print(os);
    HOEMBED_CHECK(os.str().find("ElementOrder: 1") != std::string::npos &&
        os.str().find("CurveBoundary: On") != std::string::npos,
      "PrintSelf: %s", os.str().c_str());
  }

  // Bad input.
  {
    vtkNew<vtkPolyData> empty;
    ExpectError(empty, "empty");
    vtkSmartPointer<vtkPolyData> nan = Sphere(false);
    nan->GetPoints()->SetPoint(5, std::numeric_limits<double>::quiet_NaN(), 0, 0);
    ExpectError(nan, "non-finite");
    // Open and non-manifold surfaces are meshed through the envelope: TestSurfaceWrap.
    vtkNew<vtkPoints> pts;
    pts->InsertNextPoint(0, 0, 0);
    pts->InsertNextPoint(1, 0, 0);
    vtkNew<vtkPolyData> linesOnly;
    linesOnly->SetPoints(pts);
    vtkNew<vtkCellArray> lines;
    const vtkIdType L[2] = { 0, 1 };
    lines->InsertNextCell(2, L);
    linesOnly->SetLines(lines);
    ExpectError(linesOnly, "no polygons");
  }
  return hoembed_test::Report("TestTet10Mesher");
}
