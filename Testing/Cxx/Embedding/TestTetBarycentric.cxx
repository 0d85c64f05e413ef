// hoembedTetBarycentric.h (the straight tet plus edge bumps that may exclude a cell)
// against the brute-force distance to the element.
#include "hoembedQuadraticMapTestUtilities.h"
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
  HOEMBED_CHECK(wrong == 0,
    "TetBarycentricExcludes: %d exclusions with a point of the element "
    "within reach",
    wrong);
  HOEMBED_CHECK(excluded > tried / 6 && excludedNear > triedNear / 10,
    "TetBarycentricExcludes: only %d of %d excluded, %d of %d near an edge (test setup)", excluded,
    tried, excludedNear, triedNear);
  // a degenerate (flat) straight tet gives a form that excludes nothing
  const double flat[12] = { 0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0 };
  hoembed::TetBarycentricForm form;
  hoembed::MakeTetBarycentricForm(flat, 4, form);
  const double far[3] = { 5, 5, 5 };
  HOEMBED_CHECK(!hoembed::TetBarycentricExcludes(form, far, 0.0),
    "TetBarycentricExcludes: a flat tet's form excluded a point");
  std::printf("straight tet + bumps: %d of %d (point, reach) pairs excluded (%d of %d near a "
              "curved edge), %d wrongly\n",
    excluded, tried, excludedNear, triedNear, wrong);
}

} // namespace

int main(int, char*[])
{
  TestTetBarycentricExcludes();
  return hoembed_test::Report("TestTetBarycentric");
}
