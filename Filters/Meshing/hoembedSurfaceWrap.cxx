#include "hoembedSurfaceWrap.h"

#include "hoembedTetGenBridge.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/alpha_wrap_3.h>

#include <array>
#include <cmath>
#include <exception>
#include <functional>
#include <sstream>
#include <unordered_map>

namespace hoembed
{
namespace
{
using Id = std::int64_t;
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Mesh = CGAL::Surface_mesh<Point>;

// Twice the area of triangle abc, squared.
double DoubleArea2(const double* a, const double* b, const double* c)
{
  const double u[3] = { b[0] - a[0], b[1] - a[1], b[2] - a[2] };
  const double v[3] = { c[0] - a[0], c[1] - a[1], c[2] - a[2] };
  const double n[3] = { u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2],
    u[0] * v[1] - u[1] * v[0] };
  return n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
}

// Thrown by the visitor to leave CGAL's flood fill (private: caught below only).
struct WrapStopped
{
  bool Aborted;
};

// Counts the flood fill's work; stops it at the bounds or on an abort. CGAL 5.5 calls
// the visitor once per gate treated and once per Steiner point inserted; CGAL's wrapper
// and its triangulation are local to alpha_wrap_3, so unwinding through it leaks nothing.
struct WorkVisitor : CGAL::Alpha_wraps_3::internal::Wrapping_default_visitor
{
  const SurfaceWrapLimits* Limits = nullptr;
  SurfaceWrapResult* Out = nullptr;

  template <typename Wrapper, typename Gate>
  void before_facet_treatment(const Wrapper&, const Gate&)
  {
    const std::uint64_t gates = ++this->Out->Gates;
    if (this->Limits->MaxGates > 0 && gates > this->Limits->MaxGates)
      throw WrapStopped{ false };
    if ((gates & 255u) == 0 &&
      (this->Limits->Abort ? this->Limits->Abort() : MeshingAbortRequested()))
      throw WrapStopped{ true };
  }
  template <typename Wrapper, typename Point>
  void before_Steiner_point_insertion(const Wrapper&, const Point&)
  {
    const std::uint64_t steiner = ++this->Out->SteinerPoints;
    if (this->Limits->MaxSteinerPoints > 0 && steiner > this->Limits->MaxSteinerPoints)
      throw WrapStopped{ false };
  }
};
} // namespace

SurfaceWrapResult WrapSurface(const std::vector<double>& points, const std::vector<Id>& tris,
  double alpha, double offset, const SurfaceWrapLimits& limits)
{
  SurfaceWrapResult out;
  if (!(alpha > 0.0) || !(offset > 0.0) || !std::isfinite(alpha) || !std::isfinite(offset))
  {
    out.Error = "the wrap needs a positive alpha and offset";
    return out;
  }
  const Id np = static_cast<Id>(points.size() / 3);
  std::vector<Point> cgalPoints;
  cgalPoints.reserve(static_cast<size_t>(np));
  for (Id i = 0; i < np; ++i)
    cgalPoints.emplace_back(points[3 * i], points[3 * i + 1], points[3 * i + 2]);
  // CGAL's AABB tree and projections are undefined on degenerate triangles.
  std::vector<std::array<std::size_t, 3>> faces;
  faces.reserve(tris.size() / 3);
  for (size_t t = 0; t < tris.size() / 3; ++t)
  {
    const Id a = tris[3 * t], b = tris[3 * t + 1], c = tris[3 * t + 2];
    if (a < 0 || b < 0 || c < 0 || a >= np || b >= np || c >= np || a == b || b == c || a == c)
      continue;
    if (!(DoubleArea2(&points[3 * a], &points[3 * b], &points[3 * c]) > 0.0))
      continue;
    if (CGAL::collinear(cgalPoints[a], cgalPoints[b], cgalPoints[c]))
      continue;
    faces.push_back(
      { static_cast<std::size_t>(a), static_cast<std::size_t>(b), static_cast<std::size_t>(c) });
  }
  out.UsedTriangles = static_cast<Id>(faces.size());
  if (faces.empty())
  {
    out.Error = "no triangle with a non-zero area to wrap";
    return out;
  }
  Mesh wrap;
  WorkVisitor visitor;
  visitor.Limits = &limits;
  visitor.Out = &out;
  try
  {
    CGAL::alpha_wrap_3(cgalPoints, faces, alpha, offset, wrap, CGAL::parameters::default_values(),
      CGAL::parameters::visitor(std::ref(visitor)));
  }
  catch (const WrapStopped& stop)
  {
    std::ostringstream msg;
    out.Stopped = true;
    out.Aborted = stop.Aborted;
    if (stop.Aborted)
      msg << "meshing was aborted (AbortExecute) during the envelope (CGAL's alpha wrap)";
    else
      msg << "the envelope (CGAL's alpha wrap) exceeded its work bound (" << out.SteinerPoints
          << " points inserted, " << out.Gates << " facets treated; bounds "
          << limits.MaxSteinerPoints << " and " << limits.MaxGates << ")";
    out.Error = msg.str();
    return out;
  }
  catch (const std::exception& e)
  {
    out.Error = std::string("CGAL's alpha wrapping failed: ") + e.what();
    return out;
  }
  if (wrap.number_of_faces() == 0)
  {
    out.Error = "CGAL's alpha wrapping returned an empty envelope";
    return out;
  }
  std::unordered_map<Mesh::Vertex_index, Id> index;
  index.reserve(wrap.number_of_vertices());
  out.Points.reserve(3 * wrap.number_of_vertices());
  for (Mesh::Vertex_index v : wrap.vertices())
  {
    index.emplace(v, static_cast<Id>(out.Points.size() / 3));
    const Point& p = wrap.point(v);
    out.Points.push_back(p.x());
    out.Points.push_back(p.y());
    out.Points.push_back(p.z());
  }
  out.Tris.reserve(3 * wrap.number_of_faces());
  for (Mesh::Face_index f : wrap.faces())
    for (Mesh::Vertex_index v : wrap.vertices_around_face(wrap.halfedge(f)))
      out.Tris.push_back(index.at(v));
  return out;
}
} // namespace hoembed
