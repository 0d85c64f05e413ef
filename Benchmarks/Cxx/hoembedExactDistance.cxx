#include "hoembedExactDistance.h"

#include "vtkPoints.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>

namespace hoembed_exact
{
namespace
{
using V3 = std::array<double, 3>;

inline V3 Sub(const V3& a, const V3& b)
{
  return { a[0] - b[0], a[1] - b[1], a[2] - b[2] };
}
inline double Dot(const V3& a, const V3& b)
{
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
inline double Norm(const V3& a)
{
  return std::sqrt(Dot(a, a));
}
inline V3 Comb(double s, const V3& a, double t, const V3& b)
{
  return { s * a[0] + t * b[0], s * a[1] + t * b[1], s * a[2] + t * b[2] };
}

V3 Node(const ExactMesh& M, Id i)
{
  return { M.Points[3 * i], M.Points[3 * i + 1], M.Points[3 * i + 2] };
}

// Face map at (u, v): tri6 (VTK order) or tri3 when the mid-node ids are -1.
V3 FacePoint(const ExactMesh& M, Id f, double u, double v)
{
  const Id* n = &M.Faces[6 * f];
  const double l[3] = { 1.0 - u - v, u, v };
  V3 x = { 0, 0, 0 };
  auto add = [&](Id node, double w) {
    for (int d = 0; d < 3; ++d)
      x[d] += w * M.Points[3 * node + d];
  };
  if (n[3] < 0)
  {
    for (int k = 0; k < 3; ++k)
      add(n[k], l[k]);
    return x;
  }
  for (int k = 0; k < 3; ++k)
    add(n[k], l[k] * (2.0 * l[k] - 1.0));
  add(n[3], 4.0 * l[0] * l[1]);
  add(n[4], 4.0 * l[1] * l[2]);
  add(n[5], 4.0 * l[2] * l[0]);
  return x;
}

// Distance from p to the triangle (a, b, c), degenerate triangles included.
double SegmentDistance(const V3& p, const V3& a, const V3& b)
{
  const V3 ab = Sub(b, a), ap = Sub(p, a);
  const double l2 = Dot(ab, ab);
  double t = l2 > 0.0 ? Dot(ap, ab) / l2 : 0.0;
  t = std::min(1.0, std::max(0.0, t));
  return Norm(Sub(ap, Comb(t, ab, 0.0, ab)));
}
double TriangleDistance(const V3& p, const V3& a, const V3& b, const V3& c)
{
  const V3 ab = Sub(b, a), ac = Sub(c, a), ap = Sub(p, a);
  const V3 n = { ab[1] * ac[2] - ab[2] * ac[1], ab[2] * ac[0] - ab[0] * ac[2],
    ab[0] * ac[1] - ab[1] * ac[0] };
  const double n2 = Dot(n, n);
  const double scale = std::max(Dot(ab, ab), Dot(ac, ac));
  if (n2 > 1e-20 * scale * scale)
  {
    // barycentric coordinates of the projection
    const V3 bp = Sub(p, b), cp = Sub(p, c);
    const V3 bc = Sub(c, b), ca = Sub(a, c);
    auto side = [&](const V3& e, const V3& q) {
      const V3 x = { e[1] * q[2] - e[2] * q[1], e[2] * q[0] - e[0] * q[2],
        e[0] * q[1] - e[1] * q[0] };
      return Dot(x, n);
    };
    if (side(ab, ap) >= 0.0 && side(bc, bp) >= 0.0 && side(ca, cp) >= 0.0)
      return std::fabs(Dot(ap, n)) / std::sqrt(n2);
  }
  return std::min(
    SegmentDistance(p, a, b), std::min(SegmentDistance(p, b, c), SegmentDistance(p, c, a)));
}

double BoxDistance(const double* box, const double v[3])
{
  double s = 0.0;
  for (int d = 0; d < 3; ++d)
  {
    const double e = std::max({ box[2 * d] - v[d], 0.0, v[d] - box[2 * d + 1] });
    s += e * e;
  }
  return std::sqrt(s);
}

void GrowBox(double* box, const V3& x)
{
  for (int d = 0; d < 3; ++d)
  {
    box[2 * d] = std::min(box[2 * d], x[d]);
    box[2 * d + 1] = std::max(box[2 * d + 1], x[d]);
  }
}

// Quadratic map of a sub-triangle of a face over the reference triangle (s, t):
// x = c0 + c1 s + c2 t + c3 s^2 + c4 s t + c5 t^2, from its six samples.
struct SubPatch
{
  V3 X[3], M[3]; // corners, mids of edges 01, 12, 20
  V3 C[6];
  double Dev = 0.0;   // bound of |patch - flat corner triangle|
  double Lower = 0.0; // lower bound of the distance to v
};

void MakeSubPatch(const ExactMesh& M, Id f, const double q[3][2], const V3& p, SubPatch& S,
  double& best, Id& bestFace, double bestUV[2], Id face, double slack)
{
  for (int k = 0; k < 3; ++k)
  {
    S.X[k] = FacePoint(M, f, q[k][0], q[k][1]);
    const int j = (k + 1) % 3;
    S.M[k] = FacePoint(M, f, 0.5 * (q[k][0] + q[j][0]), 0.5 * (q[k][1] + q[j][1]));
  }
  // every sample is a point of the face: an upper bound
  for (int k = 0; k < 3; ++k)
  {
    const int j = (k + 1) % 3;
    const double dx = Norm(Sub(S.X[k], p)), dm = Norm(Sub(S.M[k], p));
    if (dx < best)
    {
      best = dx;
      bestFace = face;
      bestUV[0] = q[k][0];
      bestUV[1] = q[k][1];
    }
    if (dm < best)
    {
      best = dm;
      bestFace = face;
      bestUV[0] = 0.5 * (q[k][0] + q[j][0]);
      bestUV[1] = 0.5 * (q[k][1] + q[j][1]);
    }
  }
  double emax = 0.0, esum = 0.0;
  V3 e[3];
  for (int k = 0; k < 3; ++k)
  {
    const int j = (k + 1) % 3;
    e[k] = Sub(Comb(2.0, S.M[k], -1.0, S.X[k]), S.X[j]); // 2 m - a - b
    const double l = Norm(e[k]);
    emax = std::max(emax, l);
    esum += l;
  }
  S.Dev = std::min(2.0 / 3.0 * emax, 0.5 * esum);
  S.Lower = std::max(0.0, TriangleDistance(p, S.X[0], S.X[1], S.X[2]) - S.Dev - slack);
  // monomial coefficients (X0 at (0,0), X1 at (1,0), X2 at (0,1); e01 = e[0], e20 = e[2])
  for (int d = 0; d < 3; ++d)
  {
    const double x0 = S.X[0][d], x1 = S.X[1][d], x2 = S.X[2][d];
    const double m01 = S.M[0][d], m12 = S.M[1][d], m20 = S.M[2][d];
    S.C[0][d] = x0;
    S.C[1][d] = 4.0 * m01 - 3.0 * x0 - x1;
    S.C[2][d] = 4.0 * m20 - 3.0 * x0 - x2;
    S.C[3][d] = -2.0 * e[0][d];
    S.C[5][d] = -2.0 * e[2][d];
    S.C[4][d] = 4.0 * (m12 - x0) - 2.0 * (S.C[1][d] + S.C[2][d]) - S.C[3][d] - S.C[5][d];
  }
}

struct PatchEval
{
  V3 X, Js, Jt;
};
PatchEval Evaluate(const SubPatch& S, double s, double t)
{
  PatchEval r;
  for (int d = 0; d < 3; ++d)
  {
    r.X[d] = S.C[0][d] + S.C[1][d] * s + S.C[2][d] * t + S.C[3][d] * s * s + S.C[4][d] * s * t +
      S.C[5][d] * t * t;
    r.Js[d] = S.C[1][d] + 2.0 * S.C[3][d] * s + S.C[4][d] * t;
    r.Jt[d] = S.C[2][d] + S.C[4][d] * s + 2.0 * S.C[5][d] * t;
  }
  return r;
}

// Lower bound of the smallest eigenvalue of (1/2) Hess |x(s,t) - p|^2 over the reference
// triangle; > 0: the squared distance is strongly convex there.
double ConvexityBound(const SubPatch& S, const V3& p)
{
  const PatchEval c = Evaluate(S, 1.0 / 3.0, 1.0 / 3.0);
  const double a = Dot(c.Js, c.Js), b = Dot(c.Js, c.Jt), d = Dot(c.Jt, c.Jt);
  const double lmin = 0.5 * (a + d) - std::sqrt(0.25 * (a - d) * (a - d) + b * b);
  const double smin = std::sqrt(std::max(0.0, lmin));
  // |J - J(centroid)|_F with |ds|, |dt| <= 2/3
  const double n3 = Norm(S.C[3]), n4 = Norm(S.C[4]), n5 = Norm(S.C[5]);
  const double col1 = 2.0 / 3.0 * (2.0 * n3 + n4), col2 = 2.0 / 3.0 * (n4 + 2.0 * n5);
  const double spread = std::sqrt(col1 * col1 + col2 * col2);
  if (spread >= smin)
    return -1.0;
  // farthest control point from p bounds |x - p| on the patch
  double far = 0.0;
  for (int k = 0; k < 3; ++k)
  {
    const int j = (k + 1) % 3;
    far = std::max(far, Norm(Sub(S.X[k], p)));
    const V3 ctrl = Sub(Comb(2.0, S.M[k], -0.5, S.X[k]), Comb(0.5, S.X[j], 0.0, S.X[j]));
    far = std::max(far, Norm(Sub(ctrl, p)));
  }
  const double hnorm = std::sqrt(4.0 * n3 * n3 + 2.0 * n4 * n4 + 4.0 * n5 * n5);
  return (smin - spread) * (smin - spread) - far * hnorm;
}

// Local minimum of g = |x - p|^2 on a sub-patch where g is convex: Newton inside (steps
// clipped to the triangle), monotone bisection on each edge; the best of the four.
// Returns g at the result (s, t) and sets the certified lower bound of min g.
double SolveConvex(const SubPatch& S, const V3& p, double st[2], double& lowerG)
{
  auto g = [&](double s, double t) {
    const PatchEval e = Evaluate(S, s, t);
    const V3 r = Sub(e.X, p);
    return Dot(r, r);
  };
  double bs = 1.0 / 3.0, bt = 1.0 / 3.0, bg = g(bs, bt);
  // interior Newton
  {
    double s = bs, t = bt, gv = bg;
    for (int it = 0; it < 50; ++it)
    {
      const PatchEval e = Evaluate(S, s, t);
      const V3 r = Sub(e.X, p);
      const double gs = Dot(r, e.Js), gt = Dot(r, e.Jt);
      const double hss = Dot(e.Js, e.Js) + 2.0 * Dot(r, S.C[3]);
      const double hst = Dot(e.Js, e.Jt) + Dot(r, S.C[4]);
      const double htt = Dot(e.Jt, e.Jt) + 2.0 * Dot(r, S.C[5]);
      const double det = hss * htt - hst * hst;
      if (!(det > 0.0))
        break;
      double ds = -(htt * gs - hst * gt) / det, dt = -(hss * gt - hst * gs) / det;
      // clip to the triangle s >= 0, t >= 0, s + t <= 1
      double alpha = 1.0;
      if (ds < 0.0)
        alpha = std::min(alpha, -s / ds);
      if (dt < 0.0)
        alpha = std::min(alpha, -t / dt);
      if (ds + dt > 0.0)
        alpha = std::min(alpha, (1.0 - s - t) / (ds + dt));
      alpha = std::max(0.0, alpha);
      double ns = s, nt = t, ng = gv;
      for (int k = 0; k < 40; ++k, alpha *= 0.5)
      {
        ns = std::max(0.0, s + alpha * ds);
        nt = std::max(0.0, t + alpha * dt);
        if (ns + nt > 1.0)
        {
          const double sc = 1.0 / (ns + nt);
          ns *= sc;
          nt *= sc;
        }
        ng = g(ns, nt);
        if (ng <= gv)
          break;
      }
      if (!(ng <= gv))
        break;
      const double step = std::fabs(ns - s) + std::fabs(nt - t);
      s = ns;
      t = nt;
      gv = ng;
      if (step < 1e-16)
        break;
    }
    if (gv < bg)
    {
      bs = s;
      bt = t;
      bg = gv;
    }
  }
  // edges: (tau, 0), (1 - tau, tau), (0, tau); g is convex along each, so g' is monotone
  for (int edge = 0; edge < 3; ++edge)
  {
    auto at = [&](double tau, double& s, double& t) {
      s = edge == 0 ? tau : (edge == 1 ? 1.0 - tau : 0.0);
      t = edge == 0 ? 0.0 : tau;
    };
    auto dg = [&](double tau) {
      double s, t;
      at(tau, s, t);
      const PatchEval e = Evaluate(S, s, t);
      const V3 r = Sub(e.X, p);
      const double ds = edge == 0 ? 1.0 : (edge == 1 ? -1.0 : 0.0);
      const double dt = edge == 0 ? 0.0 : 1.0;
      return Dot(r, Comb(ds, e.Js, dt, e.Jt));
    };
    double lo = 0.0, hi = 1.0, tau;
    if (dg(0.0) >= 0.0)
      tau = 0.0;
    else if (dg(1.0) <= 0.0)
      tau = 1.0;
    else
    {
      for (int k = 0; k < 60; ++k)
      {
        const double mid = 0.5 * (lo + hi);
        (dg(mid) > 0.0 ? hi : lo) = mid;
      }
      tau = 0.5 * (lo + hi);
    }
    double s, t;
    at(tau, s, t);
    const double gv = g(s, t);
    if (gv < bg)
    {
      bs = s;
      bt = t;
      bg = gv;
    }
  }
  // certificate: g(xi) >= g(xi*) + grad g(xi*) . (xi - xi*), smallest at a corner
  const PatchEval e = Evaluate(S, bs, bt);
  const V3 r = Sub(e.X, p);
  const double gs = 2.0 * Dot(r, e.Js), gt = 2.0 * Dot(r, e.Jt);
  const double m = std::min({ gs * (0.0 - bs) + gt * (0.0 - bt), gs * (1.0 - bs) + gt * (0.0 - bt),
    gs * (0.0 - bs) + gt * (1.0 - bt) });
  lowerG = bg + std::min(0.0, m);
  st[0] = bs;
  st[1] = bt;
  return bg;
}

// Own tet4/tet10 map and Jacobian (VTK node order; mids on edges 01 12 20 03 13 23).
const int EdgeCorners[6][2] = { { 0, 1 }, { 1, 2 }, { 2, 0 }, { 0, 3 }, { 1, 3 }, { 2, 3 } };

// Box (xmin, xmax, ymin, ...) of the control points of a triangle (ncorner 3: edges 01 12
// 20) or tet (4: all six edges) with nodes n: the corners and, when quadratic,
// 2 m - (a + b) / 2 per edge (mid-edge node m after the corners).
void ControlPointBox(const ExactMesh& M, const Id* n, int ncorner, bool quadratic, double* b)
{
  for (int d = 0; d < 3; ++d)
  {
    b[2 * d] = 1e300;
    b[2 * d + 1] = -1e300;
  }
  for (int k = 0; k < ncorner; ++k)
    GrowBox(b, Node(M, n[k]));
  if (!quadratic)
    return;
  const int nedges = ncorner == 3 ? 3 : 6;
  for (int e = 0; e < nedges; ++e)
  {
    const V3 a = Node(M, n[EdgeCorners[e][0]]), c = Node(M, n[EdgeCorners[e][1]]);
    const V3 m = Node(M, n[ncorner + e]);
    GrowBox(b, Sub(Comb(2.0, m, -0.5, a), Comb(0.5, c, 0.0, c)));
  }
}
void CellMap(const ExactMesh& M, Id c, const double pc[3], double x[3], double J[3][3])
{
  const Id* n = &M.Cells[M.NodesPerCell * c];
  const double l[4] = { 1.0 - pc[0] - pc[1] - pc[2], pc[0], pc[1], pc[2] };
  // dl/d(pc_j): l0 -> -1, l_j+1 -> 1
  double N[10], dNdl[10][4] = {};
  int count;
  if (M.NodesPerCell == 4)
  {
    count = 4;
    for (int k = 0; k < 4; ++k)
    {
      N[k] = l[k];
      dNdl[k][k] = 1.0;
    }
  }
  else
  {
    count = 10;
    for (int k = 0; k < 4; ++k)
    {
      N[k] = l[k] * (2.0 * l[k] - 1.0);
      dNdl[k][k] = 4.0 * l[k] - 1.0;
    }
    for (int e = 0; e < 6; ++e)
    {
      const int a = EdgeCorners[e][0], b = EdgeCorners[e][1];
      N[4 + e] = 4.0 * l[a] * l[b];
      dNdl[4 + e][a] = 4.0 * l[b];
      dNdl[4 + e][b] = 4.0 * l[a];
    }
  }
  for (int d = 0; d < 3; ++d)
  {
    x[d] = 0.0;
    for (int j = 0; j < 3; ++j)
      J[d][j] = 0.0;
  }
  for (int k = 0; k < count; ++k)
  {
    const double* X = &M.Points[3 * n[k]];
    for (int j = 0; j < 3; ++j)
    {
      const double dN = dNdl[k][j + 1] - dNdl[k][0];
      for (int d = 0; d < 3; ++d)
        J[d][j] += dN * X[d];
    }
    for (int d = 0; d < 3; ++d)
      x[d] += N[k] * X[d];
  }
}

// Newton inversion x(pc) = v from `pc`; returns |x(pc) - v|.
double Invert(const ExactMesh& M, Id c, const double v[3], double pc[3])
{
  double x[3], J[3][3];
  CellMap(M, c, pc, x, J);
  double r = std::sqrt(
    (x[0] - v[0]) * (x[0] - v[0]) + (x[1] - v[1]) * (x[1] - v[1]) + (x[2] - v[2]) * (x[2] - v[2]));
  for (int it = 0; it < 60 && r > 0.0; ++it)
  {
    const double f[3] = { v[0] - x[0], v[1] - x[1], v[2] - x[2] };
    const double det = J[0][0] * (J[1][1] * J[2][2] - J[1][2] * J[2][1]) -
      J[0][1] * (J[1][0] * J[2][2] - J[1][2] * J[2][0]) +
      J[0][2] * (J[1][0] * J[2][1] - J[1][1] * J[2][0]);
    if (!(std::fabs(det) > 0.0))
      break;
    double step[3];
    for (int k = 0; k < 3; ++k)
    {
      double A[3][3];
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
          A[i][j] = j == k ? f[i] : J[i][j];
      step[k] = (A[0][0] * (A[1][1] * A[2][2] - A[1][2] * A[2][1]) -
                  A[0][1] * (A[1][0] * A[2][2] - A[1][2] * A[2][0]) +
                  A[0][2] * (A[1][0] * A[2][1] - A[1][1] * A[2][0])) /
        det;
    }
    double alpha = 1.0, nr = r, npc[3];
    for (int k = 0; k < 30; ++k, alpha *= 0.5)
    {
      for (int i = 0; i < 3; ++i)
        npc[i] = pc[i] + alpha * step[i];
      double nx[3], nJ[3][3];
      CellMap(M, c, npc, nx, nJ);
      nr = std::sqrt((nx[0] - v[0]) * (nx[0] - v[0]) + (nx[1] - v[1]) * (nx[1] - v[1]) +
        (nx[2] - v[2]) * (nx[2] - v[2]));
      if (nr < r)
        break;
    }
    if (!(nr < r))
      break;
    for (int i = 0; i < 3; ++i)
      pc[i] = npc[i];
    CellMap(M, c, pc, x, J);
    r = nr;
    if (std::fabs(step[0]) + std::fabs(step[1]) + std::fabs(step[2]) < 1e-15)
      break;
  }
  return r;
}

// Inside test of v in cell c that cannot be trapped by a fold of the map's extension
// beyond the reference tet. Newton from a few fixed starts is not enough on a strongly
// curved cell: its damped iteration can settle on a local minimum of |x(pc) - v| outside
// the reference tet while v does have a preimage inside (stanford-bunny at ~1000 cells,
// vertex 4477, cell 751). So the reference tet is split recursively (red refinement into
// 8); a sub-tet is dropped when v is farther than tol from the box of its Bezier control
// points (the quadratic map restricted to a sub-tet is quadratic in its barycentric
// coordinates, so its image lies in the hull of corners x_i and 2 x(m_ij) - (x_i + x_j)/2),
// and Newton runs from the centroid of every sub-tet kept. Inside when one run lands in
// the reference tet with |x(pc) - v| <= tol; outside is proved when every sub-tet is
// dropped; sub-tets still kept at maxDepth (or beyond maxNodes) are counted in undecided.
bool InvertBySubdivision(const ExactMesh& M, Id c, const double v[3], double tol, int maxDepth,
  long maxNodes, double pc[3], long& nodes, int& undecided)
{
  struct SubTet
  {
    double Q[4][3];
    int Depth;
  };
  std::vector<SubTet> stack;
  stack.push_back({ { { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 } }, 0 });
  const double slack = 1e-12;
  while (!stack.empty())
  {
    const SubTet t = stack.back();
    stack.pop_back();
    if (++nodes > maxNodes)
    {
      undecided += 1 + static_cast<int>(stack.size());
      return false;
    }
    // corners and edge mid-points of the sub-tet, in reference coordinates and mapped
    double q[10][3];
    for (int k = 0; k < 4; ++k)
      for (int d = 0; d < 3; ++d)
        q[k][d] = t.Q[k][d];
    for (int e = 0; e < 6; ++e)
      for (int d = 0; d < 3; ++d)
        q[4 + e][d] = 0.5 * (t.Q[EdgeCorners[e][0]][d] + t.Q[EdgeCorners[e][1]][d]);
    double x[10][3], J[3][3];
    for (int k = 0; k < 10; ++k)
      CellMap(M, c, q[k], x[k], J);
    double box[6] = { 1e300, -1e300, 1e300, -1e300, 1e300, -1e300 };
    for (int k = 0; k < 4; ++k)
      GrowBox(box, { x[k][0], x[k][1], x[k][2] });
    for (int e = 0; e < 6; ++e)
    {
      const double* a = x[EdgeCorners[e][0]];
      const double* b = x[EdgeCorners[e][1]];
      GrowBox(box,
        { 2.0 * x[4 + e][0] - 0.5 * (a[0] + b[0]), 2.0 * x[4 + e][1] - 0.5 * (a[1] + b[1]),
          2.0 * x[4 + e][2] - 0.5 * (a[2] + b[2]) });
    }
    if (BoxDistance(box, v) > tol)
      continue;
    double p[3];
    for (int d = 0; d < 3; ++d)
      p[d] = 0.25 * (t.Q[0][d] + t.Q[1][d] + t.Q[2][d] + t.Q[3][d]);
    const double r = Invert(M, c, v, p);
    if (r <= tol && p[0] >= -slack && p[1] >= -slack && p[2] >= -slack &&
      p[0] + p[1] + p[2] <= 1.0 + slack)
    {
      for (int d = 0; d < 3; ++d)
        pc[d] = p[d];
      return true;
    }
    if (t.Depth >= maxDepth)
    {
      ++undecided;
      continue;
    }
    // red refinement: four corner tets and the inner octahedron cut along m02 - m13
    // (q[4..9] are the mids of edges 01 12 20 03 13 23)
    const int m01 = 4, m12 = 5, m02 = 6, m03 = 7, m13 = 8, m23 = 9;
    const int children[8][4] = { { 0, m01, m02, m03 }, { m01, 1, m12, m13 }, { m02, m12, 2, m23 },
      { m03, m13, m23, 3 }, { m02, m13, m01, m12 }, { m02, m13, m12, m23 }, { m02, m13, m23, m03 },
      { m02, m13, m03, m01 } };
    for (const auto& ch : children)
    {
      SubTet s;
      s.Depth = t.Depth + 1;
      for (int k = 0; k < 4; ++k)
        for (int d = 0; d < 3; ++d)
          s.Q[k][d] = q[ch[k]][d];
      stack.push_back(s);
    }
  }
  return false;
}

// VTK's own EvaluatePosition of v in cell c (its nodes copied into `cell`): the return
// code, the parametric coordinates and the squared distance.
int VtkEvaluate(
  const ExactMesh& M, Id c, vtkCell* cell, const double v[3], double pcv[3], double& d2)
{
  const int npc = M.NodesPerCell;
  const Id* n = &M.Cells[npc * c];
  for (int k = 0; k < npc; ++k)
  {
    cell->GetPoints()->SetPoint(k, &M.Points[3 * n[k]]);
    cell->GetPointIds()->SetId(k, k);
  }
  double cp[3], w[10];
  int sub;
  return cell->EvaluatePosition(v, cp, sub, pcv, d2, w);
}
} // namespace

std::string ExactMesh::Build(
  const double* points, Id numberOfPoints, const Id* cells, Id numberOfCells, int nodesPerCell)
{
  if (nodesPerCell != 4 && nodesPerCell != 10)
    return "cells must have 4 or 10 nodes";
  this->NodesPerCell = nodesPerCell;
  this->NumberOfCells = numberOfCells;
  this->Points.assign(points, points + 3 * numberOfPoints);
  this->Cells.assign(cells, cells + nodesPerCell * numberOfCells);
  double box[6] = { 1e300, -1e300, 1e300, -1e300, 1e300, -1e300 };
  for (Id i = 0; i < numberOfPoints; ++i)
    GrowBox(box, Node(*this, i));
  this->Diagonal = std::sqrt((box[1] - box[0]) * (box[1] - box[0]) +
    (box[3] - box[2]) * (box[3] - box[2]) + (box[5] - box[4]) * (box[5] - box[4]));
  // faces by sorted corner triple (VTK's own face node lists)
  std::map<std::array<Id, 3>, std::pair<int, std::array<Id, 6>>> faces;
  for (Id c = 0; c < numberOfCells; ++c)
  {
    const Id* n = &this->Cells[nodesPerCell * c];
    for (Id lf = 0; lf < 4; ++lf)
    {
      std::array<Id, 6> fn = { -1, -1, -1, -1, -1, -1 };
      if (nodesPerCell == 10)
      {
        const vtkIdType* a = vtkQuadraticTetra::GetFaceArray(lf);
        for (int k = 0; k < 6; ++k)
          fn[k] = n[a[k]];
      }
      else
      {
        const vtkIdType* a = vtkTetra::GetFaceArray(lf);
        for (int k = 0; k < 3; ++k)
          fn[k] = n[a[k]];
      }
      std::array<Id, 3> key = { fn[0], fn[1], fn[2] };
      std::sort(key.begin(), key.end());
      auto& e = faces[key];
      ++e.first;
      e.second = fn;
    }
  }
  this->Faces.clear();
  for (const auto& kv : faces)
  {
    if (kv.second.first > 2)
      return "a face is shared by more than two cells";
    if (kv.second.first == 1)
      this->Faces.insert(this->Faces.end(), kv.second.second.begin(), kv.second.second.end());
  }
  if (this->Faces.empty())
    return "no boundary faces";
  // control-point boxes: corners, and 2 m - (a + b) / 2 per edge
  const Id nf = this->NumberOfFaces();
  this->FaceBox.assign(6 * nf, 0.0);
  for (Id f = 0; f < nf; ++f)
    ControlPointBox(
      *this, &this->Faces[6 * f], 3, this->Faces[6 * f + 3] >= 0, &this->FaceBox[6 * f]);
  this->CellBox.assign(6 * numberOfCells, 0.0);
  for (Id c = 0; c < numberOfCells; ++c)
    ControlPointBox(
      *this, &this->Cells[nodesPerCell * c], 4, nodesPerCell == 10, &this->CellBox[6 * c]);
  return std::string();
}

void ExactCellPoint(const ExactMesh& M, Id c, const double pc[3], double x[3])
{
  double J[3][3];
  CellMap(M, c, pc, x, J);
}

void ExactBoundaryDistance(
  const ExactMesh& M, const double v[3], const ExactOptions& opt, ExactScratch& S, ExactResult& res)
{
  const V3 p = { v[0], v[1], v[2] };
  const double tol = opt.CertifyTolerance * M.Diagonal;
  // rounding slack of the bounds (coordinates up to |p| + diagonal, relative 1e-15)
  const double slack = 1e-15 * (Norm(p) + 4.0 * M.Diagonal);
  double best = std::numeric_limits<double>::infinity();
  double lower = std::numeric_limits<double>::infinity(); // over resolved leaves
  res.Face = -1;
  res.Nodes = 0;
  res.DepthLimited = 0;
  res.NodeLimited = false;
  auto& H = S.Heap;
  H.clear();
  const Id nf = M.NumberOfFaces();
  for (Id f = 0; f < nf; ++f)
  {
    ExactScratch::Item it;
    it.Key = BoxDistance(&M.FaceBox[6 * f], v);
    it.Face = f;
    it.Depth = -1;
    H.push_back(it);
  }
  std::make_heap(H.begin(), H.end());
  SubPatch SP;
  while (!H.empty())
  {
    const ExactScratch::Item top = H.front();
    if (top.Key >= best - tol)
      break; // nothing left can be nearer than best - tol
    if (res.Nodes >= opt.MaxNodes)
    {
      res.NodeLimited = true;
      break;
    }
    std::pop_heap(H.begin(), H.end());
    H.pop_back();
    ++res.Nodes;
    ExactScratch::Item it = top;
    if (it.Depth < 0)
    {
      // a whole face: evaluate its flat-triangle bound, queue it again
      const double q[3][2] = { { 0, 0 }, { 1, 0 }, { 0, 1 } };
      MakeSubPatch(M, it.Face, q, p, SP, best, res.Face, res.UV, it.Face, slack);
      it.Depth = 0;
      for (int k = 0; k < 3; ++k)
        for (int j = 0; j < 2; ++j)
          it.Q[k][j] = q[k][j];
      it.Key = std::max(SP.Lower, top.Key);
      if (it.Key < best - tol)
      {
        H.push_back(it);
        std::push_heap(H.begin(), H.end());
      }
      else
        lower = std::min(lower, it.Key);
      continue;
    }
    MakeSubPatch(M, it.Face, it.Q, p, SP, best, res.Face, res.UV, it.Face, slack);
    if (ConvexityBound(SP, p) > 0.0)
    {
      double st[2], lowerG;
      const double g = SolveConvex(SP, p, st, lowerG);
      const double d = std::sqrt(g);
      // (s, t) -> face (u, v)
      double uv[2];
      for (int j = 0; j < 2; ++j)
        uv[j] = it.Q[0][j] + st[0] * (it.Q[1][j] - it.Q[0][j]) + st[1] * (it.Q[2][j] - it.Q[0][j]);
      if (d < best)
      {
        best = d;
        res.Face = it.Face;
        res.UV[0] = uv[0];
        res.UV[1] = uv[1];
      }
      const double lo = std::max(it.Key, std::sqrt(std::max(0.0, lowerG)) - slack);
      if (lo >= best - tol)
      {
        lower = std::min(lower, lo);
        continue;
      }
    }
    if (it.Depth >= opt.MaxDepth)
    {
      ++res.DepthLimited;
      lower = std::min(lower, it.Key);
      continue;
    }
    // split in four (mid-points of the parametric sub-triangle)
    double m[3][2];
    for (int k = 0; k < 3; ++k)
      for (int j = 0; j < 2; ++j)
        m[k][j] = 0.5 * (it.Q[k][j] + it.Q[(k + 1) % 3][j]);
    const double* kids[4][3] = { { it.Q[0], m[0], m[2] }, { m[0], it.Q[1], m[1] },
      { m[2], m[1], it.Q[2] }, { m[1], m[2], m[0] } };
    for (auto& kid : kids)
    {
      ExactScratch::Item c;
      c.Face = it.Face;
      c.Depth = it.Depth + 1;
      for (int k = 0; k < 3; ++k)
        for (int j = 0; j < 2; ++j)
          c.Q[k][j] = kid[k][j];
      SubPatch KP;
      MakeSubPatch(M, c.Face, c.Q, p, KP, best, res.Face, res.UV, c.Face, slack);
      c.Key = std::max(KP.Lower, it.Key);
      if (c.Key < best - tol)
      {
        H.push_back(c);
        std::push_heap(H.begin(), H.end());
      }
      else
        lower = std::min(lower, c.Key);
    }
  }
  if (!H.empty())
    lower = std::min(lower, H.front().Key);
  res.Upper = best;
  res.Lower = std::min(lower, best);
}

void ExplainInside(const ExactMesh& M, const double v[3])
{
  const double starts[5][3] = { { 0.25, 0.25, 0.25 }, { 0.1, 0.1, 0.1 }, { 0.7, 0.1, 0.1 },
    { 0.1, 0.7, 0.1 }, { 0.1, 0.1, 0.7 } };
  vtkNew<vtkQuadraticTetra> qt;
  vtkNew<vtkTetra> t4;
  const int npc = M.NodesPerCell;
  vtkCell* cell = npc == 10 ? static_cast<vtkCell*>(qt) : static_cast<vtkCell*>(t4);
  for (Id c = 0; c < M.NumberOfCells; ++c)
  {
    const double* b = &M.CellBox[6 * c];
    if (v[0] < b[0] || v[0] > b[1] || v[1] < b[2] || v[1] > b[3] || v[2] < b[4] || v[2] > b[5])
      continue;
    std::fprintf(stderr, "cell %lld:", static_cast<long long>(c));
    for (const auto& s : starts)
    {
      double pc[3] = { s[0], s[1], s[2] };
      const double r = Invert(M, c, v, pc);
      std::fprintf(stderr, " own(%.3g %.3g %.3g | %.2e)", pc[0], pc[1], pc[2], r / M.Diagonal);
    }
    {
      const ExactOptions opt;
      double pc[3] = { 0, 0, 0 };
      long nodes = 0;
      int undecided = 0;
      const bool in = InvertBySubdivision(
        M, c, v, 1e-12 * M.Diagonal, opt.InsideMaxDepth, opt.InsideMaxNodes, pc, nodes, undecided);
      std::fprintf(stderr, " subdivision(%s", in ? "inside" : "outside");
      if (in)
        std::fprintf(stderr, " at %.6g %.6g %.6g", pc[0], pc[1], pc[2]);
      std::fprintf(stderr, ", %ld sub-tets, %d undecided)", nodes, undecided);
    }
    double pcv[3], d2;
    const int ret = VtkEvaluate(M, c, cell, v, pcv, d2);
    std::fprintf(stderr, " vtk ret %d pc %.6g %.6g %.6g dist %.3g\n", ret, pcv[0], pcv[1], pcv[2],
      std::sqrt(d2) / M.Diagonal);
  }
}

void ExactDistance(
  const ExactMesh& M, const double v[3], const ExactOptions& opt, ExactScratch& S, ExactResult& res)
{
  ExactBoundaryDistance(M, v, opt, S, res);
  res.Inside = false;
  res.InsideCell = -1;
  res.InsideCellsVtk = res.InsideCellsOwn = res.CandidateCells = res.VtkDisagreements = 0;
  res.InsideVtk = false;
  res.InsideNodes = 0;
  res.InsideUndecided = 0;
  const double tolInside = 1e-12 * M.Diagonal;
  const int npc = M.NodesPerCell;
  vtkCell* cell = npc == 10 ? static_cast<vtkCell*>(S.Tet10) : static_cast<vtkCell*>(S.Tet4);
  for (Id c = 0; c < M.NumberOfCells; ++c)
  {
    const double* b = &M.CellBox[6 * c];
    if (v[0] < b[0] || v[0] > b[1] || v[1] < b[2] || v[1] > b[3] || v[2] < b[4] || v[2] > b[5])
      continue;
    ++res.CandidateCells;
    double pc[3];
    const bool own = InvertBySubdivision(M, c, v, tolInside, opt.InsideMaxDepth, opt.InsideMaxNodes,
      pc, res.InsideNodes, res.InsideUndecided);
    // VTK's own inversion, with a strict reading of its parametric coordinates
    double pcv[3], d2;
    const int ret = VtkEvaluate(M, c, cell, v, pcv, d2);
    const double slackPc = 1e-9;
    const bool vtkIn = ret == 1 && pcv[0] >= -slackPc && pcv[1] >= -slackPc && pcv[2] >= -slackPc &&
      pcv[0] + pcv[1] + pcv[2] <= 1.0 + slackPc;
    res.InsideCellsOwn += own;
    res.InsideCellsVtk += vtkIn;
    res.InsideVtk = res.InsideVtk || vtkIn;
    if (own != vtkIn)
      ++res.VtkDisagreements;
    if (own && !res.Inside)
    {
      res.Inside = true;
      res.InsideCell = c;
    }
  }
}
} // namespace hoembed_exact
