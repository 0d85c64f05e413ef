// Lagrange tet meshes for the tests of the any-order path: a box of Kuhn tets with the
// nodes of order p, shared between cells, moved by a curving map (so the mesh is the
// order-p interpolant of that map), or a tet10 mesh re-expressed exactly at order p.
#ifndef hoembedLagrangeTestUtilities_h
#define hoembedLagrangeTestUtilities_h

#include "hoembedDriverTestUtilities.h"
#include "hoembedLagrangeTet.h"
#include "hoembedShapeFunctions.h"
#include "hoembedTestUtilities.h"

#include <array>
#include <cmath>
#include <functional>
#include <map>
#include <vector>

namespace hoembed_test
{
/// Plain arrays of a Lagrange tet mesh (VTK_LAGRANGE_TETRAHEDRON, nodes in VTK order).
struct LagrangeBox
{
  std::vector<double> Points;
  std::vector<std::int64_t> Connectivity;
  int NodesPerCell = 0;
  std::int64_t NumberOfCells() const
  {
    return static_cast<std::int64_t>(this->Connectivity.size() / this->NodesPerCell);
  }
};

/**
 * Order-p Lagrange tets over the Kuhn tets of an n x n x n box of cube size `h`. Each
 * node is placed at `place(cell corners (12 doubles), its parametric point)`: the straight
 * point moved by a map, or a tet10 cell's map evaluated there. Nodes are shared through
 * their exact lattice position (integers).
 */
inline LagrangeBox MakeLagrangeBox(int n, int p,
  const std::function<void(
    const double* corners, std::int64_t cell, const double pc[3], double x[3])>& place)
{
  vtkSmartPointer<vtkUnstructuredGrid> straight = MakeBoxTetMesh(n, n, n, n, n, n, 1);
  const hoembed::LagrangeTetBasis& b = *hoembed::GetLagrangeTetBasis(p);
  LagrangeBox out;
  out.NodesPerCell = b.NumberOfNodes;
  std::map<std::array<long, 3>, std::int64_t> ids;
  for (vtkIdType c = 0; c < straight->GetNumberOfCells(); ++c)
  {
    vtkIdType np;
    const vtkIdType* cp;
    straight->GetCellPoints(c, np, cp);
    double corners[12];
    for (int k = 0; k < 4; ++k)
      straight->GetPoint(cp[k], corners + 3 * k);
    for (int k = 0; k < b.NumberOfNodes; ++k)
    {
      const int* a = &b.Lattice[4 * k];
      std::array<long, 3> key{ 0, 0, 0 };
      for (int m = 0; m < 4; ++m)
        for (int d = 0; d < 3; ++d)
          key[d] += a[m] * std::lround(corners[3 * m + d]);
      auto it = ids.find(key);
      if (it == ids.end())
      {
        double pc[3], x[3];
        hoembed::LagrangeTetNodeParametric(b, k, pc);
        place(corners, c, pc, x);
        it = ids.emplace(key, static_cast<std::int64_t>(out.Points.size() / 3)).first;
        out.Points.insert(out.Points.end(), x, x + 3);
      }
      out.Connectivity.push_back(it->second);
    }
  }
  return out;
}

/// The straight point of parametric pc in a tet of `corners`.
inline void StraightPoint(const double* corners, const double pc[3], double x[3])
{
  const double w[4] = { 1 - pc[0] - pc[1] - pc[2], pc[0], pc[1], pc[2] };
  for (int d = 0; d < 3; ++d)
    x[d] =
      w[0] * corners[d] + w[1] * corners[3 + d] + w[2] * corners[6 + d] + w[3] * corners[9 + d];
}

/// A smooth curving of the box (cube size 1): small enough that every cell stays valid.
inline void Curve(double x[3])
{
  const double y[3] = { x[0], x[1], x[2] };
  x[0] = y[0] + 0.12 * std::sin(1.3 * y[1] + 0.5 * y[2]);
  x[1] = y[1] + 0.12 * std::sin(1.1 * y[2] + 0.7 * y[0]);
  x[2] = y[2] + 0.12 * std::sin(0.9 * y[0] + 0.6 * y[1]);
}

/// A strong curving (held-out style: faces bent enough for the squared distance to have
/// several local minima on one face, the cells still valid).
inline void CurveStrongly(double x[3])
{
  const double y[3] = { x[0], x[1], x[2] };
  x[0] = y[0] + 0.22 * std::sin(2.3 * y[1] + 0.4 * y[2]);
  x[1] = y[1] + 0.22 * std::sin(2.1 * y[2] + 0.5 * y[0]);
  x[2] = y[2] + 0.22 * std::sin(2.5 * y[0] + 0.3 * y[1]);
}

/// The mesh's arrays as the drivers read them (type 71, or `type`).
inline PlainTetMesh AsPlainMesh(const LagrangeBox& m, int type = 71)
{
  vtkNew<vtkUnstructuredGrid> g;
  (void)g;
  PlainTetMesh out(g);
  out.Points = m.Points;
  out.Connectivity = m.Connectivity;
  out.Offsets.assign(1, 0);
  for (std::int64_t c = 0; c < m.NumberOfCells(); ++c)
  {
    out.Types.push_back(static_cast<unsigned char>(type));
    out.Offsets.push_back((c + 1) * m.NodesPerCell);
  }
  return out;
}
} // namespace hoembed_test

#endif
