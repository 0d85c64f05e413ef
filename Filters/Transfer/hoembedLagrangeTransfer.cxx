#include "hoembedLagrangeTransfer.h"

#include "hoembedElementGeometry.h" // Determinant3

#include <cmath>

namespace hoembed
{
namespace
{
// The two cell kinds of the loops below: Evaluate gives the map of a nodal field
// (points or normals) of cell c at pc and its derivatives J[k] = d/dpc_k; Samples are
// the parametric points at which a cell whose det J is not positive counts as inverted
// (the corners and the centre).
struct TetCells
{
  const LagrangeTetBasis& B;
  void Evaluate(const std::int64_t* conn, const double* field, std::int64_t c, const double pc[3],
    double p[3], double J[3][3]) const
  {
    double x[3 * MaxLagrangeTetNodes];
    GatherCell(field, conn, B.NumberOfNodes, c, x);
    EvaluateLagrangeTet(B, x, pc, p, J);
  }
  static constexpr int NumberOfSamples = 5;
  static void Sample(int k, double pc[3])
  {
    const double at[5][3] = { { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 },
      { 0.25, 0.25, 0.25 } };
    for (int i = 0; i < 3; ++i)
      pc[i] = at[k][i];
  }
};

struct HexCells
{
  const LagrangeHexBasis& B;
  void Evaluate(const std::int64_t* conn, const double* field, std::int64_t c, const double pc[3],
    double p[3], double J[3][3]) const
  {
    // the cell's tensor form of the field
    double x[3 * MaxLagrangeHexNodes], t[3 * MaxLagrangeHexNodes];
    const int npc = B.NumberOfNodes;
    for (int k = 0; k < npc; ++k)
      for (int d = 0; d < 3; ++d)
        x[3 * k + d] = field[3 * conn[npc * c + k] + d];
    LagrangeHexToTensor(B, x, t);
    EvaluateTensorHex(B.Order, t, pc, p, J);
  }
  static constexpr int NumberOfSamples = 9;
  static void Sample(int k, double pc[3])
  {
    pc[0] = k == 8 ? 0.5 : double(k & 1);
    pc[1] = k == 8 ? 0.5 : double((k >> 1) & 1);
    pc[2] = k == 8 ? 0.5 : double(k >> 2);
  }
};

template <typename Cells, typename T>
void Transfer(const Cells& cells, const std::int64_t* conn, const double* points,
  const double* nodalNormals, const TransferEntry* plan, std::int64_t begin, std::int64_t end,
  T* out)
{
  for (std::int64_t i = begin; i < end; ++i)
  {
    const TransferEntry& e = plan[i];
    double p[3], J[3][3];
    cells.Evaluate(conn, points, e.Cell, e.PC, p, J);
    if (e.Distance != 0.0)
    {
      double s[3];
      cells.Evaluate(conn, nodalNormals, e.Cell, e.PC, s, J);
      const double len = std::sqrt(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]);
      if (len > 0.0)
        for (int d = 0; d < 3; ++d)
          p[d] += e.Distance * s[d] / len;
    }
    for (int d = 0; d < 3; ++d)
      out[3 * i + d] = static_cast<T>(p[d]);
  }
}

template <typename Cells, typename T>
void Fallback(const Cells& cells, const std::int64_t* conn, const double* points,
  const TransferEntry* plan, const std::int64_t* vertices, const double* q, std::int64_t begin,
  std::int64_t end, T* out)
{
  for (std::int64_t k = begin; k < end; ++k)
  {
    const std::int64_t i = vertices[k];
    const TransferEntry& e = plan[i];
    double p[3], J[3][3];
    cells.Evaluate(conn, points, e.Cell, e.PC, p, J);
    const double* qk = q + 3 * k;
    for (int d = 0; d < 3; ++d)
      out[3 * i + d] = static_cast<T>(p[d] + J[0][d] * qk[0] + J[1][d] * qk[1] + J[2][d] * qk[2]);
  }
}

template <typename Cells>
std::int64_t CountInverted(const Cells& cells, const std::int64_t* conn, const double* points,
  std::int64_t begin, std::int64_t end)
{
  std::int64_t count = 0;
  for (std::int64_t c = begin; c < end; ++c)
  {
    for (int k = 0; k < Cells::NumberOfSamples; ++k)
    {
      double pc[3], p[3], J[3][3], Jt[3][3];
      Cells::Sample(k, pc);
      cells.Evaluate(conn, points, c, pc, p, J);
      for (int r = 0; r < 3; ++r)
        for (int i = 0; i < 3; ++i)
          Jt[r][i] = J[i][r];
      if (!(Determinant3(Jt) > 0.0))
      {
        ++count;
        break;
      }
    }
  }
  return count;
}
} // namespace

void EvaluateLagrangeTransfer(const LagrangeTetBasis& b, const std::int64_t* conn,
  const double* points, const double* nodalNormals, const TransferEntry* plan, std::int64_t begin,
  std::int64_t end, double* out)
{
  Transfer(TetCells{ b }, conn, points, nodalNormals, plan, begin, end, out);
}

void EvaluateLagrangeTransfer(const LagrangeTetBasis& b, const std::int64_t* conn,
  const double* points, const double* nodalNormals, const TransferEntry* plan, std::int64_t begin,
  std::int64_t end, float* out)
{
  Transfer(TetCells{ b }, conn, points, nodalNormals, plan, begin, end, out);
}

void EvaluateLagrangeFallback(const LagrangeTetBasis& b, const std::int64_t* conn,
  const double* points, const TransferEntry* plan, const std::int64_t* vertices, const double* q,
  std::int64_t begin, std::int64_t end, double* out)
{
  Fallback(TetCells{ b }, conn, points, plan, vertices, q, begin, end, out);
}

void EvaluateLagrangeFallback(const LagrangeTetBasis& b, const std::int64_t* conn,
  const double* points, const TransferEntry* plan, const std::int64_t* vertices, const double* q,
  std::int64_t begin, std::int64_t end, float* out)
{
  Fallback(TetCells{ b }, conn, points, plan, vertices, q, begin, end, out);
}

std::int64_t CountInvertedLagrangeCells(const LagrangeTetBasis& b, const std::int64_t* conn,
  const double* points, std::int64_t begin, std::int64_t end)
{
  return CountInverted(TetCells{ b }, conn, points, begin, end);
}

void EvaluateHexTransfer(const LagrangeHexBasis& b, const std::int64_t* conn, const double* points,
  const double* nodalNormals, const TransferEntry* plan, std::int64_t begin, std::int64_t end,
  double* out)
{
  Transfer(HexCells{ b }, conn, points, nodalNormals, plan, begin, end, out);
}

void EvaluateHexTransfer(const LagrangeHexBasis& b, const std::int64_t* conn, const double* points,
  const double* nodalNormals, const TransferEntry* plan, std::int64_t begin, std::int64_t end,
  float* out)
{
  Transfer(HexCells{ b }, conn, points, nodalNormals, plan, begin, end, out);
}

void EvaluateHexFallback(const LagrangeHexBasis& b, const std::int64_t* conn, const double* points,
  const TransferEntry* plan, const std::int64_t* vertices, const double* q, std::int64_t begin,
  std::int64_t end, double* out)
{
  Fallback(HexCells{ b }, conn, points, plan, vertices, q, begin, end, out);
}

void EvaluateHexFallback(const LagrangeHexBasis& b, const std::int64_t* conn, const double* points,
  const TransferEntry* plan, const std::int64_t* vertices, const double* q, std::int64_t begin,
  std::int64_t end, float* out)
{
  Fallback(HexCells{ b }, conn, points, plan, vertices, q, begin, end, out);
}

std::int64_t CountInvertedHexCells(const LagrangeHexBasis& b, const std::int64_t* conn,
  const double* points, std::int64_t begin, std::int64_t end)
{
  return CountInverted(HexCells{ b }, conn, points, begin, end);
}
} // namespace hoembed
