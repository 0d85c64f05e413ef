#include "hoembedEmbeddingSearch.h"
#include "hoembedVector3.h"
#include "hoembedBoundaryNormals.h"
#include "hoembedClosestPointCertify.h"
#include "hoembedClosestPointInternal.h"
#include "hoembedShapeFunctions.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace hoembed
{
namespace
{
using Id = EmbeddingMesh::Id;

constexpr double InsideTolerance = 1e-11;     // of the diagonal
constexpr double CorrectionTolerance = 1e-12; // of the diagonal
constexpr double CertifyTolerance = 1e-10;    // of the diagonal: closest point on a patch
constexpr int MaxWalk = 64;
constexpr int MaxGridBins = 8; // face grid queries up to 2 x 2 x 2 bins

const double CornerUV[3][2] = { { 0, 0 }, { 1, 0 }, { 0, 1 } };

inline int PopCount(int b)
{
  int n = 0;
  for (; b; b &= b - 1)
    ++n;
  return n;
}

// Patch constraint bits -> the edge (0 ab, 1 bc, 2 ca) of a single active bit.
inline int EdgeOfBit(int bits)
{
  return bits == 2 ? 0 : (bits == 4 ? 1 : 2);
}
// Two active bits -> the corner (0 a, 1 b, 2 c).
inline int CornerOfBits(int bits)
{
  if ((bits & 3) == 3)
    return 0; // u = 0, v = 0
  if ((bits & 6) == 6)
    return 1; // v = 0, u + v = 1
  return 2;   // u = 0, u + v = 1
}
// Tet constraint bit k -> local face (TetFaceNodes order).
const int FaceOfTetBit[4] = { 2, 0, 3, 1 };

struct BoundaryHit
{
  Id Face = -1;
  double UV[2] = { 0, 0 };
  double Point[3] = { 0, 0, 0 };
  double Dist2 = std::numeric_limits<double>::infinity();
  int Active = 0;
};

// Map a point on edge e of face f (given by uv) to the uv of face g sharing that edge.
bool MapAcrossEdge(const EmbeddingMesh& M, Id f, int e, const double uv[2], Id g, double out[2])
{
  const int npf = M.Topology.GetNodesPerFace();
  const Id* fn = &M.Topology.BoundaryFaceNodes[npf * f];
  const Id* gn = &M.Topology.BoundaryFaceNodes[npf * g];
  const int ia = e, ib = (e + 1) % 3;
  double t = e == 0 ? uv[0] : (e == 1 ? uv[1] : 1.0 - uv[1]);
  int ja = -1, jb = -1;
  for (int k = 0; k < 3; ++k)
  {
    if (gn[k] == fn[ia])
      ja = k;
    if (gn[k] == fn[ib])
      jb = k;
  }
  if (ja < 0 || jb < 0)
    return false;
  out[0] = (1.0 - t) * CornerUV[ja][0] + t * CornerUV[jb][0];
  out[1] = (1.0 - t) * CornerUV[ja][1] + t * CornerUV[jb][1];
  return true;
}

void FaceNormal(const EmbeddingMesh& M, Id f, const double uv[2], double n[3])
{
  double x[3], J[2][3];
  EvaluateMap(M.FaceMaps[f], uv, x, J);
  Cross(J[0], J[1], n);
  const double l = std::sqrt(Dot(n, n));
  if (l > 0.0)
    for (int d = 0; d < 3; ++d)
      n[d] /= l;
}

// Pseudo-normal of the boundary at the closest point.
void PseudoNormal(const EmbeddingMesh& M, const BoundaryHit& hit, double n[3])
{
  const int k = PopCount(hit.Active & 7);
  if (k >= 2)
  {
    const int corner = CornerOfBits(hit.Active);
    const Id node = M.Topology.BoundaryFaceNodes[M.Topology.GetNodesPerFace() * hit.Face + corner];
    for (int d = 0; d < 3; ++d)
      n[d] = M.NodalNormals[3 * node + d];
    return;
  }
  FaceNormal(M, hit.Face, hit.UV, n);
  if (k == 1)
  {
    const int e = EdgeOfBit(hit.Active & 7);
    const Id g = M.Topology.BoundaryFaceNeighbor[3 * hit.Face + e];
    double uvg[2], ng[3];
    if (g >= 0 && MapAcrossEdge(M, hit.Face, e, hit.UV, g, uvg))
    {
      FaceNormal(M, g, uvg, ng);
      for (int d = 0; d < 3; ++d)
        n[d] += ng[d];
    }
  }
}

void Keep(const ClosestPointResult& r, Id f, BoundaryHit& best)
{
  if (r.Distance2 < best.Dist2)
  {
    best.Dist2 = r.Distance2;
    best.Face = f;
    best.UV[0] = r.Param[0];
    best.UV[1] = r.Param[1];
    best.Active = r.Active;
    for (int d = 0; d < 3; ++d)
      best.Point[d] = r.Point[d];
  }
}

// The squared distance over a curved patch is not convex: a solution (on the patch's
// border or inside) may be a local minimum only (large boundary faces of TetGen -Y
// meshes have them; a re-solve from the centroid is not enough either, see
// TestEmbeddingNonConvexFace). When the face's lower bound leaves room for a nearer
// point than both its solution and the best so far, the exact expansion at the solution
// certifies it (most faces: it is cheap) or a branch and bound over the patch
// (hoembedClosestPointCertify.h) finds a nearer point or certifies there is none. Done
// after the walk and the certification (SearchScratch::Retry), when the best distance is
// final or nearly so and most of these faces are excluded by the bound.
void RetryFace(const EmbeddingMesh& M, const double v[3], const SearchScratch::SolvedFace& sf,
  BoundaryHit& best, VertexEmbedding& out)
{
  const Id f = sf.Face;
  const ClosestPointResult& r = sf.Result;
  const double bound = sf.Bound >= 0.0 ? sf.Bound : M.FaceLowerBound2(f, v);
  const double tol = CertifyTolerance * M.Diagonal;
  if (bound < std::min(r.Distance2, best.Dist2) * (1.0 - 1e-10) &&
    !SolutionCertified(M.FaceMaps[f], v, best.Dist2, tol, r))
  {
    ClosestPointResult nearer = r;
    bool certified = true;
    if (CertifyClosestPointOnPatch(M.FaceMaps[f], v, best.Dist2, tol, nearer, &certified))
      Keep(nearer, f, best);
    if (!certified)
      out.Uncertified = true;
  }
}

// `bound`: FaceLowerBound2(f, v) when the caller has it, else < 0
void SolveFace(const EmbeddingMesh& M, const double v[3], Id f, const double* start, double bound,
  BoundaryHit& best, VertexEmbedding& out, SearchScratch& S, int* activeOut = nullptr)
{
  ClosestPointResult r;
  double linear[2];
  if (!start)
  {
    LinearStart(M.FaceMaps[f], v, linear);
    start = linear;
  }
  ClosestPointOnMap(M.FaceMaps[f], v, start, r);
  out.Iterations += r.Iterations;
  ++out.Visited;
  if (M.NodesPerCell() == 10) // flat tri3 faces: the distance is convex
    S.Retry.push_back({ f, r, bound });
  if (activeOut)
    *activeOut = r.Active;
  Keep(r, f, best);
}

void ClosestBoundary(const EmbeddingMesh& M, const double v[3], const VertexHint& hint,
  BoundaryHit& best, VertexEmbedding& out, SearchScratch& S)
{
  const unsigned stamp = S.NextStamp();
  const TetMeshTopology& T = M.Topology;
  S.Retry.clear();
  if (hint.Face >= 0)
  {
    // Algorithm 1 on the boundary surface, explicit queue and visited stamps
    S.Queue.clear();
    S.Queue.push_back(hint.Face);
    S.FaceStamp[hint.Face] = stamp;
    for (size_t q = 0; q < S.Queue.size() && q < static_cast<size_t>(MaxWalk); ++q)
    {
      const Id f = S.Queue[q];
      int active = 0;
      const double before = best.Dist2;
      const double bound = q > 0 ? M.FaceLowerBound2(f, v) : -1.0;
      if (q > 0 && bound >= best.Dist2 * (1.0 - 1e-10))
        continue; // cannot improve the best: neither solve nor walk on from it
      SolveFace(M, v, f, f == hint.Face ? hint.UV : nullptr, bound, best, out, S, &active);
      if (!(best.Dist2 < before) && q > 0)
        continue; // no improvement: do not walk further from here
      const int k = PopCount(active & 7);
      auto push = [&](Id g) {
        if (g >= 0 && S.FaceStamp[g] != stamp)
        {
          S.FaceStamp[g] = stamp;
          S.Queue.push_back(g);
        }
      };
      if (k == 1)
      {
        push(T.BoundaryFaceNeighbor[3 * f + EdgeOfBit(active & 7)]);
      }
      else if (k >= 2)
      {
        const Id node = T.BoundaryFaceNodes[T.GetNodesPerFace() * f + CornerOfBits(active)];
        for (Id i = T.NodeFaceOffsets[node]; i < T.NodeFaceOffsets[node + 1]; ++i)
          push(T.NodeFaces[i]);
      }
    }
  }
  // certification: every face whose box is nearer than the best distance
  // (a face whose lower bound is within 1e-10 relative of the best cannot improve it by
  // more than that, far below the 1e-8 of the diagonal that matters)
  auto certify = [&](Id f) {
    if (S.FaceStamp[f] == stamp)
      return;
    const double bound = M.FaceLowerBound2(f, v);
    if (bound >= best.Dist2 * (1.0 - 1e-10))
      return;
    S.FaceStamp[f] = stamp;
    // a face the expansion at the flat triangle's closest point already puts beyond the
    // best distance needs neither a solve nor a certificate
    double start[2];
    LinearStart(M.FaceMaps[f], v, start);
    if (M.NodesPerCell() == 10 &&
      PatchFartherThan(M.FaceMaps[f], v, start, best.Dist2, CertifyTolerance * M.Diagonal))
      return;
    SolveFace(M, v, f, start, bound, best, out, S);
  };
  // the bins within the best distance when they are few (a point near the surface),
  // else the tree, nearest boxes first
  if (!M.FaceGrid.VisitNearer(v, best.Dist2, MaxGridBins, certify))
    M.GetFaceTree().VisitNearer(v, best.Dist2, certify);
  for (const auto& sf : S.Retry)
    RetryFace(M, v, sf, best, out);
}

// Find a cell containing v (distance <= tol). Without `useCellGrid`: a short walk from
// `start` with the cheap tests only (a hint that is usually right). With it: a
// breadth-first walk, then the cells the cell grid lists near v. `tolerance` (a
// distance; default InsideTolerance of the diagonal) and `skip` (a cell not to test)
// serve the outside proof at the closest boundary point (OutsideByFace). One function
// (~160 lines): the cell test (a lambda: cheap bounds, then the inversion, recording the
// exit face) is shared by the three phases, which also share the visit stamps, so a cell
// is tested once per query whichever phase reaches it.
bool LocateCell(const EmbeddingMesh& M, const double v[3], Id start, bool useCellGrid,
  VertexEmbedding& out, SearchScratch& S, int maxWalk = MaxWalk, double tolerance = -1.0,
  Id skip = -1)
{
  const double tol = tolerance >= 0.0 ? tolerance : InsideTolerance * M.Diagonal;
  const double tol2 = tol * tol;
  const unsigned stamp = S.NextStamp();
  ClosestPointResult r;
  // exit face of the walk when the fast test fails: opposite the most negative
  // barycentric coordinate of the (extrapolated) parametric point
  int exitFace = -1;
  // v is expected outside (no start cell): the Newton inversion either lands inside
  // the cell or, usually, proves v away from it (TetMapExcludes); else the constrained
  // solve decides
  const bool expectOutside = start < 0;
  // Newton stops once the point is clearly outside the element and this close: the
  // exclusion proof (or the constrained solve, or the walk's exit face) needs no more
  const double outsideStop = 1e-6 * M.Diagonal;
  auto test = [&](Id c, bool fastOnly) {
    if (fastOnly)
    {
      // beyond a slab of the cell: certainly not inside, leave through that face
      exitFace = M.CellExitFace(c, v, tol);
      if (exitFace >= 0)
      {
        ++out.Visited;
        return false;
      }
    }
    // v expected outside: the straight tet plus edge bumps usually proves it away
    // without a Newton iteration (TetBarycentricExcludes)
    if (expectOutside && !fastOnly && TetBarycentricExcludes(M.CellForms[c], v, tol))
    {
      ++out.Visited;
      return false;
    }
    double start[3];
    LinearStart(M.CellMaps[c], v, start);
    // fast path: plain Newton inversion from the straight tet's coordinates; accepted only
    // when it lands inside the cell
    double pc[3] = { start[0], start[1], start[2] };
    int its = 0;
    const double res = InvertTetMap(M.CellMaps[c], v, pc, its, 8, outsideStop);
    out.Iterations += its;
    ++out.Visited;
    if (res <= tol && pc[0] >= 0.0 && pc[1] >= 0.0 && pc[2] >= 0.0 && pc[0] + pc[1] + pc[2] <= 1.0)
    {
      out.Cell = c;
      for (int i = 0; i < 3; ++i)
        out.PC[i] = pc[i];
      out.Residual = res;
      return true;
    }
    if (expectOutside && !fastOnly && res <= std::max(tol, outsideStop))
    {
      // no point of the cell within tol of v; the cell's exclusion rate is computed once
      double& rate = S.ExclusionRate[c];
      if (rate < 0.0)
        rate = TetMapExclusionRate(M.CellMaps[c]);
      if (TetMapExclusionRadius(M.CellMaps[c], pc, rate) > tol + res)
        return false;
    }
    if (fastOnly)
    {
      const double L[4] = { 1.0 - pc[0] - pc[1] - pc[2], pc[0], pc[1], pc[2] };
      int k = 0;
      for (int a = 1; a < 4; ++a)
        if (L[a] < L[k])
          k = a;
      exitFace = TetCornerOppositeFace[k];
      return false;
    }
    ClosestPointOnMap(M.CellMaps[c], v, start, r);
    out.Iterations += r.Iterations;
    const ClosestPointResult* hit = r.Distance2 <= tol2 ? &r : nullptr;
    // On a strongly curved cell the solve from the straight tet's coordinates can stop
    // at a constrained local minimum on the cell's border although v is inside (the
    // centroid start then finds it inside; Benchmarks/RESULTS.md has the case): a
    // second try, Newton inversion from the centroid (cheaper than a second constrained
    // solve; TestEmbeddingNonConvexFace, TestCurvedCell).
    ClosestPointResult r2;
    if (!hit && r.Active != 0)
    {
      double pc2[3] = { 0.25, 0.25, 0.25 };
      int its2 = 0;
      const double res2 = InvertTetMap(M.CellMaps[c], v, pc2, its2, 20, outsideStop);
      out.Iterations += its2;
      if (res2 <= tol && pc2[0] >= 0.0 && pc2[1] >= 0.0 && pc2[2] >= 0.0 &&
        pc2[0] + pc2[1] + pc2[2] <= 1.0)
      {
        for (int i = 0; i < 3; ++i)
          r2.Param[i] = pc2[i];
        r2.Distance2 = res2 * res2;
        hit = &r2;
      }
    }
    if (hit)
    {
      out.Cell = c;
      for (int i = 0; i < 3; ++i)
        out.PC[i] = hit->Param[i];
      out.Residual = std::sqrt(hit->Distance2);
      return true;
    }
    return false;
  };
  S.Queue.clear();
  if (start >= 0)
  {
    S.Queue.push_back(start);
    S.CellStamp[start] = stamp;
  }
  if (maxWalk == 0)
    return start >= 0 && test(start, true);
  if (!useCellGrid)
  {
    // short walk from a hint: cheap tests, leave through the face the point is beyond
    Id c = start;
    for (int step = 0; step < maxWalk && c >= 0; ++step)
    {
      if (test(c, true))
        return true;
      c = exitFace >= 0 ? M.Topology.FaceNeighbor[4 * c + exitFace] : -1;
    }
    return false;
  }
  for (size_t q = 0; q < S.Queue.size() && q < static_cast<size_t>(maxWalk); ++q)
  {
    const Id c = S.Queue[q];
    if (test(c, false))
      return true;
    for (int b = 0; b < 4; ++b)
    {
      if (!(r.Active & (1 << b)))
        continue;
      const Id nb = M.Topology.FaceNeighbor[4 * c + FaceOfTetBit[b]];
      if (nb >= 0 && S.CellStamp[nb] != stamp)
      {
        S.CellStamp[nb] = stamp;
        S.Queue.push_back(nb);
      }
    }
  }
  if (!useCellGrid)
    return false;
  S.Candidates.clear();
  M.CellGrid.Containing(v, tol, S.Candidates);
  for (Id c : S.Candidates)
  {
    if (S.CellStamp[c] == stamp || c == skip)
      continue;
    S.CellStamp[c] = stamp;
    if (!M.CellMayContain(c, v, tol))
      continue;
    if (test(c, false))
      return true;
  }
  return false;
}

// Proof that v, on the outer side of its closest boundary point p (distance d, side test
// passed), is outside the mesh, when p lies inside a face f (no active constraint):
// - The open ball B(v, d*) (d* >= d - t the true distance, t = CertifyTolerance of the
//   diagonal) holds no point of a boundary face. The boundary of the union R of the cells
//   lies on boundary faces (positive Jacobians: interior faces, edges and nodes are
//   covered from all sides), so the ball lies entirely inside R or entirely outside.
// - y = p + 2t (v - p) / d lies in the ball. The owner cell of f holds no point just
//   outside f at p (det J > 0: near p it lies on the inner side), so if v is inside, y is
//   inside another cell c, and p is within 2t of c.
// So when no cell other than the owner holds p within 2t (+ the inside tolerance), v is
// outside. Returns true when proven; false (test v itself) for p on an edge or corner of
// f, distances within a few t, or a cell holding p (a boundary that crosses itself).
bool OutsideByFace(const EmbeddingMesh& M, const BoundaryHit& hit, double d, Id owner,
  VertexEmbedding& out, SearchScratch& S)
{
  const double t = CertifyTolerance * M.Diagonal;
  if ((hit.Active & 7) != 0 || !(d > 4.0 * t))
    return false;
  const double reach = 2.0 * t + InsideTolerance * M.Diagonal;
  return !LocateCell(M, hit.Point, -1, true, out, S, MaxWalk, reach, owner);
}

// The correction's start at the closest point: a point on an edge or at a corner of its
// face lies on the faces around it too, and which of them the search named depends on
// where it came from (the flood's starting points). Where v = p + d n has several
// solutions (beyond the normal field's focal distance) the start decides which one the
// correction reaches, so it starts from the lowest-numbered of those faces.
void CanonicalStart(const EmbeddingMesh& M, const BoundaryHit& hit, Id& f, double uv[2])
{
  const TetMeshTopology& T = M.Topology;
  const int k = PopCount(hit.Active & 7);
  if (k == 1)
  {
    const int e = EdgeOfBit(hit.Active & 7);
    const Id g = T.BoundaryFaceNeighbor[3 * f + e];
    double uvg[2];
    if (g >= 0 && g < f && MapAcrossEdge(M, f, e, uv, g, uvg))
    {
      f = g;
      uv[0] = uvg[0];
      uv[1] = uvg[1];
    }
  }
  else if (k >= 2)
  {
    const int npf = T.GetNodesPerFace();
    const Id node = T.BoundaryFaceNodes[npf * f + CornerOfBits(hit.Active)];
    for (Id i = T.NodeFaceOffsets[node]; i < T.NodeFaceOffsets[node + 1]; ++i)
    {
      const Id g = T.NodeFaces[i];
      if (g >= f)
        continue;
      for (int a = 0; a < 3; ++a)
        if (T.BoundaryFaceNodes[npf * g + a] == node)
        {
          f = g;
          uv[0] = CornerUV[a][0];
          uv[1] = CornerUV[a][1];
        }
    }
  }
}

void SetInside(VertexEmbedding& out)
{
  out.Inside = true;
  out.Distance = 0.0;
  out.ClosestDistance = 0.0;
  out.Face = -1;
}
} // namespace

VertexHint VertexEmbedding::AsHint(const double v[3]) const
{
  VertexHint h;
  h.Point[0] = v[0];
  h.Point[1] = v[1];
  h.Point[2] = v[2];
  // a distance that may be a local minimum only proves nothing
  h.Distance = this->Uncertified ? -1.0 : this->ClosestDistance;
  h.Face = this->BoundaryFace;
  h.UV[0] = this->UV[0];
  h.UV[1] = this->UV[1];
  h.Cell = this->Cell;
  h.Inside = this->Inside;
  return h;
}

void SearchScratch::Prepare(const EmbeddingMesh& mesh)
{
  this->FaceStamp.assign(mesh.Topology.GetNumberOfBoundaryFaces(), 0u);
  this->CellStamp.assign(mesh.Topology.NumberOfCells, 0u);
  this->ExclusionRate.assign(mesh.Topology.NumberOfCells, -1.0);
  this->Stamp = 0;
}

unsigned SearchScratch::NextStamp()
{
  if (++this->Stamp == 0)
  {
    std::fill(this->FaceStamp.begin(), this->FaceStamp.end(), 0u);
    std::fill(this->CellStamp.begin(), this->CellStamp.end(), 0u);
    this->Stamp = 1;
  }
  return this->Stamp;
}

double ReconstructionResidual(
  const EmbeddingMesh& M, const double v[3], Id cell, const double pc[3], int face, double d)
{
  double p[3];
  M.CellPoint(cell, pc, p);
  double n[3] = { 0, 0, 0 };
  if (face >= 0)
  {
    const Id bf = M.Topology.CellBoundaryFace[4 * cell + face];
    if (bf >= 0)
    {
      const double L[4] = { 1.0 - pc[0] - pc[1] - pc[2], pc[0], pc[1], pc[2] };
      const double uv[2] = { L[TetFaceNodes[face][1]], L[TetFaceNodes[face][2]] };
      InterpolateBoundaryNormal(M.Topology, M.NodalNormals.data(), bf, uv, n);
    }
  }
  double r[3];
  for (int k = 0; k < 3; ++k)
    r[k] = v[k] - p[k] - d * n[k];
  return std::sqrt(Dot(r, r));
}

namespace
{
/// |v - (p + J(pc) q)|, p and J of the cell's map at pc (the fallback's reconstruction)
double FallbackResidual(
  const EmbeddingMesh& M, const double v[3], Id cell, const double pc[3], const double q[3])
{
  double J[3][3], x[3], r[3];
  detail::Eval<3>(M.CellMaps[cell], pc, x, J);
  M.CellPoint(cell, pc, x);
  for (int k = 0; k < 3; ++k)
    r[k] = v[k] - x[k] - (J[0][k] * q[0] + J[1][k] * q[1] + J[2][k] * q[2]);
  return std::sqrt(Dot(r, r));
}

// Step 4 of EmbedVertex for an outside vertex: from the closest boundary point `hit` (at
// distance `dist`), the point p and offset d with v = p + d n (paper eq. 8-9), walking
// across boundary edges; when that fails, every face around the corners of the closest
// face, then every face within reach (smallest |d|); only feet within reach count; else
// the flagged
// fallback (closest point p and the parametric offset q with v = p + J(p) q).
void CorrectNormalOffset(const EmbeddingMesh& M, const double v[3], const BoundaryHit& hit,
  double dist, VertexEmbedding& out, SearchScratch& S)
{
  const TetMeshTopology& T = M.Topology;
  const double tolF = CorrectionTolerance * M.Diagonal;
  auto correct = [&](Id& f, double uv[2], double& d) {
    int status = -1;
    for (int sw = 0; sw < 16; ++sw)
    {
      status = SolveNormalOffset(M.FaceMaps[f], M.NormalMaps[f], v, uv, d, tolF, out.Iterations);
      if (status <= 0)
        break;
      const int e = status - 1;
      const Id g = T.BoundaryFaceNeighbor[3 * f + e];
      double uvg[2];
      if (g < 0 || !MapAcrossEdge(M, f, e, uv, g, uvg))
        return false;
      f = g;
      uv[0] = uvg[0];
      uv[1] = uvg[1];
      ++out.Visited;
    }
    return status == 0;
  };
  // A solution's foot p lies |d| from v (n has unit length), and the closest point lies
  // dist from v: a walk may converge onto a foot far across the mesh (beyond the normal
  // field's focal distance v = p + d n has several solutions), where |d| is many times
  // dist and the transfer would swing v on a long lever. Only feet within `reach` count,
  // the faces the wide search below looks at; which far foot a walk reaches depends on
  // where it started, so this also keeps the result independent of the flood's starts.
  // 8 x dist: the smooth normal leans from the true one in concave regions and on tet4's
  // faceted normals, so a near foot can lie several times as far as the closest point
  // (ratios measured: Benchmarks/RESULTS.md, Embedding).
  const double reach = 8.0 * dist + 1e-6 * M.Diagonal;
  auto correctNear = [&](Id& fc, double w[2], double& dc) {
    return correct(fc, w, dc) && std::fabs(dc) <= reach;
  };
  Id f = hit.Face;
  double uv[2] = { hit.UV[0], hit.UV[1] };
  CanonicalStart(M, hit, f, uv);
  const Id start = f;
  double d = dist;
  bool ok = correctNear(f, uv, d);
  if (!ok)
  {
    // fallback: every face around the corners of the (canonical) closest face, from its
    // centroid
    const int npf = T.GetNodesPerFace();
    for (int a = 0; a < 3 && !ok; ++a)
    {
      const Id node = T.BoundaryFaceNodes[npf * start + a];
      for (Id i = T.NodeFaceOffsets[node]; i < T.NodeFaceOffsets[node + 1] && !ok; ++i)
      {
        f = T.NodeFaces[i];
        uv[0] = uv[1] = 1.0 / 3.0;
        d = dist;
        ++out.Visited;
        ok = correctNear(f, uv, d);
      }
    }
    if (!ok)
    {
      // wider fallback: every face within reach, keep the smallest |d|
      S.Candidates.clear();
      const double reach2 = reach * reach;
      M.GetFaceTree().VisitNearer(v, reach2, [&](Id g) { S.Candidates.push_back(g); });
      double bestD = std::numeric_limits<double>::infinity();
      Id bestF = -1;
      double bestUV[2] = { 0, 0 };
      const double starts[4][2] = { { 1.0 / 3.0, 1.0 / 3.0 }, { 0.8, 0.1 }, { 0.1, 0.8 },
        { 0.1, 0.1 } };
      for (size_t k = 0; k < 4 * S.Candidates.size(); ++k)
      {
        Id fg = S.Candidates[k / 4];
        double w[2] = { starts[k % 4][0], starts[k % 4][1] };
        double dg = dist;
        ++out.Visited;
        if (correctNear(fg, w, dg) && std::fabs(dg) < bestD)
        {
          bestD = std::fabs(dg);
          bestF = fg;
          bestUV[0] = w[0];
          bestUV[1] = w[1];
          d = dg;
        }
      }
      if (bestF >= 0)
      {
        ok = true;
        f = bestF;
        uv[0] = bestUV[0];
        uv[1] = bestUV[1];
      }
    }
    if (!ok)
    {
      // no normal offset rebuilds v (the normal field does not reach it, or v is so far
      // away that the round-off of d n exceeds the tolerance): the closest point p and
      // the offset v - p, in the cell's parametric units so that the transfer carries
      // it with the deformation gradient at p (exact at rest)
      const Id owner = T.BoundaryFaceCell[hit.Face];
      TetFaceToTetParametric(T.BoundaryFaceLocal[hit.Face], hit.UV, out.PC);
      out.Cell = owner;
      out.Fallback = true;
      double q[3];
      TetMapOffset(M.CellMaps[owner], out.PC, v, q);
      out.Distance = 0.0;
      out.Face = -1;
      out.Residual = FallbackResidual(M, v, owner, out.PC, q);
      return;
    }
  }
  out.Cell = T.BoundaryFaceCell[f];
  out.Face = static_cast<signed char>(T.BoundaryFaceLocal[f]);
  TetFaceToTetParametric(out.Face, uv, out.PC);
  out.Distance = d;
  out.Residual = ReconstructionResidual(M, v, out.Cell, out.PC, out.Face, d);
}
} // namespace

void EmbedVertex(const EmbeddingMesh& M, int method, const double v[3], const VertexHint& hint,
  VertexEmbedding& out, SearchScratch& S)
{
  out = VertexEmbedding();
  const TetMeshTopology& T = M.Topology;
  // a neighbour farther from the mesh than from v proves v outside (1-Lipschitz distance;
  // the neighbour's distance is certified to within t of the true one)
  const double t = CertifyTolerance * M.Diagonal;
  const double toHint[3] = { v[0] - hint.Point[0], v[1] - hint.Point[1], v[2] - hint.Point[2] };
  const double hintGap = std::sqrt(Dot(toHint, toHint)); // |v - neighbour|
  bool provenOutside =
    hint.Distance > 0.0 && hint.Distance - t - hintGap > InsideTolerance * M.Diagonal;
  // 1. inside, from an inside neighbour: walk through a few cells. (From an outside
  // neighbour, trying its cell first found v inside in about 1 case of 10, so those go
  // straight to the boundary search; step 3 locates the few inside ones.)
  if (!provenOutside && hint.Cell >= 0 && hint.Inside &&
    LocateCell(M, v, hint.Cell, false, out, S, 8))
  {
    SetInside(out);
    out.BoundaryFace = hint.Face;
    out.UV[0] = hint.UV[0];
    out.UV[1] = hint.UV[1];
    return;
  }
  VertexHint h = hint;
  if (h.Face < 0 && h.Cell >= 0)
  {
    for (int k = 0; k < 4 && h.Face < 0; ++k)
      h.Face = T.CellBoundaryFace[4 * h.Cell + k];
    h.UV[0] = h.UV[1] = 1.0 / 3.0;
  }
  if (h.Face < 0)
  {
    // no start (a flood's seed, or an interior cell): the walk starts from a face near v
    // in the face grid (cheaper than the tree's nearest-first search from an infinite
    // distance, and the tree is then rarely built at all)
    h.Face = M.FaceGrid.NearItem(v);
    h.UV[0] = h.UV[1] = 1.0 / 3.0;
  }
  // 2. closest boundary point (walk + certification)
  BoundaryHit hit;
  ClosestBoundary(M, v, h, hit, out, S);
  out.BoundaryFace = hit.Face;
  out.UV[0] = hit.UV[0];
  out.UV[1] = hit.UV[1];
  const double dist = std::sqrt(hit.Dist2);
  const Id owner = T.BoundaryFaceCell[hit.Face];
  const int local = T.BoundaryFaceLocal[hit.Face];
  if (dist <= InsideTolerance * M.Diagonal && !provenOutside)
  {
    out.Cell = owner;
    TetFaceToTetParametric(local, hit.UV, out.PC);
    SetInside(out);
    out.Residual = ReconstructionResidual(M, v, out.Cell, out.PC, -1, 0.0);
    return;
  }
  // 3. inside or outside. Proof from the outside neighbour: the open balls around it and
  // around v, of their certified distances less t, hold no boundary point; when they
  // meet, their union is connected, so it lies wholly outside the mesh or wholly inside
  // (the boundary of the union of the cells lies on the boundary faces), and the
  // neighbour is outside. (This saves the cell queries of the tests below for nearly every
  // outside vertex of a surface whose edges are longer than its distance to the mesh.)
  if (!provenOutside && hint.Distance > 0.0 && !hint.Inside)
  {
    const double rh = hint.Distance - t, rv = dist - t;
    provenOutside = rh > 0.0 && rv > 0.0 && hintGap < rh + rv - InsideTolerance * M.Diagonal;
  }
  if (!provenOutside)
  {
    double n[3], w[3];
    PseudoNormal(M, hit, n);
    for (int k = 0; k < 3; ++k)
      w[k] = v[k] - hit.Point[k];
    const double side = Dot(w, n);
    const double margin = 0.2 * dist * std::sqrt(Dot(n, n));
    // The pseudo-normal decides only where the curved boundary is an embedded surface.
    // Curved cells may poke through a boundary face of another part of the mesh (a thin
    // region whose two sides cross after curving): then v lies outside that face and
    // still inside a cell. So an "outside" verdict is confirmed against every cell whose
    // control-point box and slabs hold v (usually none or one: cheap).
    // On the outer side of the interior of a face, v is outside unless a cell other
    // than the face's owner holds the closest point p (the test of OutsideByFace), which
    // costs about half of testing v against every cell that may hold it.
    const bool inside = side <= margin
      ? LocateCell(M, v, owner, true, out, S)
      : !OutsideByFace(M, hit, dist, owner, out, S) && LocateCell(M, v, -1, true, out, S);
    if (inside)
    {
      SetInside(out);
      return;
    }
  }
  out.Inside = false;
  out.ClosestDistance = dist;
  out.Cell = owner;
  if (method == EMBED_BARYCENTRIC)
  {
    TetFaceToTetParametric(local, hit.UV, out.PC);
    InvertTetMap(M.CellMaps[owner], v, out.PC, out.Iterations);
    out.Distance = 0.0;
    out.Face = -1;
    out.Residual = ReconstructionResidual(M, v, out.Cell, out.PC, -1, 0.0);
    return;
  }
  // 4. normal-offset correction (eq. 8-9)
  CorrectNormalOffset(M, v, hit, dist, out, S);
}

double BruteForceDistance(const EmbeddingMesh& M, const double v[3], Id* face, double* uv)
{
  const double faceStarts[7][2] = { { 1.0 / 3, 1.0 / 3 }, { 0.8, 0.1 }, { 0.1, 0.8 }, { 0.1, 0.1 },
    { 0.45, 0.45 }, { 0.45, 0.1 }, { 0.1, 0.45 } };
  const double cellStarts[5][3] = { { 0.25, 0.25, 0.25 }, { 0.7, 0.1, 0.1 }, { 0.1, 0.7, 0.1 },
    { 0.1, 0.1, 0.7 }, { 0.1, 0.1, 0.1 } };
  double best = std::numeric_limits<double>::infinity();
  ClosestPointResult r;
  for (Id f = 0; f < M.Topology.GetNumberOfBoundaryFaces(); ++f)
    for (const auto& s : faceStarts)
    {
      ClosestPointOnMap(M.FaceMaps[f], v, s, r, 200);
      if (r.Distance2 < best)
      {
        best = r.Distance2;
        if (face)
          *face = f;
        if (uv)
        {
          uv[0] = r.Param[0];
          uv[1] = r.Param[1];
        }
      }
    }
  const double tol = InsideTolerance * M.Diagonal;
  for (Id c = 0; c < M.Topology.NumberOfCells; ++c)
    for (const auto& s : cellStarts)
    {
      ClosestPointOnMap(M.CellMaps[c], v, s, r, 200);
      if (r.Distance2 <= tol * tol)
        return 0.0;
    }
  return std::sqrt(best);
}
} // namespace hoembed
