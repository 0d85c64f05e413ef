#include "hoembedSurfaceCheck.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace hoembed
{
void SurfaceCheck::Run(const double* pts, Id npts, const Id* tris, Id ntris)
{
  *this = SurfaceCheck();
  // Directed half-edges bucketed by their smaller endpoint.
  std::vector<Id> offsets(npts + 1, 0);
  for (Id t = 0; t < ntris; ++t)
  {
    for (int e = 0; e < 3; ++e)
    {
      const Id a = tris[3 * t + e], b = tris[3 * t + (e + 1) % 3];
      ++offsets[(a < b ? a : b) + 1];
    }
  }
  for (Id i = 0; i < npts; ++i)
  {
    offsets[i + 1] += offsets[i];
  }
  struct Half
  {
    Id Other;
    bool Forward; // a < b in the triangle's direction
  };
  std::vector<Half> halves(offsets[npts]);
  std::vector<Id> fill(offsets.begin(), offsets.end() - 1);
  for (Id t = 0; t < ntris; ++t)
  {
    const Id* tri = tris + 3 * t;
    if (tri[0] == tri[1] || tri[1] == tri[2] || tri[2] == tri[0])
    {
      ++this->DegenerateTriangles;
    }
    const double* p0 = pts + 3 * tri[0];
    const double* p1 = pts + 3 * tri[1];
    const double* p2 = pts + 3 * tri[2];
    const double u[3] = { p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2] };
    const double v[3] = { p2[0] - p0[0], p2[1] - p0[1], p2[2] - p0[2] };
    const double n[3] = { u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2],
      u[0] * v[1] - u[1] * v[0] };
    const double area2 = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    if (!(area2 > 0.0) && !(tri[0] == tri[1] || tri[1] == tri[2] || tri[2] == tri[0]))
    {
      ++this->DegenerateTriangles;
    }
    this->Area += 0.5 * area2;
    this->SignedVolume += (p0[0] * n[0] + p0[1] * n[1] + p0[2] * n[2]) / 6.0;
    for (int e = 0; e < 3; ++e)
    {
      const Id a = tri[e], b = tri[(e + 1) % 3];
      const Id lo = a < b ? a : b;
      halves[fill[lo]++] = Half{ a < b ? b : a, a < b };
    }
  }
  for (Id p = 0; p < npts; ++p)
  {
    for (Id i = offsets[p]; i < offsets[p + 1]; ++i)
    {
      Id count = 0, forward = 0;
      bool first = true;
      for (Id j = offsets[p]; j < offsets[p + 1]; ++j)
      {
        if (halves[j].Other != halves[i].Other)
          continue;
        if (j < i)
          first = false;
        ++count;
        forward += halves[j].Forward ? 1 : 0;
      }
      if (!first)
        continue;
      bool bad = false;
      if (count == 1)
      {
        ++this->BoundaryEdges;
        bad = true;
      }
      else if (count > 2)
      {
        ++this->NonManifoldEdges;
        bad = true;
      }
      else if (forward != 1)
      {
        ++this->InconsistentEdges;
        bad = true;
      }
      if (bad && this->ExampleEdge[0] < 0)
      {
        this->ExampleEdge[0] = p;
        this->ExampleEdge[1] = halves[i].Other;
      }
    }
  }
}

bool SegmentCrossesTriangle(
  const double* p, const double* q, const double* a, const double* b, const double* c, double eps)
{
  double d[3], e1[3], e2[3], h[3], s[3], qv[3];
  for (int k = 0; k < 3; ++k)
  {
    d[k] = q[k] - p[k];
    e1[k] = b[k] - a[k];
    e2[k] = c[k] - a[k];
  }
  h[0] = d[1] * e2[2] - d[2] * e2[1];
  h[1] = d[2] * e2[0] - d[0] * e2[2];
  h[2] = d[0] * e2[1] - d[1] * e2[0];
  const double det = e1[0] * h[0] + e1[1] * h[1] + e1[2] * h[2];
  const double scale = std::sqrt((d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) *
    (e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2]) *
    (e2[0] * e2[0] + e2[1] * e2[1] + e2[2] * e2[2]));
  if (std::fabs(det) <= 1e-12 * scale)
  {
    return false; // parallel or coplanar: left to the other edges' tests
  }
  const double inv = 1.0 / det;
  for (int k = 0; k < 3; ++k)
    s[k] = p[k] - a[k];
  const double u = inv * (s[0] * h[0] + s[1] * h[1] + s[2] * h[2]);
  if (u < -eps || u > 1.0 + eps)
    return false;
  qv[0] = s[1] * e1[2] - s[2] * e1[1];
  qv[1] = s[2] * e1[0] - s[0] * e1[2];
  qv[2] = s[0] * e1[1] - s[1] * e1[0];
  const double v = inv * (d[0] * qv[0] + d[1] * qv[1] + d[2] * qv[2]);
  if (v < -eps || u + v > 1.0 + eps)
    return false;
  const double t = inv * (e2[0] * qv[0] + e2[1] * qv[1] + e2[2] * qv[2]);
  return t >= -eps && t <= 1.0 + eps;
}

SurfaceCheck::Id SurfaceCheck::CountSelfIntersections(
  const double* pts, Id npts, const Id* tris, Id ntris, double relTol, Id maxCount)
{
  (void)npts;
  struct Box
  {
    double Lo[3], Hi[3];
    Id Tri;
  };
  std::vector<Box> boxes(ntris);
  double glo[3] = { 1e300, 1e300, 1e300 }, ghi[3] = { -1e300, -1e300, -1e300 };
  for (Id t = 0; t < ntris; ++t)
  {
    Box& b = boxes[t];
    b.Tri = t;
    for (int k = 0; k < 3; ++k)
    {
      b.Lo[k] = 1e300;
      b.Hi[k] = -1e300;
    }
    for (int v = 0; v < 3; ++v)
      for (int k = 0; k < 3; ++k)
      {
        const double x = pts[3 * tris[3 * t + v] + k];
        b.Lo[k] = std::min(b.Lo[k], x);
        b.Hi[k] = std::max(b.Hi[k], x);
        glo[k] = std::min(glo[k], x);
        ghi[k] = std::max(ghi[k], x);
      }
  }
  const double diag = std::sqrt((ghi[0] - glo[0]) * (ghi[0] - glo[0]) +
    (ghi[1] - glo[1]) * (ghi[1] - glo[1]) + (ghi[2] - glo[2]) * (ghi[2] - glo[2]));
  const double pad = relTol * diag;
  std::sort(
    boxes.begin(), boxes.end(), [](const Box& a, const Box& b) { return a.Lo[0] < b.Lo[0]; });
  Id count = 0;
  for (size_t i = 0; i < boxes.size() && count < maxCount; ++i)
  {
    const Box& A = boxes[i];
    const Id* ta = tris + 3 * A.Tri;
    for (size_t j = i + 1; j < boxes.size() && boxes[j].Lo[0] <= A.Hi[0] + pad; ++j)
    {
      const Box& B = boxes[j];
      if (B.Lo[1] > A.Hi[1] + pad || B.Hi[1] < A.Lo[1] - pad || B.Lo[2] > A.Hi[2] + pad ||
        B.Hi[2] < A.Lo[2] - pad)
        continue;
      const Id* tb = tris + 3 * B.Tri;
      int shared = 0, sa = -1, sb = -1;
      for (int x = 0; x < 3; ++x)
        for (int y = 0; y < 3; ++y)
          if (ta[x] == tb[y])
          {
            ++shared;
            sa = x;
            sb = y;
          }
      if (shared >= 2)
        continue;
      // Relative tolerance in barycentric terms.
      const double eps = 1e-9;
      bool hit = false;
      for (int e = 0; e < 3 && !hit; ++e)
      {
        // With one shared vertex, only the edges away from it can cross the other triangle.
        if (shared == 1 && (e == sa || (e + 1) % 3 == sa))
          ;
        else
          hit = SegmentCrossesTriangle(&pts[3 * ta[e]], &pts[3 * ta[(e + 1) % 3]], &pts[3 * tb[0]],
            &pts[3 * tb[1]], &pts[3 * tb[2]], eps);
        if (!hit && !(shared == 1 && (e == sb || (e + 1) % 3 == sb)))
          hit = SegmentCrossesTriangle(&pts[3 * tb[e]], &pts[3 * tb[(e + 1) % 3]], &pts[3 * ta[0]],
            &pts[3 * ta[1]], &pts[3 * ta[2]], eps);
      }
      if (hit && ++count >= maxCount)
        break;
    }
  }
  return count;
}
} // namespace hoembed
