// Hexahedral meshes for the tests of the hexahedra (hoembedLagrangeHex.h): Cells^3 cells
// over a box, each cell's node (i, j, k) / p at the global lattice point (shared between
// cells), moved by a curving map, so the mesh is the cell type's interpolant of that map.
#ifndef hoembedHexTestUtilities_h
#define hoembedHexTestUtilities_h

#include "hoembedDriverTestUtilities.h"
#include "hoembedLagrangeHex.h"

#include <cmath>
#include <map>
#include <vector>

namespace hoembed_test
{
using Id = std::int64_t;

struct HexMesh
{
  int Type = 0, NodesPerCell = 0;
  std::vector<double> Points;
  std::vector<Id> Conn;
};

inline constexpr int Cells = 2;
inline constexpr double Box[3] = { 2.0, 1.5, 1.0 };

inline void Curve(double a, const double x[3], double y[3])
{
  y[0] = x[0] + a * std::sin(2.0 * x[1]) + 0.5 * a * x[2] * x[2];
  y[1] = x[1] + a * std::cos(1.5 * x[0]) * x[2];
  y[2] = x[2] + a * std::sin(x[0] + x[1]);
}

// Cells x Cells x Cells hexes of a type over Box, nodes curved by Curve(a): each cell's
// node (i, j, k) / p at the global lattice point, shared between cells.
inline HexMesh MakeMesh(int type, int npc, double a)
{
  const hoembed::LagrangeHexBasis& b = *hoembed::GetLagrangeHexBasis(type, npc);
  const int p = b.Order, g = Cells * p + 1;
  HexMesh m;
  m.Type = type;
  m.NodesPerCell = npc;
  std::map<int, Id> ids;
  for (int cz = 0; cz < Cells; ++cz)
    for (int cy = 0; cy < Cells; ++cy)
      for (int cx = 0; cx < Cells; ++cx)
        for (int k = 0; k < npc; ++k)
        {
          const int* l = &b.Lattice[3 * k];
          const int I = cx * p + l[0], J = cy * p + l[1], K = cz * p + l[2];
          const int key = (K * g + J) * g + I;
          auto it = ids.find(key);
          if (it == ids.end())
          {
            const double x[3] = { Box[0] * I / (g - 1), Box[1] * J / (g - 1),
              Box[2] * K / (g - 1) };
            double y[3];
            Curve(a, x, y);
            it = ids.emplace(key, static_cast<Id>(m.Points.size() / 3)).first;
            m.Points.insert(m.Points.end(), y, y + 3);
          }
          m.Conn.push_back(it->second);
        }
  return m;
}

inline void CellMap(
  const HexMesh& m, const hoembed::LagrangeHexBasis& b, Id c, const double pc[3], double x[3])
{
  double N[64];
  hoembed::LagrangeHexShape(b, pc, N);
  x[0] = x[1] = x[2] = 0.0;
  for (int k = 0; k < m.NodesPerCell; ++k)
    for (int d = 0; d < 3; ++d)
      x[d] += N[k] * m.Points[3 * m.Conn[m.NodesPerCell * c + k] + d];
}

/// The mesh as the drivers' plain arrays (every cell of the mesh's type).
inline PlainTetMesh AsPlainMesh(const HexMesh& m)
{
  vtkNew<vtkUnstructuredGrid> g;
  PlainTetMesh out(g);
  out.Points = m.Points;
  out.Connectivity = m.Conn;
  out.Offsets.assign(1, 0);
  for (std::size_t c = 0; c < m.Conn.size() / m.NodesPerCell; ++c)
  {
    out.Types.push_back(static_cast<unsigned char>(m.Type));
    out.Offsets.push_back(static_cast<std::int64_t>((c + 1) * m.NodesPerCell));
  }
  return out;
}
} // namespace hoembed_test

#endif
