// hoembed::CurveMidEdgeNodes with the quality floor (hoembed::Tet10Acceptable's
// minQuality): a mid-edge node sent far enough to spoil its element is pulled back just
// enough that the element's minimum scaled Jacobian, recomputed here from VTK's own
// quadratic-tetra derivatives at the 20 points of the cubic lattice, is at least the
// floor; without the floor the same move keeps a far worse element; a sliver whose
// straight shape is below the floor is kept as good as its straight shape.
#include "hoembedCurvedBoundary.h"
#include "hoembedTestUtilities.h"

#include "vtkMath.h"
#include "vtkQuadraticTetra.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace
{
using Id = std::int64_t;

// Verdict's scaled Jacobian at parametric point pc, from vtkQuadraticTetra's derivatives:
// sqrt(2) det J over the largest product of the three mapped reference edges at a corner.
double ScaledJacobianAt(const double x[30], const double pc[3])
{
  double derivs[30];
  vtkQuadraticTetra::InterpolationDerivs(pc, derivs);
  double J[3][3] = { { 0 } }; // J[r][c] = d x_r / d pc_c
  for (int a = 0; a < 10; ++a)
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c)
        J[r][c] += x[3 * a + r] * derivs[10 * c + a];
  auto mapped = [&](const double e[3]) {
    double v[3];
    for (int r = 0; r < 3; ++r)
      v[r] = J[r][0] * e[0] + J[r][1] * e[1] + J[r][2] * e[2];
    return vtkMath::Norm(v);
  };
  const double c[4][3] = { { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 } };
  double largest = 0.0;
  for (int k = 0; k < 4; ++k)
  {
    double product = 1.0;
    for (int j = 0; j < 4; ++j)
      if (j != k)
      {
        const double e[3] = { c[j][0] - c[k][0], c[j][1] - c[k][1], c[j][2] - c[k][2] };
        product *= mapped(e);
      }
    largest = std::max(largest, product);
  }
  return std::sqrt(2.0) * vtkMath::Determinant3x3(J) / largest;
}

// Minimum over the cubic lattice (barycentric multiples of 1/3).
double LatticeMinScaledJacobian(const double x[30])
{
  double lowest = VTK_DOUBLE_MAX;
  for (int i = 0; i <= 3; ++i)
    for (int j = 0; i + j <= 3; ++j)
      for (int k = 0; i + j + k <= 3; ++k)
      {
        const double pc[3] = { i / 3.0, j / 3.0, k / 3.0 };
        lowest = std::min(lowest, ScaledJacobianAt(x, pc));
      }
  return lowest;
}

// One straight tet10 of corners c (4 x 3), mid-edge nodes at edge midpoints (VTK order).
std::vector<double> StraightTet10(const double c[12])
{
  static const int edges[6][2] = { { 0, 1 }, { 1, 2 }, { 0, 2 }, { 0, 3 }, { 1, 3 }, { 2, 3 } };
  std::vector<double> p(c, c + 12);
  for (const auto& e : edges)
    for (int d = 0; d < 3; ++d)
      p.push_back(0.5 * (c[3 * e[0] + d] + c[3 * e[1] + d]));
  return p;
}
} // namespace

int main(int, char*[])
{
  const std::vector<Id> conn{ 0, 1, 2, 3, 4, 5, 6, 7, 8, 9 };
  const std::vector<Id> nodes{ 4 }; // the mid-edge node of edge 0-1
  const double floor = 0.05;
  // A regular tet; the node of edge 0-1 goes towards the opposite edge 2-3, deep enough
  // that the element would not be valid there.
  const double s = 1.0 / std::sqrt(2.0);
  const double regular[12] = { 1, 0, -s, -1, 0, -s, 0, -1, s, 0, 1, s };
  const std::vector<double> straight = StraightTet10(regular);
  const std::vector<double> target{ 0.0, 0.0, 0.9 * s };
  HOEMBED_CHECK(LatticeMinScaledJacobian(straight.data()) > 0.99, "the regular tet scores %g",
    LatticeMinScaledJacobian(straight.data()));
  {
    std::vector<double> moved(straight);
    std::copy(target.begin(), target.end(), moved.begin() + 12);
    HOEMBED_CHECK(LatticeMinScaledJacobian(moved.data()) < 0.0,
      "the full move should invert the element (%g)", LatticeMinScaledJacobian(moved.data()));
  }

  // With the floor: pulled back part of the way, no further than needed.
  std::vector<double> withFloor(straight);
  const hoembed::CurvingResult r =
    hoembed::CurveMidEdgeNodes(withFloor, conn, nodes, target, 0.02, floor);
  const double q = LatticeMinScaledJacobian(withFloor.data());
  std::printf("with the floor: alpha %g, min scaled Jacobian %g\n", r.Alpha[0], q);
  HOEMBED_CHECK(r.Relaxed == 1 && r.Alpha[0] > 0.0 && r.Alpha[0] < 1.0,
    "the node should be pulled back part of the way (alpha %g)", r.Alpha[0]);
  HOEMBED_CHECK(q >= floor * (1.0 - 1e-9), "min scaled Jacobian %g below the floor", q);
  {
    // 2% further along the move the element is below the floor: the pull-back is tight.
    std::vector<double> further(withFloor);
    for (int d = 0; d < 3; ++d)
      further[12 + d] = straight[12 + d] + (r.Alpha[0] + 0.02) * (target[d] - straight[12 + d]);
    HOEMBED_CHECK(LatticeMinScaledJacobian(further.data()) < floor,
      "alpha %g + 0.02 still scores %g: pulled back more than needed", r.Alpha[0],
      LatticeMinScaledJacobian(further.data()));
  }
  HOEMBED_CHECK(hoembed::Tet10Acceptable(withFloor.data(), 0.02, floor), "not acceptable");

  // Without the floor (validity and 2% of the straight quality only) the node goes
  // further and the element is worse: the floor is what keeps it usable.
  std::vector<double> noFloor(straight);
  const hoembed::CurvingResult r0 =
    hoembed::CurveMidEdgeNodes(noFloor, conn, nodes, target, 0.02, 0.0);
  const double q0 = LatticeMinScaledJacobian(noFloor.data());
  std::printf("without the floor: alpha %g, min scaled Jacobian %g\n", r0.Alpha[0], q0);
  HOEMBED_CHECK(r0.Alpha[0] > r.Alpha[0] && q0 < floor && q0 > 0.0,
    "without the floor: alpha %g, quality %g", r0.Alpha[0], q0);

  // A sliver (straight scaled Jacobian below the floor): kept at its straight quality.
  const double sliver[12] = { 0, 0, 0, 1, 0, 0, 0.5, 0.9, 0, 0.5, 0.3, 0.02 };
  std::vector<double> flat = StraightTet10(sliver);
  const double qStraight = LatticeMinScaledJacobian(flat.data());
  HOEMBED_CHECK(qStraight > 0.0 && qStraight < floor, "the sliver scores %g", qStraight);
  const std::vector<double> up{ 0.5, 0.0, 0.2 }; // node of edge 0-1 lifted
  const hoembed::CurvingResult rs = hoembed::CurveMidEdgeNodes(flat, conn, nodes, up, 0.02, floor);
  const double qs = LatticeMinScaledJacobian(flat.data());
  std::printf("sliver: straight %g, alpha %g, curved %g\n", qStraight, rs.Alpha[0], qs);
  HOEMBED_CHECK(
    qs >= 0.999 * qStraight * (1.0 - 1e-9), "the sliver lost quality: %g < %g", qs, qStraight);
  HOEMBED_CHECK(hoembed::Tet10RequiredQuality(qStraight, 0.02, floor) < floor,
    "a straight shape below the floor must be acceptable as it is");
  return hoembed_test::Report("TestCurvedBoundary");
}
