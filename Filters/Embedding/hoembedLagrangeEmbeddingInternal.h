// What hoembed::LagrangeEmbeddingMesh (hoembedLagrangeEmbedding.cxx,
// hoembedLagrangeFaceSearch.cxx: tetrahedra, triangular faces) and
// hoembed::LagrangeHexEmbeddingMesh (hoembedLagrangeHexEmbedding.cxx: hexahedra,
// quadrilateral faces) share: small numerical pieces, the local solve on a face, the
// certified search of a face (over a policy of its sub-patches), and the embedding of one
// vertex (inside cells, the normal-offset walk, the fallback), written
// once over an adapter of the mesh (see LagrangeCells below). Private.
#ifndef hoembedLagrangeEmbeddingInternal_h
#define hoembedLagrangeEmbeddingInternal_h

#include "hoembedAabbTree.h"
#include "hoembedEmbeddingFlood.h"  // EMBED_* values
#include "hoembedEmbeddingSearch.h" // VertexEmbedding

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace hoembed
{
namespace lagrange_detail
{
using LagrangeId = std::int64_t;

inline double Dot(const double a[3], const double b[3])
{
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

// Solve A x = b (3 x 3, A[r][c]) by Cramer's rule; false when singular.
inline bool Solve3(const double A[3][3], const double b[3], double x[3])
{
  const double det = A[0][0] * (A[1][1] * A[2][2] - A[1][2] * A[2][1]) -
    A[0][1] * (A[1][0] * A[2][2] - A[1][2] * A[2][0]) +
    A[0][2] * (A[1][0] * A[2][1] - A[1][1] * A[2][0]);
  double scale = 0.0;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      scale = std::max(scale, std::abs(A[r][c]));
  if (!(std::abs(det) > 1e-300) || !(std::abs(det) > 1e-14 * scale * scale * scale))
    return false;
  for (int k = 0; k < 3; ++k)
  {
    double M[3][3];
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c)
        M[r][c] = c == k ? b[r] : A[r][c];
    x[k] = (M[0][0] * (M[1][1] * M[2][2] - M[1][2] * M[2][1]) -
             M[0][1] * (M[1][0] * M[2][2] - M[1][2] * M[2][0]) +
             M[0][2] * (M[1][0] * M[2][1] - M[1][1] * M[2][0])) /
      det;
  }
  return true;
}

// Interval arithmetic of the branch and bound's Hessian bounds.
struct Interval
{
  double Lo = HUGE_VAL, Hi = -HUGE_VAL;
  void Add(double x)
  {
    Lo = std::min(Lo, x);
    Hi = std::max(Hi, x);
  }
};
inline Interval Mul(const Interval& a, const Interval& b)
{
  Interval r;
  r.Add(a.Lo * b.Lo);
  r.Add(a.Lo * b.Hi);
  r.Add(a.Hi * b.Lo);
  r.Add(a.Hi * b.Hi);
  return r;
}
inline Interval Square(const Interval& a)
{
  Interval r;
  r.Lo = a.Lo > 0 ? a.Lo * a.Lo : (a.Hi < 0 ? a.Hi * a.Hi : 0.0);
  r.Hi = std::max(a.Lo * a.Lo, a.Hi * a.Hi);
  return r;
}
inline Interval Sum(const Interval& a, const Interval& b)
{
  Interval r;
  r.Lo = a.Lo + b.Lo;
  r.Hi = a.Hi + b.Hi;
  return r;
}

// Euclidean projection of (u, v) onto the reference triangle.
inline void ProjectTriangle(double uv[2])
{
  double u = uv[0], v = uv[1];
  if (u + v > 1.0)
  {
    const double s = 0.5 * (u + v - 1.0);
    u -= s;
    v -= s;
  }
  u = std::max(0.0, u);
  v = std::max(0.0, v);
  if (u > 1.0)
    u = 1.0;
  if (v > 1.0 - u)
    v = 1.0 - u;
  uv[0] = u;
  uv[1] = v;
}

// (u, v) clamped into the unit square.
inline void ClampSquare(double uv[2])
{
  uv[0] = std::min(1.0, std::max(0.0, uv[0]));
  uv[1] = std::min(1.0, std::max(0.0, uv[1]));
}

// The two face domains (of LocalFaceSolve and the normal-offset walk): Project puts
// (u, v) into the domain; Binding counts the sides at which the gradient g of the
// distance pushes (u, v) out, and for one such side gives the direction t along it.
struct TriangleDomain
{
  static constexpr int Edges = 3; // 0: v = 0 (corners 0-1), 1: u + v = 1 (1-2), 2: u = 0 (2-0)
  static constexpr double Centre = 1.0 / 3.0;
  static bool Inside(const double uv[2], double e)
  {
    return uv[0] >= -e && uv[1] >= -e && uv[0] + uv[1] <= 1 + e;
  }
  // the side that the step from uv crosses first, with a lowered to the fraction of the
  // step that reaches it; -1 when no side is crossed before a
  static int Exit(const double uv[2], const double step[3], double& a)
  {
    const double t[2] = { uv[0] + step[0], uv[1] + step[1] };
    int side = -1;
    if (t[1] < 0 && step[1] < 0)
    {
      const double s = -uv[1] / step[1];
      if (s < a)
        a = s, side = 0;
    }
    if (t[0] + t[1] > 1 && step[0] + step[1] > 0)
    {
      const double s = (1 - uv[0] - uv[1]) / (step[0] + step[1]);
      if (s < a)
        a = s, side = 1;
    }
    if (t[0] < 0 && step[0] < 0)
    {
      const double s = -uv[0] / step[0];
      if (s < a)
        a = s, side = 2;
    }
    return side;
  }
  // the parameter along edge e (0 at its first corner) of a point uv on it, and back
  static double EdgeParameter(int e, const double uv[2])
  {
    return e == 0 ? uv[0] : (e == 1 ? uv[1] : 1 - uv[1]);
  }
  static void OnEdge(int e, double t, double uv[2])
  {
    if (e == 0)
      uv[0] = t, uv[1] = 0;
    else if (e == 1)
      uv[0] = 1 - t, uv[1] = t;
    else
      uv[0] = 0, uv[1] = 1 - t;
  }
  static void Project(double uv[2])
  {
    ProjectTriangle(uv);
  }
  static int Binding(const double uv[2], const double g[2], double t[2])
  {
    const double eps = 1e-15;
    const bool b0 = uv[0] <= eps && g[0] > 0, b1 = uv[1] <= eps && g[1] > 0;
    const bool b2 = uv[0] + uv[1] >= 1 - eps && g[0] + g[1] < 0;
    t[0] = b0 ? 0.0 : 1.0;
    t[1] = b0 ? 1.0 : (b1 ? 0.0 : -1.0);
    return int(b0) + int(b1) + int(b2);
  }
};
struct SquareDomain
{
  static constexpr int Edges = 4; // 0: v = 0, 1: u = 1, 2: v = 1, 3: u = 0 (corner e to e + 1)
  static constexpr double Centre = 0.5;
  static bool Inside(const double uv[2], double e)
  {
    return uv[0] >= -e && uv[1] >= -e && uv[0] <= 1 + e && uv[1] <= 1 + e;
  }
  static int Exit(const double uv[2], const double step[3], double& a)
  {
    int side = -1;
    auto cross = [&](double from, double st, double bound, int sd) {
      if (st == 0.0)
        return;
      const double to = from + st;
      if ((bound == 0.0 && to < 0.0) || (bound == 1.0 && to > 1.0))
      {
        const double sv = (bound - from) / st;
        if (sv < a)
          a = sv, side = sd;
      }
    };
    cross(uv[1], step[1], 0.0, 0);
    cross(uv[0], step[0], 1.0, 1);
    cross(uv[1], step[1], 1.0, 2);
    cross(uv[0], step[0], 0.0, 3);
    return side;
  }
  static double EdgeParameter(int e, const double uv[2])
  {
    return e == 0 ? uv[0] : (e == 1 ? uv[1] : (e == 2 ? 1 - uv[0] : 1 - uv[1]));
  }
  static void OnEdge(int e, double t, double uv[2])
  {
    const double at[4][2] = { { t, 0 }, { 1, t }, { 1 - t, 1 }, { 0, 1 - t } };
    uv[0] = at[e][0];
    uv[1] = at[e][1];
  }
  static void Project(double uv[2])
  {
    ClampSquare(uv);
  }
  static int Binding(const double uv[2], const double g[2], double t[2])
  {
    const double eps = 1e-15;
    bool bound[2];
    for (int k = 0; k < 2; ++k)
      bound[k] = (uv[k] <= eps && g[k] > 0) || (uv[k] >= 1 - eps && g[k] < 0);
    t[0] = bound[0] ? 0.0 : 1.0;
    t[1] = bound[0] ? 1.0 : 0.0;
    return int(bound[0]) + int(bound[1]);
  }
};

// Local closest point on one face: projected Newton over the face's reference domain
// (Domain: an active set of its sides), monotone in |x - v|^2. eval(uv, x, xu, xv, H)
// gives the point, its derivatives and the second derivatives (H[0] = xuu, H[1] = xuv,
// H[2] = xvv). Returns that squared distance; `iterations` counts the Newton steps.
template <typename Domain, typename Eval>
double LocalFaceSolve(const Eval& eval, const double v[3], double uv[2], int& iterations)
{
  Domain::Project(uv);
  double x[3], xu[3], xv[3], H[3][3];
  eval(uv, x, xu, xv, H);
  double e[3] = { x[0] - v[0], x[1] - v[1], x[2] - v[2] };
  double f = Dot(e, e);
  for (int it = 0; it < 60; ++it)
  {
    ++iterations;
    const double g[2] = { 2 * Dot(xu, e), 2 * Dot(xv, e) };
    double A[2][2] = { { 2 * (Dot(xu, xu) + Dot(e, H[0])), 2 * (Dot(xu, xv) + Dot(e, H[1])) },
      { 0, 2 * (Dot(xv, xv) + Dot(e, H[2])) } };
    A[1][0] = A[0][1];
    double t[2];
    const int nb = Domain::Binding(uv, g, t);
    double step[2] = { 0, 0 };
    if (nb >= 2)
      break; // a corner with both sides binding: a KKT point
    if (nb == 1)
    {
      // Newton along the binding side
      const double gt = g[0] * t[0] + g[1] * t[1];
      const double ht =
        t[0] * (A[0][0] * t[0] + A[0][1] * t[1]) + t[1] * (A[1][0] * t[0] + A[1][1] * t[1]);
      const double a = ht > 0 ? -gt / ht : -gt;
      step[0] = a * t[0];
      step[1] = a * t[1];
    }
    else
    {
      // Newton, shifted to positive definite where the Hessian is not
      const double tr = A[0][0] + A[1][1];
      double mu = 0.0;
      const double det = A[0][0] * A[1][1] - A[0][1] * A[1][0];
      if (!(A[0][0] > 0 && det > 1e-14 * tr * tr))
      {
        const double disc = std::sqrt(std::max(0.0, 0.25 * tr * tr - det));
        const double lmin = 0.5 * tr - disc;
        mu = -lmin + 1e-3 * std::abs(tr) + 1e-300;
      }
      const double a00 = A[0][0] + mu, a11 = A[1][1] + mu;
      const double dd = a00 * a11 - A[0][1] * A[1][0];
      if (!(dd > 0))
      {
        step[0] = -g[0];
        step[1] = -g[1];
      }
      else
      {
        step[0] = -(a11 * g[0] - A[0][1] * g[1]) / dd;
        step[1] = -(a00 * g[1] - A[1][0] * g[0]) / dd;
      }
    }
    double alpha = 1.0;
    bool moved = false;
    for (int ls = 0; ls < 40; ++ls, alpha *= 0.5)
    {
      double s[2] = { uv[0] + alpha * step[0], uv[1] + alpha * step[1] };
      Domain::Project(s);
      double y[3], yu[3], yv[3], yH[3][3];
      eval(s, y, yu, yv, yH);
      const double en[3] = { y[0] - v[0], y[1] - v[1], y[2] - v[2] };
      const double fn = Dot(en, en);
      if (fn <= f)
      {
        const double change = std::abs(s[0] - uv[0]) + std::abs(s[1] - uv[1]);
        uv[0] = s[0];
        uv[1] = s[1];
        std::copy(y, y + 3, x);
        std::copy(yu, yu + 3, xu);
        std::copy(yv, yv + 3, xv);
        for (int k = 0; k < 3; ++k)
          std::copy(yH[k], yH[k] + 3, H[k]);
        std::copy(en, en + 3, e);
        moved = change > 1e-16;
        f = fn;
        break;
      }
    }
    if (!moved)
      break;
  }
  return f;
}

// The bounding box (lo, hi) of a cell's n control points (3 per point): the cell lies in
// their convex hull.
inline void ControlPointBox(const double* ctrl, int n, double box[6])
{
  for (int d = 0; d < 3; ++d)
  {
    box[d] = HUGE_VAL;
    box[d + 3] = -HUGE_VAL;
  }
  for (int k = 0; k < n; ++k)
    for (int d = 0; d < 3; ++d)
    {
      box[d] = std::min(box[d], ctrl[3 * k + d]);
      box[d + 3] = std::max(box[d + 3], ctrl[3 * k + d]);
    }
}

// The first cell flagged in `invalid`, or n when none is.
inline LagrangeId FirstFlagged(const std::vector<unsigned char>& invalid, LagrangeId n)
{
  for (LagrangeId c = 0; c < n; ++c)
    if (invalid[c])
      return c;
  return n;
}

// The nearest boundary point over the faces whose boxes may hold a point nearer than the
// best so far (search(f, best2, face, uv, certified) lowers best2 on face f); returns
// best2, with the number of faces searched.
template <typename Search>
double NearestOverFaces(const AabbTree& faces, const double v[3], LagrangeId& face, double uv[2],
  bool& certified, int* facesSearched, const Search& search)
{
  double best2 = HUGE_VAL;
  face = -1;
  certified = true;
  int searched = 0;
  faces.VisitNearer(v, best2, [&](LagrangeId f) {
    ++searched;
    search(f, best2, face, uv, certified);
  });
  if (facesSearched)
    *facesSearched = searched;
  return best2;
}

/*
 * The certified closest point on one curved face: a branch and bound over sub-patches of
 * the face's parameter domain (LagrangeEmbeddingMesh: sub-triangles,
 * LagrangeHexEmbeddingMesh: sub-squares), lowering best2 / bestFace / bestUV where the
 * face holds a point nearer than best2. A sub-patch is dropped when a lower bound of
 * |x - v|^2 over it (the box of its Bernstein net, then a second-order bound from an
 * interval Hessian) cannot beat best2 by the mesh's search tolerance; else a local solve
 * starts in it and it is split. `certified` turns false when the budget or the depth runs
 * out before every sub-patch was settled. Over a policy P of the sub-patches:
 *   using Sub; static constexpr int Budget, MaxDepth; Sub Root();
 *   void Net(s, net) (its Bernstein net, 3 per control point; count() of them);
 *   void Derivatives(net, xs, xt, xss, xst, xtt) (interval bounds of the first and second
 *     derivatives in the sub-patch's own coordinates);
 *   void Centre(s, c); bool Inside(s, u);
 *   double CornerBound(s, c, g, lambda): the least of f(c) + g . d + min(0, lambda) / 2
 *     |d|^2 (d in the sub-patch's own coordinates) over its corners, f(c) left out;
 *   int Split(s, stack, top): pushes its 4 children, returns the new top.
 * and a mesh M with FacePoint(f, uv, x[, xu, xv[, H]]), SearchTolerance and Diagonal.
 */
template <typename Patches, typename Mesh>
void SearchFacePatches(const Patches& P, const Mesh& M, LagrangeId f, const double v[3],
  double& best2, LagrangeId& bestFace, double bestUV[2], bool& certified)
{
  using Sub = typename Patches::Sub;
  auto eval = [&](const double uv[2], double x[3], double xu[3], double xv[3], double H[3][3]) {
    M.FacePoint(f, uv, x, xu, xv, H);
  };
  const double tol = M.SearchTolerance * M.Diagonal;
  auto threshold = [&]() {
    const double r = std::max(0.0, std::sqrt(best2) - tol);
    return r * r;
  };
  // this face's own local solution (a KKT point of the face: the tight place to bound
  // from, also when another face holds the same point as the best one)
  double ownUV[2] = { 0, 0 }, ownD2 = HUGE_VAL;
  auto tryStart = [&](double uv[2]) {
    int its = 0;
    const double d2 = LocalFaceSolve<typename Patches::Domain>(eval, v, uv, its);
    if (d2 < ownD2)
    {
      ownD2 = d2;
      ownUV[0] = uv[0];
      ownUV[1] = uv[1];
    }
    if (d2 < best2)
    {
      best2 = d2;
      bestFace = f;
      bestUV[0] = uv[0];
      bestUV[1] = uv[1];
    }
  };
  // Second-order bound at a point c of the sub-patch: for every u in it, with d the
  // sub-patch's own coordinates of u - c, f(u) >= f(c) + grad f(c) . d + lambda / 2 |d|^2;
  // with lambda < 0 that is concave in d, so its minimum is at a corner; with lambda >= 0
  // the linear part alone (at a corner too) is a bound. c: the best point when it lies in
  // the sub-patch (then grad f . d >= 0 there and the bound is tight), else the centre.
  auto secondOrder = [&](const Sub& s, const double c[2], double lambda, double& fc) {
    double x[3], xu[3], xv[3];
    M.FacePoint(f, c, x, xu, xv);
    const double e[3] = { x[0] - v[0], x[1] - v[1], x[2] - v[2] };
    fc = Dot(e, e);
    const double g[2] = { 2 * Dot(xu, e), 2 * Dot(xv, e) };
    return fc + P.CornerBound(s, c, g, lambda);
  };
  // no solve up front: the root's bounds drop most faces a search visits, and where they
  // do not, a local solve starts from the first sub-patch holding a nearer point
  Sub stack[256];
  int top = 0;
  stack[top++] = P.Root();
  int budget = Patches::Budget;
  double net[3 * 16];
  while (top > 0)
  {
    const Sub s = stack[--top];
    if (--budget < 0)
    {
      certified = false;
      return;
    }
    const int n = P.Net(s, net);
    // the box lower bound (convex hull of the net)
    Interval box[3];
    for (int i = 0; i < n; ++i)
      for (int d = 0; d < 3; ++d)
        box[d].Add(net[3 * i + d]);
    double lb = 0.0;
    for (int d = 0; d < 3; ++d)
    {
      const double gap = std::max(0.0, std::max(box[d].Lo - v[d], v[d] - box[d].Hi));
      lb += gap * gap;
    }
    if (lb >= threshold())
      continue;
    // interval Hessian of f = |x - v|^2 in the sub-patch's own coordinates (s, t)
    double lambda = 0.0; // lower bound of the smallest eigenvalue of the Hessian of f
    {
      Interval xs[3], xt[3], xss[3], xst[3], xtt[3];
      P.Derivatives(net, xs, xt, xss, xst, xtt);
      Interval hss, htt, hst;
      hss.Lo = hss.Hi = htt.Lo = htt.Hi = hst.Lo = hst.Hi = 0.0;
      for (int d = 0; d < 3; ++d)
      {
        Interval e;
        e.Lo = box[d].Lo - v[d];
        e.Hi = box[d].Hi - v[d];
        hss = Sum(hss, Sum(Square(xs[d]), Mul(e, xss[d])));
        htt = Sum(htt, Sum(Square(xt[d]), Mul(e, xtt[d])));
        hst = Sum(hst, Sum(Mul(xs[d], xt[d]), Mul(e, xst[d])));
      }
      const double off = std::max(std::abs(hst.Lo), std::abs(hst.Hi));
      // the smallest eigenvalue of any matrix with diagonal >= (hss.Lo, htt.Lo) and
      // off-diagonal within +-off is at least that of [[hss.Lo, off], [off, htt.Lo]]
      const double mean = 0.5 * (hss.Lo + htt.Lo), half = 0.5 * (hss.Lo - htt.Lo);
      lambda = 2.0 * (mean - std::sqrt(half * half + off * off)); // f's Hessian is 2 h
    }
    double cen[2];
    P.Centre(s, cen);
    double c[2] = { cen[0], cen[1] };
    if (ownD2 < HUGE_VAL && P.Inside(s, ownUV))
      c[0] = ownUV[0], c[1] = ownUV[1];
    double fc = 0.0;
    if (secondOrder(s, c, lambda, fc) >= threshold())
      continue;
    // a nearer point may lie here (or, at the root, the face was never solved): solve from
    // c, then bound again from the face's solution when it lies in this sub-patch
    double fcen = fc;
    if (c[0] != cen[0] || c[1] != cen[1])
    {
      double x[3];
      M.FacePoint(f, cen, x);
      fcen = (x[0] - v[0]) * (x[0] - v[0]) + (x[1] - v[1]) * (x[1] - v[1]) +
        (x[2] - v[2]) * (x[2] - v[2]);
    }
    if (s.Depth == 0 || fcen < best2 || fc < best2)
    {
      double uv[2] = { c[0], c[1] };
      tryStart(uv);
      if (P.Inside(s, ownUV))
      {
        c[0] = ownUV[0], c[1] = ownUV[1];
        if (secondOrder(s, c, lambda, fc) >= threshold())
          continue;
      }
    }
    if (s.Depth >= Patches::MaxDepth || top + 4 > 256)
    {
      certified = false;
      continue;
    }
    top = P.Split(s, stack, top);
  }
}

/*
 * The per-vertex embedding, over an adapter A of a mesh (TetCells in
 * hoembedLagrangeEmbedding.cxx, HexCells in hoembedLagrangeHexEmbedding.cxx) that has:
 *   using Face = TriangleDomain or SquareDomain;
 *   static constexpr double CellCentre;        (the reference cell's centre, each coordinate)
 *   static constexpr int StartCorners[4];      (corner 0 and the far ends of its 3 edges)
 *   static bool InsideCell(pc, m), FarOutside(pc); static void ClampIntoCell(pc);
 *   Bound Bind(Id c, bool normals): the cell's map, Bound::Point(pc, x, J), and with
 *     normals its normal field, Bound::Normal(pc, s, J) (J[i][k] = d x_k / d pc_i);
 *   Id FaceCell(f); int FaceLocal(f); FaceToParametric(lf, uv, pc);
 *   FaceTangents(lf, J, xu, xv) (d x / du, d x / dv from the cell's J);
 *   Id Neighbor(f, e) (across edge e, or -1); Id Corner(f, e) (mesh node at corner e);
 *   Id NodeFacesBegin(n), NodeFacesEnd(n), NodeFace(i) (boundary faces around node n);
 *   and, from MeshCells: Diagonal, Points, Connectivity, NodesPerCell, CellTree,
 *   FacePoint(f, uv, x), Closest(v, f, uv, certified, visited) (the certified search).
 */
// What both adapters forward to their mesh alike (an adapter derives from this).
template <typename Mesh>
struct MeshCells
{
  const Mesh& M;
  const AabbTree& CellTree;
  const double Diagonal = M.Diagonal;
  const double* Points = M.Points.data();
  const LagrangeId* Connectivity = M.Connectivity.data();
  const int NodesPerCell = M.NodesPerCell;
  void FacePoint(LagrangeId f, const double uv[2], double x[3]) const
  {
    M.FacePoint(f, uv, x);
  }
  double Closest(
    const double v[3], LagrangeId& f, double uv[2], bool& certified, int* visited) const
  {
    return M.ClosestBoundaryPoint(v, f, uv, certified, visited);
  }
};

// v inside a cell: the cells whose control-point box holds v, the map inverted by damped
// Newton from the straight cell's parameters of v and from the centre.
template <typename A>
bool LocateInCells(const A& a, const double v[3], LagrangeId& cell, double pc[3])
{
  const double tiny = 1e-300;
  double reach2 = std::max(tiny, 1e-24 * a.Diagonal * a.Diagonal);
  bool found = false;
  a.CellTree.VisitNearer(v, reach2, [&](LagrangeId c) {
    if (found)
      return;
    const auto cellMap = a.Bind(c, false);
    // starts: the straight cell of corner 0 and its three edges, the centre
    const double m0 = A::CellCentre;
    double starts[2][3] = { { m0, m0, m0 }, { m0, m0, m0 } };
    {
      const LagrangeId* ids = a.Connectivity + static_cast<LagrangeId>(a.NodesPerCell) * c;
      const double* x0 = a.Points + 3 * ids[A::StartCorners[0]];
      double M[3][3], r[3], s[3];
      for (int i = 0; i < 3; ++i)
      {
        for (int d = 0; d < 3; ++d)
          M[d][i] = a.Points[3 * ids[A::StartCorners[i + 1]] + d] - x0[d];
        r[i] = v[i] - x0[i];
      }
      if (Solve3(M, r, s))
        std::copy(s, s + 3, starts[0]);
    }
    for (int k = 0; k < 2 && !found; ++k)
    {
      double q[3] = { starts[k][0], starts[k][1], starts[k][2] };
      double y[3], J[3][3];
      cellMap.Point(q, y, J);
      double r = std::sqrt((y[0] - v[0]) * (y[0] - v[0]) + (y[1] - v[1]) * (y[1] - v[1]) +
        (y[2] - v[2]) * (y[2] - v[2]));
      for (int it = 0; it < 60 && r > 1e-15 * a.Diagonal; ++it)
      {
        double M[3][3], rhs[3], step[3];
        for (int d = 0; d < 3; ++d)
        {
          for (int i = 0; i < 3; ++i)
            M[d][i] = J[i][d];
          rhs[d] = v[d] - y[d];
        }
        if (!Solve3(M, rhs, step))
          break;
        double alpha = 1.0;
        bool better = false;
        for (int ls = 0; ls < 30; ++ls, alpha *= 0.5)
        {
          const double t[3] = { q[0] + alpha * step[0], q[1] + alpha * step[1],
            q[2] + alpha * step[2] };
          double yn[3], Jn[3][3];
          cellMap.Point(t, yn, Jn);
          const double rn = std::sqrt((yn[0] - v[0]) * (yn[0] - v[0]) +
            (yn[1] - v[1]) * (yn[1] - v[1]) + (yn[2] - v[2]) * (yn[2] - v[2]));
          if (rn < r)
          {
            std::copy(t, t + 3, q);
            std::copy(yn, yn + 3, y);
            for (int i = 0; i < 3; ++i)
              std::copy(Jn[i], Jn[i] + 3, J[i]);
            r = rn;
            better = true;
            break;
          }
        }
        if (!better || A::FarOutside(q))
          break; // no progress, or far outside the reference cell: not this cell
      }
      if (r <= 1e-12 * a.Diagonal && A::InsideCell(q, 1e-10))
      {
        found = true;
        cell = c;
        std::copy(q, q + 3, pc);
        reach2 = 0.0; // stops the traversal
      }
    }
  });
  return found;
}

// q with J(pc) q = v - x(pc) in cell c (the fallback offset); false when J is singular.
template <typename A>
bool OffsetInCell(const A& a, LagrangeId c, const double pc[3], const double v[3], double q[3])
{
  double x[3], J[3][3], M[3][3], r[3];
  a.Bind(c, false).Point(pc, x, J);
  for (int d = 0; d < 3; ++d)
  {
    for (int i = 0; i < 3; ++i)
      M[d][i] = J[i][d];
    r[d] = v[d] - x[d];
  }
  if (Solve3(M, r, q))
    return true;
  q[0] = q[1] = q[2] = 0.0;
  return false;
}

// The normal offset p = x(u, v) + d s / |s| on the boundary: Newton in (u, v, d) from
// face f at uv with d, walking across the faces' edges (at most 16 faces). Returns 0
// (f, uv, d: the foot), else -1.
template <typename A>
int NormalOffsetWalk(
  const A& a, const double p[3], LagrangeId& f, double uv[2], double& d, int& iterations)
{
  using Face = typename A::Face;
  const double tolF = 1e-13 * a.Diagonal;
  int lastEdge = -1;
  for (int hop = 0; hop < 16; ++hop)
  {
    const LagrangeId c = a.FaceCell(f);
    const int lf = a.FaceLocal(f);
    const auto cellMap = a.Bind(c, true);
    auto residual = [&](const double t[2], double dd, double F[3], double M[3][3]) {
      double pc[3], x[3], J[3][3], s[3], Js[3][3];
      a.FaceToParametric(lf, t, pc);
      cellMap.Point(pc, x, J);
      cellMap.Normal(pc, s, Js);
      const double sl = std::sqrt(Dot(s, s));
      if (!(sl > 1e-12))
        return false;
      double sh[3], xu[3], xv[3], su[3], sv[3];
      for (int k = 0; k < 3; ++k)
        sh[k] = s[k] / sl;
      a.FaceTangents(lf, J, xu, xv);
      a.FaceTangents(lf, Js, su, sv);
      const double shu = Dot(sh, su), shv = Dot(sh, sv);
      for (int k = 0; k < 3; ++k)
      {
        F[k] = x[k] + dd * sh[k] - p[k];
        M[k][0] = xu[k] + dd * (su[k] - sh[k] * shu) / sl;
        M[k][1] = xv[k] + dd * (sv[k] - sh[k] * shv) / sl;
        M[k][2] = sh[k];
      }
      return true;
    };
    int exitEdge = -1;
    double lastNorm = HUGE_VAL;
    for (int it = 0; it < 40; ++it)
    {
      ++iterations;
      double F[3], M[3][3], step[3];
      if (!residual(uv, d, F, M))
        return -1;
      const double nF = std::sqrt(Dot(F, F));
      const bool inside = Face::Inside(uv, 1e-12);
      if (inside && nF <= tolF)
        return 0;
      const double rhs[3] = { -F[0], -F[1], -F[2] };
      if (!Solve3(M, rhs, step))
        return -1;
      if (inside && nF <= 100 * tolF && std::abs(step[0]) + std::abs(step[1]) < 1e-13)
        return 0; // stagnation at round-off
      if (it > 0 && !(nF < lastNorm) && nF > 100 * tolF)
        return -1;
      lastNorm = nF;
      // leaving the face: stop at the side crossed first, then go across it
      double s = 1.0;
      const int side = Face::Exit(uv, step, s);
      s = std::max(0.0, s);
      uv[0] += s * step[0];
      uv[1] += s * step[1];
      d += s * step[2];
      if (side >= 0)
      {
        Face::Project(uv);
        exitEdge = side;
        break;
      }
    }
    if (exitEdge < 0)
      return -1;
    // across edge exitEdge to the neighbouring boundary face, at the same point of the edge
    const LagrangeId g = a.Neighbor(f, exitEdge);
    if (g < 0 || (exitEdge == lastEdge && hop > 8))
      return -1;
    const LagrangeId A0 = a.Corner(f, exitEdge), B0 = a.Corner(f, (exitEdge + 1) % Face::Edges);
    const double t = Face::EdgeParameter(exitEdge, uv);
    int ge = -1;
    double gt = 0;
    for (int e = 0; e < Face::Edges; ++e)
    {
      const LagrangeId a0 = a.Corner(g, e), b0 = a.Corner(g, (e + 1) % Face::Edges);
      if (a0 == A0 && b0 == B0)
        ge = e, gt = t;
      else if (a0 == B0 && b0 == A0)
        ge = e, gt = 1 - t;
    }
    if (ge < 0)
      return -1;
    f = g;
    lastEdge = ge;
    Face::OnEdge(ge, gt, uv);
  }
  return -1;
}

// Embed one point (method: EMBED_NORMAL_OFFSET or EMBED_BARYCENTRIC).
template <typename A>
void EmbedVertex(const A& a, const double v[3], int method, VertexEmbedding& r)
{
  using Face = typename A::Face;
  auto distance = [&](const double x[3]) {
    return std::sqrt((x[0] - v[0]) * (x[0] - v[0]) + (x[1] - v[1]) * (x[1] - v[1]) +
      (x[2] - v[2]) * (x[2] - v[2]));
  };
  r = VertexEmbedding();
  LagrangeId cell = -1;
  double pc[3];
  if (LocateInCells(a, v, cell, pc))
  {
    A::ClampIntoCell(pc); // round-off
    double x[3], J[3][3];
    a.Bind(cell, false).Point(pc, x, J);
    r.Cell = cell;
    std::copy(pc, pc + 3, r.PC);
    r.Inside = true;
    r.Residual = distance(x);
    return;
  }
  LagrangeId f = -1;
  double uv[2] = { Face::Centre, Face::Centre };
  bool certified = true;
  const double d2 = a.Closest(v, f, uv, certified, &r.Visited);
  r.Uncertified = !certified;
  r.ClosestDistance = std::sqrt(d2);
  r.BoundaryFace = f;
  r.UV[0] = uv[0];
  r.UV[1] = uv[1];
  double x[3];
  a.FacePoint(f, uv, x);
  const LagrangeId closestCell = a.FaceCell(f);
  double closestPC[3];
  a.FaceToParametric(a.FaceLocal(f), uv, closestPC);
  if (method == EMBED_BARYCENTRIC)
  {
    // the closest cell's map extrapolated: its inverse from the closest point
    const auto cellMap = a.Bind(closestCell, false);
    double q[3] = { closestPC[0], closestPC[1], closestPC[2] };
    double y[3], J[3][3];
    for (int it = 0; it < 40; ++it)
    {
      ++r.Iterations;
      cellMap.Point(q, y, J);
      double M[3][3], rhs[3], step[3];
      for (int d = 0; d < 3; ++d)
      {
        for (int i = 0; i < 3; ++i)
          M[d][i] = J[i][d];
        rhs[d] = v[d] - y[d];
      }
      if (!Solve3(M, rhs, step) || Dot(rhs, rhs) <= 1e-30 * a.Diagonal * a.Diagonal)
        break;
      for (int i = 0; i < 3; ++i)
        q[i] += step[i];
    }
    cellMap.Point(q, y, J);
    r.Cell = closestCell;
    std::copy(q, q + 3, r.PC);
    r.Residual = distance(y);
    return;
  }
  // normal offset from the closest point; d starts at the signed distance along n
  double s[3];
  {
    double J[3][3];
    a.Bind(closestCell, true).Normal(closestPC, s, J);
  }
  const double e[3] = { v[0] - x[0], v[1] - x[1], v[2] - x[2] };
  double d = (Dot(e, s) >= 0 ? 1.0 : -1.0) * r.ClosestDistance;
  // As on tet10 (hoembedEmbeddingSearch.cxx): only a foot within 8 x the closest distance
  // counts (beyond the normal field's focal distance a walk can reach a far foot, and the
  // transfer would swing v on a long lever); retried from the faces around the closest
  // face's corners, then the fallback.
  const double reach = 8.0 * r.ClosestDistance + 1e-6 * a.Diagonal;
  const double d0 = d;
  LagrangeId nf = f;
  double nuv[2] = { uv[0], uv[1] };
  int its = 0;
  int status = NormalOffsetWalk(a, v, nf, nuv, d, its);
  if (status == 0 && std::abs(d) > reach)
    status = -1;
  for (int k = 0; k < Face::Edges && status != 0; ++k)
  {
    const LagrangeId node = a.Corner(f, k);
    for (LagrangeId i = a.NodeFacesBegin(node); i < a.NodeFacesEnd(node) && status != 0; ++i)
    {
      nf = a.NodeFace(i);
      nuv[0] = nuv[1] = Face::Centre;
      d = d0;
      status = NormalOffsetWalk(a, v, nf, nuv, d, its);
      if (status == 0 && std::abs(d) > reach)
        status = -1;
    }
  }
  r.Iterations = its;
  if (status == 0)
  {
    const LagrangeId c = a.FaceCell(nf);
    const int lf = a.FaceLocal(nf);
    Face::Project(nuv);
    a.FaceToParametric(lf, nuv, r.PC);
    r.Cell = c;
    r.Face = static_cast<signed char>(lf);
    r.Distance = d;
    r.BoundaryFace = nf;
    // the residual of the reconstruction p + d n from the stored values
    const auto cellMap = a.Bind(c, true);
    double y[3], n[3], J[3][3];
    cellMap.Point(r.PC, y, J);
    cellMap.Normal(r.PC, n, J);
    const double nl = std::sqrt(Dot(n, n));
    double rebuilt[3];
    for (int k = 0; k < 3; ++k)
      rebuilt[k] = y[k] + d * n[k] / nl;
    r.Residual = distance(rebuilt);
    return;
  }
  // fallback: the closest point and v = p + J(pc) q
  r.Fallback = true;
  r.Cell = closestCell;
  std::copy(closestPC, closestPC + 3, r.PC);
  r.Face = -1;
  r.Distance = 0.0;
  double q[3], y[3], J[3][3];
  OffsetInCell(a, closestCell, closestPC, v, q);
  a.Bind(closestCell, false).Point(closestPC, y, J);
  double rebuilt[3];
  for (int k = 0; k < 3; ++k)
    rebuilt[k] = y[k] + J[0][k] * q[0] + J[1][k] * q[1] + J[2][k] * q[2];
  r.Residual = distance(rebuilt);
}

} // namespace lagrange_detail
} // namespace hoembed

#endif
