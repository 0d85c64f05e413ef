#include "hoembedLagrangeTransfer.h"

#include "hoembedElementGeometry.h" // Determinant3

#include <cmath>

namespace hoembed
{
namespace
{
template <typename T>
void Transfer(const LagrangeTetBasis& b, const std::int64_t* conn, const double* points,
  const double* nodalNormals, const TransferEntry* plan, std::int64_t begin, std::int64_t end,
  T* out)
{
  const int npc = b.NumberOfNodes;
  double x[3 * MaxLagrangeTetNodes], n[3 * MaxLagrangeTetNodes];
  for (std::int64_t i = begin; i < end; ++i)
  {
    const TransferEntry& e = plan[i];
    double p[3], J[3][3];
    GatherCell(points, conn, npc, e.Cell, x);
    EvaluateLagrangeTet(b, x, e.PC, p, J);
    if (e.Distance != 0.0)
    {
      double s[3], Js[3][3];
      GatherCell(nodalNormals, conn, npc, e.Cell, n);
      EvaluateLagrangeTet(b, n, e.PC, s, Js);
      const double len = std::sqrt(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]);
      if (len > 0.0)
        for (int d = 0; d < 3; ++d)
          p[d] += e.Distance * s[d] / len;
    }
    for (int d = 0; d < 3; ++d)
      out[3 * i + d] = static_cast<T>(p[d]);
  }
}

template <typename T>
void Fallback(const LagrangeTetBasis& b, const std::int64_t* conn, const double* points,
  const TransferEntry* plan, const std::int64_t* vertices, const double* q, std::int64_t begin,
  std::int64_t end, T* out)
{
  const int npc = b.NumberOfNodes;
  double x[3 * MaxLagrangeTetNodes];
  for (std::int64_t k = begin; k < end; ++k)
  {
    const std::int64_t i = vertices[k];
    const TransferEntry& e = plan[i];
    double p[3], J[3][3];
    GatherCell(points, conn, npc, e.Cell, x);
    EvaluateLagrangeTet(b, x, e.PC, p, J);
    const double* qk = q + 3 * k;
    for (int d = 0; d < 3; ++d)
      out[3 * i + d] = static_cast<T>(p[d] + J[0][d] * qk[0] + J[1][d] * qk[1] + J[2][d] * qk[2]);
  }
}
} // namespace

void EvaluateLagrangeTransfer(const LagrangeTetBasis& b, const std::int64_t* conn,
  const double* points, const double* nodalNormals, const TransferEntry* plan, std::int64_t begin,
  std::int64_t end, double* out)
{
  Transfer(b, conn, points, nodalNormals, plan, begin, end, out);
}

void EvaluateLagrangeTransfer(const LagrangeTetBasis& b, const std::int64_t* conn,
  const double* points, const double* nodalNormals, const TransferEntry* plan, std::int64_t begin,
  std::int64_t end, float* out)
{
  Transfer(b, conn, points, nodalNormals, plan, begin, end, out);
}

void EvaluateLagrangeFallback(const LagrangeTetBasis& b, const std::int64_t* conn,
  const double* points, const TransferEntry* plan, const std::int64_t* vertices, const double* q,
  std::int64_t begin, std::int64_t end, double* out)
{
  Fallback(b, conn, points, plan, vertices, q, begin, end, out);
}

void EvaluateLagrangeFallback(const LagrangeTetBasis& b, const std::int64_t* conn,
  const double* points, const TransferEntry* plan, const std::int64_t* vertices, const double* q,
  std::int64_t begin, std::int64_t end, float* out)
{
  Fallback(b, conn, points, plan, vertices, q, begin, end, out);
}

std::int64_t CountInvertedLagrangeCells(const LagrangeTetBasis& b, const std::int64_t* conn,
  const double* points, std::int64_t begin, std::int64_t end)
{
  const int npc = b.NumberOfNodes;
  const double at[5][3] = { { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 },
    { 0.25, 0.25, 0.25 } };
  double x[3 * MaxLagrangeTetNodes];
  std::int64_t count = 0;
  for (std::int64_t c = begin; c < end; ++c)
  {
    GatherCell(points, conn, npc, c, x);
    for (const auto& pc : at)
    {
      double p[3], J[3][3], Jt[3][3];
      EvaluateLagrangeTet(b, x, pc, p, J);
      for (int r = 0; r < 3; ++r)
        for (int k = 0; k < 3; ++k)
          Jt[r][k] = J[k][r];
      if (!(Determinant3(Jt) > 0.0))
      {
        ++count;
        break;
      }
    }
  }
  return count;
}

namespace
{
// The cell's tensor form of a nodal field.
void HexTensor(const LagrangeHexBasis& b, const std::int64_t* conn, const double* field,
  std::int64_t c, double* t)
{
  double x[3 * MaxLagrangeHexNodes];
  const int npc = b.NumberOfNodes;
  for (int k = 0; k < npc; ++k)
    for (int d = 0; d < 3; ++d)
      x[3 * k + d] = field[3 * conn[npc * c + k] + d];
  LagrangeHexToTensor(b, x, t);
}

template <typename T>
void HexTransfer(const LagrangeHexBasis& b, const std::int64_t* conn, const double* points,
  const double* nodalNormals, const TransferEntry* plan, std::int64_t begin, std::int64_t end,
  T* out)
{
  double t[3 * MaxLagrangeHexNodes];
  for (std::int64_t i = begin; i < end; ++i)
  {
    const TransferEntry& e = plan[i];
    double p[3], J[3][3];
    HexTensor(b, conn, points, e.Cell, t);
    EvaluateTensorHex(b.Order, t, e.PC, p, J);
    if (e.Distance != 0.0)
    {
      double s[3];
      HexTensor(b, conn, nodalNormals, e.Cell, t);
      EvaluateTensorHex(b.Order, t, e.PC, s, J);
      const double len = std::sqrt(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]);
      if (len > 0.0)
        for (int d = 0; d < 3; ++d)
          p[d] += e.Distance * s[d] / len;
    }
    for (int d = 0; d < 3; ++d)
      out[3 * i + d] = static_cast<T>(p[d]);
  }
}

template <typename T>
void HexFallback(const LagrangeHexBasis& b, const std::int64_t* conn, const double* points,
  const TransferEntry* plan, const std::int64_t* vertices, const double* q, std::int64_t begin,
  std::int64_t end, T* out)
{
  double t[3 * MaxLagrangeHexNodes];
  for (std::int64_t k = begin; k < end; ++k)
  {
    const std::int64_t i = vertices[k];
    const TransferEntry& e = plan[i];
    double p[3], J[3][3];
    HexTensor(b, conn, points, e.Cell, t);
    EvaluateTensorHex(b.Order, t, e.PC, p, J);
    const double* qk = q + 3 * k;
    for (int d = 0; d < 3; ++d)
      out[3 * i + d] = static_cast<T>(p[d] + J[0][d] * qk[0] + J[1][d] * qk[1] + J[2][d] * qk[2]);
  }
}
} // namespace

void EvaluateHexTransfer(const LagrangeHexBasis& b, const std::int64_t* conn, const double* points,
  const double* nodalNormals, const TransferEntry* plan, std::int64_t begin, std::int64_t end,
  double* out)
{
  HexTransfer(b, conn, points, nodalNormals, plan, begin, end, out);
}

void EvaluateHexTransfer(const LagrangeHexBasis& b, const std::int64_t* conn, const double* points,
  const double* nodalNormals, const TransferEntry* plan, std::int64_t begin, std::int64_t end,
  float* out)
{
  HexTransfer(b, conn, points, nodalNormals, plan, begin, end, out);
}

void EvaluateHexFallback(const LagrangeHexBasis& b, const std::int64_t* conn, const double* points,
  const TransferEntry* plan, const std::int64_t* vertices, const double* q, std::int64_t begin,
  std::int64_t end, double* out)
{
  HexFallback(b, conn, points, plan, vertices, q, begin, end, out);
}

void EvaluateHexFallback(const LagrangeHexBasis& b, const std::int64_t* conn, const double* points,
  const TransferEntry* plan, const std::int64_t* vertices, const double* q, std::int64_t begin,
  std::int64_t end, float* out)
{
  HexFallback(b, conn, points, plan, vertices, q, begin, end, out);
}

std::int64_t CountInvertedHexCells(const LagrangeHexBasis& b, const std::int64_t* conn,
  const double* points, std::int64_t begin, std::int64_t end)
{
  double t[3 * MaxLagrangeHexNodes];
  std::int64_t count = 0;
  for (std::int64_t c = begin; c < end; ++c)
  {
    HexTensor(b, conn, points, c, t);
    for (int k = 0; k < 9; ++k)
    {
      const double pc[3] = { k == 8 ? 0.5 : double(k & 1), k == 8 ? 0.5 : double((k >> 1) & 1),
        k == 8 ? 0.5 : double(k >> 2) };
      double p[3], J[3][3], Jt[3][3];
      EvaluateTensorHex(b.Order, t, pc, p, J);
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
} // namespace hoembed
