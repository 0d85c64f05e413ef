// The hexahedra of hoembedLagrangeHex.h against VTK's own cells, which nobody here wrote:
//  - node positions: GetParametricCoords of vtkLagrangeHexahedron (orders 1-3),
//    vtkTriQuadraticHexahedron and vtkQuadraticHexahedron, node for node;
//  - shape functions and their derivatives: InterpolateFunctions / InterpolateDerivs
//    (vtkLagrangeHexahedron writes dN_i/dr_k at i * 3 + k, the other two at k * n + i);
//  - the tensor form: x and J of a curved cell against VTK's EvaluateLocation and the
//    derivatives through VTK's, the Hessian against central differences of J; the
//    20-node cell's tensor form (Q_2 at 27 points) equals its serendipity map everywhere;
//  - validity: a curved valid cell is proven, a cell folded by one moved node refused.
#include "hoembedLagrangeHex.h"
#include "hoembedTestUtilities.h"

#include "vtkLagrangeHexahedron.h"
#include "vtkNew.h"
#include "vtkPoints.h"
#include "vtkQuadraticHexahedron.h"
#include "vtkTriQuadraticHexahedron.h"

#include <cmath>
#include <random>
#include <vector>

using namespace hoembed_test;

namespace
{
void Check(vtkNonLinearCell* cell, int type, int n, bool interleaved)
{
  const hoembed::LagrangeHexBasis* b = hoembed::GetLagrangeHexBasis(type, n);
  HOEMBED_CHECK(b != nullptr, "type %d, %d nodes: no basis", type, n);
  if (!b)
    return;
  cell->GetPointIds()->SetNumberOfIds(n);
  cell->GetPoints()->SetNumberOfPoints(n);
  std::mt19937 rng(11 + n);
  std::uniform_real_distribution<double> jitter(-0.04, 0.04), unit(0.0, 1.0);
  const double* vpc = cell->GetParametricCoords();
  std::vector<double> x(3 * n);
  for (int k = 0; k < n; ++k)
  {
    double pc[3];
    hoembed::LagrangeHexNodeParametric(*b, k, pc);
    for (int d = 0; d < 3; ++d)
      HOEMBED_CHECK(std::abs(pc[d] - vpc[3 * k + d]) < 1e-14, "type %d n %d node %d: %g vs VTK %g",
        type, n, k, pc[d], vpc[3 * k + d]);
    const double straight[3] = { 1.0 + 2 * pc[0] + 0.3 * pc[1], 0.5 * pc[0] + 1.7 * pc[1],
      0.2 * pc[1] + 1.5 * pc[2] + 0.1 * pc[0] };
    for (int d = 0; d < 3; ++d)
      x[3 * k + d] = straight[d] + (n > 8 ? jitter(rng) : 0.0);
    cell->GetPoints()->SetPoint(k, x.data() + 3 * k);
    cell->GetPointIds()->SetId(k, k);
  }
  std::vector<double> t(3 * b->TensorNodes), N(n), w(n), dw(3 * n);
  hoembed::LagrangeHexToTensor(*b, x.data(), t.data());
  for (int s = 0; s < 30; ++s)
  {
    double pc[3] = { unit(rng), unit(rng), unit(rng) };
    if (s < 8) // the corners too
      for (int d = 0; d < 3; ++d)
        pc[d] = (s >> d) & 1;
    hoembed::LagrangeHexShape(*b, pc, N.data());
    cell->InterpolateFunctions(pc, w.data());
    cell->InterpolateDerivs(pc, dw.data());
    for (int k = 0; k < n; ++k)
      HOEMBED_CHECK(
        std::abs(w[k] - N[k]) < 1e-12, "type %d n %d: N_%d %g vs VTK %g", type, n, k, N[k], w[k]);
    double vx[3], hx[3], J[3][3], H[3][3][3];
    int sub = 0;
    cell->EvaluateLocation(sub, pc, vx, w.data());
    hoembed::EvaluateTensorHex(b->Order, t.data(), pc, hx, J, H);
    for (int d = 0; d < 3; ++d)
      HOEMBED_CHECK(std::abs(vx[d] - hx[d]) < 1e-12, "type %d n %d: x differs from VTK's by %g",
        type, n, vx[d] - hx[d]);
    // J through VTK's derivatives
    for (int a = 0; a < 3; ++a)
      for (int d = 0; d < 3; ++d)
      {
        double v = 0.0;
        for (int k = 0; k < n; ++k)
          v += (interleaved ? dw[3 * k + a] : dw[a * n + k]) * x[3 * k + d];
        HOEMBED_CHECK(std::abs(v - J[a][d]) < 1e-11, "type %d n %d: dx%d/dr%d %g vs VTK %g", type,
          n, d, a, J[a][d], v);
      }
    // the Hessian against central differences of J
    const double h = 1e-6;
    for (int a = 0; a < 3; ++a)
    {
      double pp[3] = { pc[0], pc[1], pc[2] }, pm[3] = { pc[0], pc[1], pc[2] };
      pp[a] += h;
      pm[a] -= h;
      double xp[3], xm[3], Jp[3][3], Jm[3][3];
      hoembed::EvaluateTensorHex(b->Order, t.data(), pp, xp, Jp);
      hoembed::EvaluateTensorHex(b->Order, t.data(), pm, xm, Jm);
      for (int bb = 0; bb < 3; ++bb)
        for (int d = 0; d < 3; ++d)
          HOEMBED_CHECK(std::abs((Jp[bb][d] - Jm[bb][d]) / (2 * h) - H[a][bb][d]) < 1e-6,
            "type %d n %d: H[%d][%d][%d] %g vs %g", type, n, a, bb, d, H[a][bb][d],
            (Jp[bb][d] - Jm[bb][d]) / (2 * h));
    }
  }
  HOEMBED_CHECK(
    hoembed::LagrangeHexIsValid(*b, t.data()), "type %d n %d: valid cell refused", type, n);
  // a node pushed through the opposite face: folded
  std::vector<double> folded = x;
  const int k = n > 8 ? 8 : 0; // an edge node (a corner for the trilinear cell)
  folded[3 * k + 1] += 3.0;
  folded[3 * k + 2] += 3.0;
  hoembed::LagrangeHexToTensor(*b, folded.data(), t.data());
  HOEMBED_CHECK(
    !hoembed::LagrangeHexIsValid(*b, t.data()), "type %d n %d: folded cell accepted", type, n);
}
} // namespace

int main(int, char*[])
{
  for (int p = 1; p <= 3; ++p)
  {
    vtkNew<vtkLagrangeHexahedron> cell;
    const int n = (p + 1) * (p + 1) * (p + 1);
    cell->SetUniformOrderFromNumPoints(n);
    cell->GetPointIds()->SetNumberOfIds(n);
    cell->GetPoints()->SetNumberOfPoints(n);
    cell->Initialize();
    Check(cell, hoembed::LagrangeHexahedronCellType, n, true);
  }
  {
    vtkNew<vtkTriQuadraticHexahedron> cell;
    Check(cell, hoembed::TriQuadraticHexahedronCellType, 27, false);
  }
  {
    vtkNew<vtkQuadraticHexahedron> cell;
    Check(cell, hoembed::QuadraticHexahedronCellType, 20, false);
  }
  HOEMBED_CHECK(hoembed::GetLagrangeHexBasis(hoembed::LagrangeHexahedronCellType, 125) == nullptr,
    "order 4 accepted");
  HOEMBED_CHECK(hoembed::GetLagrangeHexBasis(hoembed::QuadraticHexahedronCellType, 27) == nullptr,
    "27-node quadratic hex accepted");
  return Report("TestLagrangeHex");
}
