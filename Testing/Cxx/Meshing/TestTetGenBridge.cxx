// hoembed::RunTetGen's bounds (work bound, abort, point ids) and vtkTet10Mesher's checks
// before any VTK filter sees its input (point ids, NaN properties, the element limit).
#include "hoembedTestUtilities.h"

#include "hoembedTetGenBridge.h"
#include "vtkTet10Mesher.h"

#include "vtkCellArray.h"
#include "vtkCommand.h"
#include "vtkExecutive.h"
#include "vtkNew.h"
#include "vtkPolyData.h"
#include "vtkSphereSource.h"
#include "vtkUnstructuredGrid.h"

#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace
{
class ErrorCatcher : public vtkCommand
{
public:
  static ErrorCatcher* New()
  {
    return new ErrorCatcher;
  }
  void Execute(vtkObject*, unsigned long, void* data) override
  {
    this->Text += data ? static_cast<const char*>(data) : "";
  }
  std::string Text;
};

vtkSmartPointer<vtkPolyData> Sphere(int res)
{
  vtkNew<vtkSphereSource> s;
  s->SetThetaResolution(res);
  s->SetPhiResolution(res);
  s->Update();
  return s->GetOutput();
}

void ToArrays(vtkPolyData* pd, std::vector<double>& pts, std::vector<std::int64_t>& tris)
{
  pts.resize(3 * pd->GetNumberOfPoints());
  for (vtkIdType i = 0; i < pd->GetNumberOfPoints(); ++i)
    pd->GetPoint(i, &pts[3 * i]);
  vtkIdType n;
  const vtkIdType* ids;
  tris.clear();
  for (pd->GetPolys()->InitTraversal(); pd->GetPolys()->GetNextCell(n, ids);)
    tris.insert(tris.end(), ids, ids + 3);
}

// Run the mesher; return its error text ("" on success).
std::string Mesh(vtkTet10Mesher* mesher, vtkPolyData* input)
{
  vtkNew<ErrorCatcher> catcher;
  const unsigned long a = mesher->AddObserver(vtkCommand::ErrorEvent, catcher);
  const unsigned long b = mesher->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, catcher);
  mesher->SetInputData(input);
  mesher->Modified();
  mesher->Update();
  mesher->RemoveObserver(a);
  mesher->GetExecutive()->RemoveObserver(b);
  return catcher->Text;
}

void ExpectMeshError(vtkTet10Mesher* mesher, vtkPolyData* input, const char* what)
{
  const std::string text = Mesh(mesher, input);
  HOEMBED_CHECK(text.find(what) != std::string::npos, "expected '%s' in '%s'", what, text.c_str());
  HOEMBED_CHECK(mesher->GetOutput()->GetNumberOfCells() == 0, "output not empty after '%s'", what);
}
} // namespace

int main(int, char*[])
{
  std::vector<double> pts;
  std::vector<std::int64_t> tris;
  ToArrays(Sphere(24), pts, tris);
  hoembed::TetGenParameters params;
  params.MaxVolume = 4.0 / 3.0 * 3.14159 * 0.125 / 2000.0; // about 2000 tets

  // The checkpoint is live: TetGen's work is counted (each final tet was created at least
  // once, and flips create more).
  HOEMBED_CHECK(hoembed::TetGenWorkIsBounded(), "TetGen built without the checkpoint patch");
  hoembed::TetGenResult ok = hoembed::RunTetGen(pts, tris, params);
  const size_t nTets = ok.Tets.size() / 4;
  HOEMBED_CHECK(
    ok.Error.empty() && nTets > 500, "reference run: '%s', %zu tets", ok.Error.c_str(), nTets);
  HOEMBED_CHECK(ok.CreatedTetrahedra >= nTets && !ok.Stopped, "created %llu for %zu tets",
    static_cast<unsigned long long>(ok.CreatedTetrahedra), nTets);

  // The work bound stops TetGen with a clear error; a bound above the work it needs does not.
  hoembed::TetGenParameters bounded = params;
  bounded.MaxCreatedTetrahedra = static_cast<double>(ok.CreatedTetrahedra / 2);
  hoembed::TetGenResult stopped = hoembed::RunTetGen(pts, tris, bounded);
  HOEMBED_CHECK(stopped.Stopped && stopped.Error.find("work bound") != std::string::npos &&
      stopped.Tets.empty() && stopped.Points.empty(),
    "work bound: stopped %d, error '%s'", stopped.Stopped, stopped.Error.c_str());
  HOEMBED_CHECK(stopped.CreatedTetrahedra == ok.CreatedTetrahedra / 2 + 1,
    "stopped after %llu tetrahedra, bound %llu",
    static_cast<unsigned long long>(stopped.CreatedTetrahedra),
    static_cast<unsigned long long>(ok.CreatedTetrahedra / 2));
  bounded.MaxCreatedTetrahedra = static_cast<double>(ok.CreatedTetrahedra);
  hoembed::TetGenResult same = hoembed::RunTetGen(pts, tris, bounded);
  HOEMBED_CHECK(same.Error.empty() && same.Tets == ok.Tets, "bound at the work needed: '%s'",
    same.Error.c_str());

  // An abort callback stops TetGen (polled every 4096 tetrahedra); outside its scope a run
  // is unaffected, and scopes nest.
  {
    int polls = 0;
    hoembed::ScopedTetGenAbort outer([&polls]() {
      ++polls;
      return false;
    });
    {
      hoembed::ScopedTetGenAbort inner([]() { return true; });
      hoembed::TetGenResult aborted = hoembed::RunTetGen(pts, tris, params);
      HOEMBED_CHECK(aborted.Stopped && aborted.Error.find("aborted") != std::string::npos &&
          aborted.CreatedTetrahedra == 4096,
        "abort: '%s' after %llu", aborted.Error.c_str(),
        static_cast<unsigned long long>(aborted.CreatedTetrahedra));
    }
    hoembed::TetGenResult again = hoembed::RunTetGen(pts, tris, params);
    HOEMBED_CHECK(again.Error.empty() && again.Tets == ok.Tets, "after the inner scope: '%s'",
      again.Error.c_str());
    HOEMBED_CHECK(polls == static_cast<int>(ok.CreatedTetrahedra / 4096), "%d polls for %llu",
      polls, static_cast<unsigned long long>(ok.CreatedTetrahedra));
  }

  // Point ids out of range are refused before TetGen reads them.
  {
    std::vector<std::int64_t> bad = tris;
    bad[7] = static_cast<std::int64_t>(pts.size() / 3);
    hoembed::TetGenResult r = hoembed::RunTetGen(pts, bad, params);
    HOEMBED_CHECK(
      r.Error.find("does not exist") != std::string::npos, "bad id: '%s'", r.Error.c_str());
    bad[7] = -1;
    r = hoembed::RunTetGen(pts, bad, params);
    HOEMBED_CHECK(
      r.Error.find("does not exist") != std::string::npos, "negative id: '%s'", r.Error.c_str());
  }

  // vtkTet10Mesher: point ids, NaN properties, the element limit.
  vtkSmartPointer<vtkPolyData> sphere = Sphere(24);
  {
    vtkNew<vtkTet10Mesher> mesher;
    mesher->SetTargetNumberOfElements(200);
    for (const vtkIdType badId : { sphere->GetNumberOfPoints(), vtkIdType(-1), vtkIdType(1) << 40 })
    {
      vtkNew<vtkPolyData> copy;
      copy->DeepCopy(sphere);
      vtkNew<vtkCellArray> polys;
      polys->DeepCopy(copy->GetPolys());
      polys->GetConnectivityArray()->SetComponent(10, 0, static_cast<double>(badId));
      copy->SetPolys(polys);
      ExpectMeshError(mesher, copy, "names point id");
    }
    const double nan = std::numeric_limits<double>::quiet_NaN();
    mesher->SetRadiusEdgeRatio(nan);
    ExpectMeshError(mesher, sphere, "RadiusEdgeRatio must be in [1.05, 100] (got nan).");
    mesher->SetRadiusEdgeRatio(1.5);
    mesher->SetMinDihedralAngle(nan);
    ExpectMeshError(mesher, sphere, "MinDihedralAngle must be in [0, 30] (got nan).");
    mesher->SetMinDihedralAngle(10.0);
    mesher->SetTargetEdgeLength(nan);
    ExpectMeshError(mesher, sphere, "TargetEdgeLength must be >= 0 (got nan).");
    mesher->SetTargetEdgeLength(0.0);

    mesher->SetTargetNumberOfElements(10000000);
    ExpectMeshError(mesher, sphere, "about 10000000 elements");
    mesher->SetTargetNumberOfElements(200);
    mesher->SetTargetEdgeLength(1e-4);
    ExpectMeshError(mesher, sphere, "raise MaximumNumberOfElements");
    mesher->SetTargetEdgeLength(0.0);
    mesher->SetMaximumNumberOfElements(100);
    ExpectMeshError(mesher, sphere, "MaximumNumberOfElements = 100");
    mesher->SetMaximumNumberOfElements(1000);
    const std::string text = Mesh(mesher, sphere);
    HOEMBED_CHECK(text.empty() && mesher->GetOutput()->GetNumberOfCells() > 0,
      "a mesh within the raised limit failed: '%s'", text.c_str());
  }
  return hoembed_test::Report("TestTetGenBridge");
}
