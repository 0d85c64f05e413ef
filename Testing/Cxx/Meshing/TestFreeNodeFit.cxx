// hoembed::FitWithFreeNodes: a boundary mid-edge node pushed into a box far enough that
// its elements are no longer acceptable reaches its target once the free nodes may move,
// every element then has det J > 0 at sampled points (VTK's own quadratic tetra
// derivatives) and passes the acceptance test; with no free node nothing moves.
#include "hoembedCurvedBoundary.h"
#include "hoembedFreeNodeFit.h"
#include "hoembedTestUtilities.h"

#include "vtkMath.h"
#include "vtkQuadraticTetra.h"
#include "vtkUnstructuredGrid.h"

#include <cmath>
#include <cstdint>
#include <vector>

namespace
{
using Id = std::int64_t;

void Gather(const std::vector<double>& p, const std::vector<Id>& conn, Id c, double x[30])
{
  for (int a = 0; a < 10; ++a)
    for (int d = 0; d < 3; ++d)
      x[3 * a + d] = p[3 * conn[10 * c + a] + d];
}

// Smallest det J over a lattice of parametric points, from vtkQuadraticTetra's derivatives.
double SampledMinDet(const double x[30])
{
  double lowest = VTK_DOUBLE_MAX;
  const int n = 8;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; i + j <= n; ++j)
      for (int k = 0; i + j + k <= n; ++k)
      {
        const double pc[3] = { double(i) / n, double(j) / n, double(k) / n };
        double derivs[30];
        vtkQuadraticTetra::InterpolationDerivs(pc, derivs);
        double J[3][3] = { { 0 } };
        for (int a = 0; a < 10; ++a)
          for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c)
              J[r][c] += x[3 * a + r] * derivs[10 * c + a];
        lowest = std::min(lowest, vtkMath::Determinant3x3(J));
      }
  return lowest;
}

bool AllAcceptable(
  const std::vector<double>& p, const std::vector<Id>& conn, double ratio, double& minDet)
{
  bool ok = true;
  minDet = VTK_DOUBLE_MAX;
  for (Id c = 0; c < static_cast<Id>(conn.size() / 10); ++c)
  {
    double x[30];
    Gather(p, conn, c, x);
    ok = ok && hoembed::Tet10Acceptable(x, ratio, 0.0);
    minDet = std::min(minDet, SampledMinDet(x));
  }
  return ok;
}
} // namespace

int main(int argc, char* argv[])
{
  auto grid = hoembed_test::MakeBoxTetMesh(2, 2, 2, 1.0, 1.0, 1.0, 2);
  std::vector<double> pts(3 * grid->GetNumberOfPoints());
  for (vtkIdType i = 0; i < grid->GetNumberOfPoints(); ++i)
    grid->GetPoint(i, &pts[3 * i]);
  std::vector<Id> conn;
  std::vector<char> isCorner(grid->GetNumberOfPoints(), 0);
  for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c)
  {
    vtkIdType npts;
    const vtkIdType* ids;
    grid->GetCellPoints(c, npts, ids);
    conn.insert(conn.end(), ids, ids + 10);
    for (int a = 0; a < 4; ++a)
      isCorner[ids[a]] = 1;
  }
  auto onBox = [&](Id i) {
    for (int d = 0; d < 3; ++d)
      if (std::fabs(pts[3 * i + d]) < 1e-12 || std::fabs(pts[3 * i + d] - 1.0) < 1e-12)
        return true;
    return false;
  };
  // The boundary mid-edge node at (0.5, 0.25, 1) (an edge of the top face) goes down.
  Id m = -1;
  for (Id i = 0; i < static_cast<Id>(pts.size() / 3); ++i)
    if (!isCorner[i] &&
      std::fabs(pts[3 * i] - 0.5) + std::fabs(pts[3 * i + 1] - 0.25) +
          std::fabs(pts[3 * i + 2] - 1.0) <
        1e-12)
      m = i;
  HOEMBED_CHECK(m >= 0, "no mid-edge node at (0.5, 0.25, 1)");
  if (m < 0)
    return hoembed_test::Report("TestFreeNodeFit");
  const double ratio = 0.1;
  // The smallest push (in steps of 0.01) that makes an element around m not acceptable.
  double depth = 0.0;
  for (double d = 0.01; d < 0.5 && depth == 0.0; d += 0.01)
  {
    std::vector<double> p(pts);
    p[3 * m + 2] -= d;
    double minDet;
    if (!AllAcceptable(p, conn, ratio, minDet))
      depth = d + 0.01;
  }
  HOEMBED_CHECK(depth > 0.0, "pushing the node in never broke an element");
  std::printf("push depth %g\n", depth);
  const std::vector<Id> nodes{ m };
  const std::vector<double> target{ pts[3 * m], pts[3 * m + 1], pts[3 * m + 2] - depth };
  {
    std::vector<double> p(pts);
    p[3 * m + 2] -= depth;
    double minDet;
    HOEMBED_CHECK(!AllAcceptable(p, conn, ratio, minDet), "the target should break an element");
  }

  // No free node: nothing may move.
  {
    std::vector<double> p(pts), alpha{ 0.0 };
    std::vector<char> isFree(pts.size() / 3, 0);
    const Id fitted = hoembed::FitWithFreeNodes(p, conn, nodes, target, alpha, isFree, ratio, 0.0);
    HOEMBED_CHECK(
      fitted == 0 && alpha[0] == 0.0, "fitted %lld without free nodes", (long long)fitted);
    HOEMBED_CHECK(p == pts, "points moved although nothing could be fitted");
  }
  // Corners and interior mid-edge nodes free: the node reaches its target, all valid.
  {
    std::vector<double> p(pts), alpha{ 0.0 };
    std::vector<char> isFree(pts.size() / 3, 0);
    for (Id i = 0; i < static_cast<Id>(isFree.size()); ++i)
      isFree[i] = isCorner[i] || !onBox(i);
    const Id fitted = hoembed::FitWithFreeNodes(p, conn, nodes, target, alpha, isFree, ratio, 0.0);
    HOEMBED_CHECK(fitted == 1 && alpha[0] == 1.0, "the node was not fitted (push %g)", depth);
    HOEMBED_CHECK(p[3 * m] == target[0] && p[3 * m + 1] == target[1] && p[3 * m + 2] == target[2],
      "the node is not at its target");
    double minDet;
    HOEMBED_CHECK(AllAcceptable(p, conn, ratio, minDet), "an element is not acceptable");
    HOEMBED_CHECK(minDet > 0.0, "sampled det J %g", minDet);
    // Boundary mid-edge nodes other than m did not move.
    for (Id i = 0; i < static_cast<Id>(isFree.size()); ++i)
      if (!isFree[i] && i != m)
        HOEMBED_CHECK(p[3 * i] == pts[3 * i] && p[3 * i + 1] == pts[3 * i + 1] &&
            p[3 * i + 2] == pts[3 * i + 2],
          "fixed node %lld moved", (long long)i);
  }
  (void)argc;
  (void)argv;
  return hoembed_test::Report("TestFreeNodeFit");
}
