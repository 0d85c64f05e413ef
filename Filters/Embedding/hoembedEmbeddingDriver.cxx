#include "hoembedEmbeddingDriver.h"

#include "hoembedClosestPoint.h"
#include "hoembedParallel.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <mutex>
#include <sstream>

namespace hoembed
{
using Id = EmbeddingMesh::Id;

std::string EmbeddingDriver::SetSurface(const double* pointsDouble, const float* pointsFloat,
  std::int64_t numberOfPoints, const CellArrayView& polygons, const CellArrayView& strips)
{
  this->NumberOfPoints = numberOfPoints;
  std::vector<double>& out = this->SurfacePoints;
  if (pointsDouble)
    out.assign(pointsDouble, pointsDouble + 3 * numberOfPoints);
  else
    out.assign(pointsFloat, pointsFloat + 3 * numberOfPoints);
  const std::int64_t bad = FirstNonFinitePoint(out.data(), numberOfPoints);
  if (bad >= 0)
  {
    std::ostringstream msg;
    msg << "The surface has a non-finite (NaN or infinite) coordinate at point " << bad << ".";
    return msg.str();
  }
  // the triangles' problems are reported after the mesh's (PrepareAndOrder)
  this->Triangles.clear();
  AppendSurfaceTriangles(polygons, strips, this->Triangles);
  this->SurfaceError = CheckSurfaceTriangles(this->Triangles, numberOfPoints);
  return std::string();
}

std::string EmbeddingDriver::PrepareMesh(const TetMeshArrays& arrays, bool validateElements)
{
  std::ostringstream msg;
  EmbeddingMesh& em = this->Mesh;
  // types, connectivity, node ranges, finite points and the fingerprint: the one reader
  TetMeshInput input;
  const std::string readError = input.Read(arrays,
    TetMeshInput::KeepPoints | TetMeshInput::KeepFingerprint | TetMeshInput::KeepLagrange |
      TetMeshInput::KeepHexahedra);
  if (!readError.empty())
  {
    return readError + ".";
  }
  this->Hexahedra = TetMeshInput::IsHexahedron(input.CellType);
  this->Lagrange = !this->Hexahedra && input.NodesPerCell > 10;
  if (this->Hexahedra)
  {
    Id firstBad = input.NumberOfCells;
    const std::string err =
      this->HexMesh.Build(std::move(input.Points), std::move(input.Connectivity), input.CellType,
        input.NodesPerCell, validateElements ? &firstBad : nullptr);
    if (!err.empty())
    {
      msg << "The FE mesh topology is not usable: " << err << ".";
      return msg.str();
    }
    if (firstBad < input.NumberOfCells)
    {
      msg << "The FE mesh has an inverted or degenerate element: cell " << firstBad << " ("
          << HexahedronTypeName(input.CellType, input.NodesPerCell)
          << ") has a Jacobian determinant not proven positive throughout (its Bernstein "
             "coefficients).";
      return msg.str();
    }
    this->Fingerprint = input.Fingerprint;
    return std::string();
  }
  if (this->Lagrange)
  {
    Id firstBad = input.NumberOfCells;
    const std::string err = this->LagrangeMesh.Build(std::move(input.Points),
      std::move(input.Connectivity), input.NodesPerCell, validateElements ? &firstBad : nullptr);
    if (!err.empty())
    {
      msg << "The FE mesh topology is not usable: " << err << ".";
      return msg.str();
    }
    if (firstBad < input.NumberOfCells)
    {
      msg << "The FE mesh has an inverted or degenerate element: cell " << firstBad
          << " (VTK_LAGRANGE_TETRAHEDRON of order " << LagrangeTetOrder(input.NodesPerCell)
          << ") has a Jacobian determinant not proven positive throughout (its Bernstein "
             "coefficients).";
      return msg.str();
    }
    this->Fingerprint = input.Fingerprint;
    return std::string();
  }
  em.Points.swap(input.Points);
  em.Connectivity.swap(input.Connectivity);
  const int npc = input.NodesPerCell;
  const Id ncells = input.NumberOfCells;
  // element validity is checked in the pass that builds the cell maps
  Id firstInvalid = ncells;
  const std::string err = em.Prepare(npc, validateElements ? &firstInvalid : nullptr);
  if (firstInvalid < ncells)
  {
    msg << "The FE mesh has an inverted or degenerate element: cell " << firstInvalid
        << " has a non-positive Jacobian determinant"
        << (npc == 10 ? " somewhere inside it." : ".");
    return msg.str();
  }
  if (!err.empty())
  {
    msg << "The FE mesh topology is not usable: " << err;
    return msg.str();
  }
  this->Fingerprint = input.Fingerprint;
  return std::string();
}

std::string EmbeddingDriver::PrepareAndOrder(
  const TetMeshArrays* mesh, bool validateElements, int partitions)
{
  const std::string rangeError = CheckPropertyRange(EmbeddingRanges[0], partitions);
  if (!rangeError.empty())
  {
    return rangeError;
  }
  // The surface's order for the flood depends on the surface only: it is built while the
  // mesh is prepared (two tasks; on two threads the preparation's serial parts and the
  // ordering overlap). Both tasks only record problems.
  std::string meshError;
  if (mesh)
    this->Fingerprint.clear();
  ParallelLoop(0, 2, 1, [&](int b, int e) {
    for (int task = b; task < e; ++task)
    {
      if (task == 0 && mesh)
        meshError = this->PrepareMesh(*mesh, validateElements);
      else if (task == 1 && this->SurfaceError.empty())
        OrderSurface(this->SurfacePoints.data(), this->NumberOfPoints, this->Triangles, partitions,
          &this->Order, this->Flood);
    }
  });
  if (!meshError.empty())
  {
    this->Fingerprint.clear();
    return meshError;
  }
  return this->SurfaceError;
}

void EmbeddingDriver::Embed(int method, const std::function<void(double)>& progress)
{
  this->Method = method;
  if (this->Hexahedra)
  {
    const Id n = this->NumberOfPoints;
    this->Results.resize(n);
    ParallelLoop(Id(0), n, [&](Id b, Id e) {
      for (Id k = b; k < e; ++k)
        this->HexMesh.Embed(&this->SurfacePoints[3 * this->Order[k]], method, this->Results[k]);
    });
    if (progress)
      progress(1.0);
    return;
  }
  if (this->Lagrange)
  {
    // one certified search per vertex (results in the flood's order, as WriteArrays reads)
    const Id n = this->NumberOfPoints;
    this->Results.resize(n);
    ParallelLoop(Id(0), n, [&](Id b, Id e) {
      for (Id k = b; k < e; ++k)
        this->LagrangeMesh.Embed(
          &this->SurfacePoints[3 * this->Order[k]], method, this->Results[k]);
    });
    if (progress)
      progress(1.0);
    return;
  }
  FloodSurface(this->Mesh, method, this->Results, progress, nullptr, this->Flood);
}

std::string EmbeddingDriver::WriteArrays(
  const EmbeddingOutputArrays& out, EmbeddingSummary& summary) const
{
  const Id ns = this->NumberOfPoints;
  const std::vector<VertexEmbedding>& res = this->Results;
  const std::vector<Id>& order = this->Order; // res[k] belongs to surface point order[k]
  const bool barycentric = this->Method == EMBED_BARYCENTRIC;
  std::atomic<Id> firstFailed(ns);
  std::atomic<Id> uncertified(0), firstUncertified(ns);
  std::atomic<Id> fallbacks(0), firstFallback(ns);
  std::atomic<Id> inexact(0), firstInexact(ns);
  const double residualBound = ResidualTolerance * this->MeshDiagonal();
  std::mutex worstLock;
  double worst = 0.0;
  auto lowest = [](std::atomic<Id>& first, Id i) {
    Id cur = first.load();
    while (i < cur && !first.compare_exchange_weak(cur, i))
    {
    }
  };
  ParallelLoop(Id(0), ns, [&](Id b, Id e) {
    Id localUncertified = 0, localFallbacks = 0, localInexact = 0;
    double localWorst = 0.0;
    for (Id k = b; k < e; ++k)
    {
      const VertexEmbedding& r = res[k];
      const Id i = order[k];
      if (r.Uncertified)
      {
        ++localUncertified;
        lowest(firstUncertified, i);
      }
      if (!std::isfinite(r.PC[0]) || !std::isfinite(r.PC[1]) || !std::isfinite(r.PC[2]) ||
        !std::isfinite(r.Distance) || !std::isfinite(r.Residual) || r.Cell < 0)
      {
        lowest(firstFailed, i);
        continue;
      }
      out.CellId[i] = r.Cell;
      for (int d = 0; d < 3; ++d)
        out.ParametricCoords[3 * i + d] = r.PC[d];
      out.Distance[i] = r.Distance;
      out.Residual[i] = r.Residual;
      if (r.Residual > residualBound)
      {
        ++localInexact;
        lowest(firstInexact, i);
        localWorst = std::max(localWorst, r.Residual);
      }
      out.ClosestDistance[i] = r.ClosestDistance;
      out.Face[i] = barycentric ? -1 : r.Face;
      out.Iterations[i] = r.Iterations;
      out.Visited[i] = r.Visited;
      out.Fallback[i] = r.Fallback ? 1 : 0;
      if (r.Fallback)
      {
        ++localFallbacks;
        lowest(firstFallback, i);
      }
    }
    uncertified += localUncertified;
    fallbacks += localFallbacks;
    if (localInexact > 0)
    {
      inexact += localInexact;
      std::lock_guard<std::mutex> guard(worstLock);
      worst = std::max(worst, localWorst);
    }
  });
  if (firstFailed.load() < ns)
  {
    std::ostringstream msg;
    msg << "Surface point " << firstFailed.load() << " could not be embedded (non-finite result).";
    return msg.str();
  }
  summary.Uncertified = uncertified.load();
  summary.FirstUncertified = summary.Uncertified > 0 ? firstUncertified.load() : -1;
  summary.Fallbacks = fallbacks.load();
  summary.FirstFallback = summary.Fallbacks > 0 ? firstFallback.load() : -1;
  summary.Inexact = inexact.load();
  summary.FirstInexact = summary.Inexact > 0 ? firstInexact.load() : -1;
  summary.MaxResidual = this->MeshDiagonal() > 0.0 ? worst / this->MeshDiagonal() : worst;
  summary.Method = this->Method;
  return std::string();
}

void EmbeddingDriver::WriteFallbackOffsets(double* out) const
{
  const std::vector<VertexEmbedding>& res = this->Results;
  const std::vector<Id>& order = this->Order;
  ParallelLoop(Id(0), this->NumberOfPoints, [&](Id b, Id e) {
    for (Id k = b; k < e; ++k)
    {
      double q[3] = { 0, 0, 0 };
      if (res[k].Fallback && this->Hexahedra)
        this->HexMesh.Offset(res[k].Cell, res[k].PC, &this->SurfacePoints[3 * order[k]], q);
      else if (res[k].Fallback && this->Lagrange)
        this->LagrangeMesh.Offset(res[k].Cell, res[k].PC, &this->SurfacePoints[3 * order[k]], q);
      else if (res[k].Fallback) // the q of its residual (EmbedVertex), computed again
        TetMapOffset(
          this->Mesh.CellMaps[res[k].Cell], res[k].PC, &this->SurfacePoints[3 * order[k]], q);
      for (int d = 0; d < 3; ++d)
        out[3 * order[k] + d] = q[d];
    }
  });
}

void EmbeddingDriver::ReleaseLargeSurfaceMemory()
{
  constexpr std::size_t maxKeptBytes = std::size_t(64) << 20;
  const std::size_t bytes = this->Flood.GetCapacityInBytes() +
    sizeof(double) * this->SurfacePoints.capacity() +
    sizeof(Id) * (this->Triangles.capacity() + this->Order.capacity()) +
    sizeof(VertexEmbedding) * this->Results.capacity();
  if (bytes <= maxKeptBytes)
    return;
  this->Flood.Release();
  std::vector<double>().swap(this->SurfacePoints);
  std::vector<Id>().swap(this->Triangles);
  std::vector<Id>().swap(this->Order);
  std::vector<VertexEmbedding>().swap(this->Results);
}
//------------------------------------------------------------------------------
std::vector<std::string> EmbeddingWarnings(const EmbeddingSummary& summary)
{
  std::vector<std::string> out;
  if (summary.Uncertified > 0)
  {
    std::ostringstream o;
    o << summary.Uncertified << " surface point(s) (e.g. point " << summary.FirstUncertified
      << "): the closest-point search on a curved boundary face ran out of its budget; "
         "their distance may be a local minimum only.";
    out.push_back(o.str());
  }
  if (summary.Fallbacks > 0)
  {
    std::ostringstream o;
    o << summary.Fallbacks << " surface point(s) (e.g. point " << summary.FirstFallback
      << ") have no normal offset v = p + d n: they use their closest point p and the "
         "offset v - p instead (EmbeddingFallback = 1).";
    out.push_back(o.str());
  }
  if (summary.Inexact > 0)
  {
    std::ostringstream o;
    o << summary.Inexact << " surface point(s) (e.g. point " << summary.FirstInexact
      << ") are not reproduced by their embedding: EmbeddingResidual up to " << summary.MaxResidual
      << " of the mesh's diagonal (tolerance " << ResidualTolerance << ")";
    if (summary.Method == EMBED_BARYCENTRIC)
    {
      o << "; they lie outside the mesh, where the barycentric method extrapolates the "
           "map of their closest cell, which a curved cell does not invert far out (the "
           "normal-offset method embeds them).";
    }
    else
    {
      o << ".";
    }
    out.push_back(o.str());
  }
  return out;
}
} // namespace hoembed
