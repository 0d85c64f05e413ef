#include "hoembedTetMeshInput.h"

#include "hoembedMeshFingerprint.h"

#include <cmath>
#include <sstream>

namespace hoembed
{
namespace
{
template <typename T>
std::int64_t FirstNonFinite(const T* xyz, std::int64_t n)
{
  for (std::int64_t i = 0; i < n; ++i)
  {
    const T* x = xyz + 3 * i;
    if (!std::isfinite(x[0]) || !std::isfinite(x[1]) || !std::isfinite(x[2]))
    {
      return i;
    }
  }
  return -1;
}

// Steps 2 and 3 over one id width: types and sizes first (so a mixed mesh is reported
// as such, not as a range error of a cell read with the wrong size), then the ids.
template <typename T>
std::string ReadCells(const T* offsets, const T* ids, const unsigned char* types,
  std::int64_t ncells, std::int64_t npts, TetMeshInput& out)
{
  std::ostringstream msg;
  const int type0 = types[0];
  const int npc = out.NodesPerCell;
  for (std::int64_t c = 0; c < ncells; ++c)
  {
    const std::int64_t size = static_cast<std::int64_t>(offsets[c + 1] - offsets[c]);
    if (types[c] != type0)
    {
      msg << "the FE mesh mixes cell types: cell " << c << " has type " << int(types[c])
          << ", cell 0 has type " << type0
          << (type0 == TetMeshInput::LagrangeTetra
                 ? "; use only VTK_LAGRANGE_TETRAHEDRON cells (of one order)"
                 : TetMeshInput::IsHexahedron(type0)
                 ? "; use one hexahedron type (and one order) for the whole mesh"
                 : "; use only VTK_QUADRATIC_TETRA or only VTK_TETRA cells");
      return msg.str();
    }
    if (size != npc)
    {
      msg << "cell " << c << " of the FE mesh has " << size << " points, expected " << npc;
      return msg.str();
    }
  }
  // every cell has npc ids: they lie back to back
  out.Connectivity.assign(ids + offsets[0], ids + offsets[ncells]);
  const std::int64_t* conn = out.Connectivity.data();
  for (std::int64_t i = 0; i < npc * ncells; ++i)
  {
    if (conn[i] < 0 || conn[i] >= npts)
    {
      msg << "cell " << i / npc << " of the FE mesh refers to node " << conn[i]
          << ", out of range [0, " << npts << ")";
      return msg.str();
    }
  }
  return std::string();
}
} // namespace

std::int64_t FirstNonFinitePoint(const double* xyz, std::int64_t n)
{
  return FirstNonFinite(xyz, n);
}

std::int64_t FirstNonFinitePoint(const float* xyz, std::int64_t n)
{
  return FirstNonFinite(xyz, n);
}

std::string TetMeshInput::Read(const TetMeshArrays& in, int keep)
{
  std::ostringstream msg;
  this->NumberOfPoints = in.NumberOfPoints;
  this->NumberOfCells = in.NumberOfCells;
  this->Fingerprint.clear();
  const bool has64 = in.Offsets64 && in.Connectivity64;
  const bool has32 = in.Offsets32 && in.Connectivity32;
  if (in.NumberOfPoints <= 0 || in.NumberOfCells <= 0 || !in.CellTypes || !(has64 || has32))
  {
    return "the FE mesh is empty: it needs points and VTK_QUADRATIC_TETRA or VTK_TETRA cells";
  }
  const int type0 = in.CellTypes[0];
  const bool lagrange = (keep & KeepLagrange) && type0 == LagrangeTetra;
  const bool hexahedra = (keep & KeepHexahedra) && IsHexahedron(type0);
  if (type0 != QuadraticTetra && type0 != LinearTetra && !lagrange && !hexahedra)
  {
    msg << "Unsupported cell type " << type0
        << " (cell 0): the FE mesh must have only VTK_QUADRATIC_TETRA (24) or only VTK_TETRA "
           "(10) cells"
        << ((keep & KeepLagrange) ? ", or only VTK_LAGRANGE_TETRAHEDRON (71) cells of order 1-4"
                                  : "")
        << ((keep & KeepHexahedra)
               ? ", or only VTK_LAGRANGE_HEXAHEDRON (72) cells of order 1-3, or only "
                 "VTK_TRIQUADRATIC_HEXAHEDRON (29), or only VTK_QUADRATIC_HEXAHEDRON (25) cells"
               : "");
    return msg.str();
  }
  if (in.CellGhosts)
  {
    std::int64_t ghosts = 0, first = -1;
    for (std::int64_t c = 0; c < in.NumberOfCells; ++c)
    {
      if (in.CellGhosts[c] & GhostDuplicateCell)
      {
        first = first < 0 ? c : first;
        ++ghosts;
      }
    }
    if (ghosts > 0)
    {
      msg << "the FE mesh has " << ghosts << " ghost cells of " << in.NumberOfCells
          << " (the first: cell " << first
          << "), so it is a distributed mesh: the whole mesh is needed on every process; "
             "remove the filter that distributes it or adds ghost cells (D3, "
             "RedistributeDataSet, GhostCellsGenerator) from the mesh input";
      return msg.str();
    }
  }
  this->CellType = type0;
  this->NodesPerCell = type0 == QuadraticTetra ? 10 : 4;
  if (lagrange)
  {
    // the order is the first cell's; ReadCells then holds every cell to its size
    const std::int64_t size0 =
      has64 ? in.Offsets64[1] - in.Offsets64[0] : in.Offsets32[1] - in.Offsets32[0];
    if (size0 != 4 && size0 != 10 && size0 != 20 && size0 != 35)
    {
      msg << "cell 0 of the FE mesh is a VTK_LAGRANGE_TETRAHEDRON of " << size0
          << " points: only complete orders 1-4 (4, 10, 20 or 35 points) are supported";
      return msg.str();
    }
    this->NodesPerCell = static_cast<int>(size0);
  }
  if (hexahedra)
  {
    const std::int64_t size0 =
      has64 ? in.Offsets64[1] - in.Offsets64[0] : in.Offsets32[1] - in.Offsets32[0];
    const bool ok = type0 == LagrangeHexahedron ? (size0 == 8 || size0 == 27 || size0 == 64)
                                                : size0 == (type0 == QuadraticHexahedron ? 20 : 27);
    if (!ok)
    {
      msg << "cell 0 of the FE mesh is a "
          << (type0 == LagrangeHexahedron       ? "VTK_LAGRANGE_HEXAHEDRON"
                 : type0 == QuadraticHexahedron ? "VTK_QUADRATIC_HEXAHEDRON"
                                                : "VTK_TRIQUADRATIC_HEXAHEDRON")
          << " of " << size0 << " points: "
          << (type0 == LagrangeHexahedron
                 ? "only uniform orders 1-3 (8, 27 or 64 points) are supported"
                 : type0 == QuadraticHexahedron ? "it needs 20"
                                                : "it needs 27");
      return msg.str();
    }
    this->NodesPerCell = static_cast<int>(size0);
  }
  if (hexahedra && type0 == LagrangeHexahedron && in.HigherOrderDegrees)
  {
    // the order is read from the node count: a non-uniform cell of as many nodes (orders
    // 1, 3, 7 have 64) would be read wrongly
    const double p = this->NodesPerCell == 8 ? 1 : (this->NodesPerCell == 27 ? 2 : 3);
    for (std::int64_t c = 0; c < in.NumberOfCells; ++c)
    {
      const double* g = in.HigherOrderDegrees + 3 * c;
      if (g[0] != p || g[1] != p || g[2] != p)
      {
        msg << "cell " << c << " of the FE mesh is a VTK_LAGRANGE_HEXAHEDRON of orders (" << g[0]
            << ", " << g[1] << ", " << g[2]
            << ") (its HigherOrderDegrees): only uniform orders 1-3 are supported, one per mesh";
        return msg.str();
      }
    }
  }
  const std::string cells = has64 ? ReadCells(in.Offsets64, in.Connectivity64, in.CellTypes,
                                      in.NumberOfCells, in.NumberOfPoints, *this)
                                  : ReadCells(in.Offsets32, in.Connectivity32, in.CellTypes,
                                      in.NumberOfCells, in.NumberOfPoints, *this);
  if (!cells.empty())
  {
    return cells;
  }
  if (in.PointsDouble || in.PointsFloat)
  {
    const std::int64_t bad = in.PointsDouble
      ? FirstNonFinitePoint(in.PointsDouble, in.NumberOfPoints)
      : FirstNonFinitePoint(in.PointsFloat, in.NumberOfPoints);
    if (bad >= 0)
    {
      msg << "the FE mesh has a non-finite (NaN or infinite) coordinate at node " << bad;
      return msg.str();
    }
    if (keep & KeepPoints)
    {
      const std::size_t n = 3 * static_cast<std::size_t>(in.NumberOfPoints);
      if (in.PointsDouble)
      {
        this->Points.assign(in.PointsDouble, in.PointsDouble + n);
      }
      else
      {
        this->Points.assign(in.PointsFloat, in.PointsFloat + n);
      }
    }
  }
  else if (keep & KeepPoints)
  {
    return "the FE mesh has no point coordinates";
  }
  if (keep & KeepFingerprint)
  {
    MeshFingerprint fp(in.NumberOfPoints, in.NumberOfCells);
    const std::int64_t* conn = this->Connectivity.data();
    for (std::int64_t c = 0; c < in.NumberOfCells; ++c)
    {
      fp.AddCell(type0, conn + this->NodesPerCell * c, this->NodesPerCell);
    }
    this->Fingerprint = fp.Hex();
  }
  return std::string();
}
} // namespace hoembed
