// hoembed._hoembed.mesh_surface: the mesher (hoembed::ReadSurface + hoembed::RunMesher, the
// functions vtkTet10Mesher calls) for the pip wheel.
//
// The VTK-dependent steps come from a Python object (Wrapping/Python/hoembed/meshing.py's
// services over the user's pip VTK) with the methods
//   ear_cut(ids, xyz) -> local ids or None        merge(tris) -> (points, tris) or None
//   decimate(reduction, smoothed) -> (points, tris) or None
//   closest(x, y, z) -> (x, y, z)                 ray(ax, ay, az, bx, by, bz) -> (x, y, z) or None
//   vertices_within(x, y, z, r) -> (k, 3) array   normal_at(x, y, z) -> (x, y, z)
//   max_distance(points, tris, query) -> float    check_cell(x10) -> bool
// The driver calls them one at a time from this thread (it runs no threads of its own),
// with the GIL held throughout: no locking per call. Arrays handed to Python are copies
// (Python may keep them); results are read into the driver's vectors. A Python exception
// in a service propagates out of mesh_surface as that exception.
#include "hoembedArrayNames.h"
#include "hoembedMesherDriver.h"
#include "hoembedSurfaceRead.h"

#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/vector.h>

#include <cstdint>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

namespace nb = nanobind;

namespace
{
using Id = std::int64_t;
using In = nb::ndarray<nb::ro, nb::c_contig, nb::device::cpu>;

template <typename T>
const T* Data(const In& a, const char* what)
{
  if (a.dtype() != nb::dtype<T>())
    throw std::invalid_argument(std::string(what) + ": wrong dtype");
  return static_cast<const T*>(a.data());
}

hoembed::SurfaceCells Cells(const In& offsets, const In& conn, const char* what)
{
  hoembed::SurfaceCells c;
  if (offsets.size() < 2)
    return c;
  c.NumberOfCells = static_cast<Id>(offsets.size()) - 1;
  c.Offsets = Data<Id>(offsets, what);
  c.Connectivity = Data<Id>(conn, what);
  if (c.Offsets[0] != 0 || c.Offsets[c.NumberOfCells] != static_cast<Id>(conn.size()))
    throw std::invalid_argument(std::string(what) + ": offsets do not match the connectivity");
  for (Id k = 0; k < c.NumberOfCells; ++k)
    if (c.Offsets[k + 1] < c.Offsets[k])
      throw std::invalid_argument(std::string(what) + ": offsets decrease");
  return c;
}

// A numpy array that owns a copy of `n` values of `data`, shaped (n / cols, cols).
template <typename T>
nb::object Copy(const T* data, size_t n, size_t cols)
{
  auto* heap = new std::vector<T>(data, data + n);
  nb::capsule owner(heap, [](void* p) noexcept { delete static_cast<std::vector<T>*>(p); });
  return nb::cast(nb::ndarray<nb::numpy, T>(heap->data(), { n / cols, cols }, owner));
}
template <typename T>
nb::object Take(std::vector<T>&& v, size_t cols)
{
  auto* heap = new std::vector<T>(std::move(v));
  nb::capsule owner(heap, [](void* p) noexcept { delete static_cast<std::vector<T>*>(p); });
  return nb::cast(nb::ndarray<nb::numpy, T>(heap->data(), { heap->size() / cols, cols }, owner));
}

// The values of a numpy array (any shape) returned by a service, as T.
template <typename T>
void Read(const nb::handle& h, std::vector<T>& out, const char* what)
{
  In a;
  if (!nb::try_cast(h, a) || a.dtype() != nb::dtype<T>())
    throw std::invalid_argument(std::string("mesher service ") + what +
      ": expected a C-contiguous numpy array of " +
      (std::is_floating_point<T>::value ? "float64" : "int64"));
  const T* p = static_cast<const T*>(a.data());
  out.assign(p, p + a.size());
}

void Read3(const nb::handle& h, double out[3])
{
  nb::tuple t = nb::cast<nb::tuple>(h);
  for (int d = 0; d < 3; ++d)
    out[d] = nb::cast<double>(t[d]);
}

// (points, tris) of a service, or false for None.
bool ReadSurface(
  const nb::object& r, std::vector<double>& points, std::vector<Id>& tris, const char* what)
{
  if (r.is_none())
    return false;
  nb::tuple t = nb::cast<nb::tuple>(r);
  Read(t[0], points, what);
  Read(t[1], tris, what);
  if (points.size() % 3 != 0 || tris.size() % 3 != 0)
    throw std::invalid_argument(
      std::string("mesher service ") + what + ": not 3 values per point/triangle");
  return true;
}

hoembed::MesherServices Services(const nb::object& py)
{
  hoembed::MesherServices s;
  nb::object decimate = py.attr("decimate"), closest = py.attr("closest"), ray = py.attr("ray"),
             within = py.attr("vertices_within"), normal = py.attr("normal_at"),
             distance = py.attr("max_distance"), check = py.attr("check_cell");
  s.Decimate = [decimate](double reduction, bool smoothed, std::vector<double>& points,
                 std::vector<Id>& tris) {
    return ReadSurface(decimate(reduction, smoothed), points, tris, "decimate");
  };
  s.Fine.Closest = [closest](
                     const double x[3], double cp[3]) { Read3(closest(x[0], x[1], x[2]), cp); };
  s.Fine.Ray = [ray](const double a[3], const double b[3], double hit[3]) {
    nb::object r = ray(a[0], a[1], a[2], b[0], b[1], b[2]);
    if (r.is_none())
      return false;
    Read3(r, hit);
    return true;
  };
  s.Fine.VerticesWithin = [within](const double x[3], double r, std::vector<double>& out) {
    Read(within(x[0], x[1], x[2], r), out, "vertices_within");
  };
  s.NormalAt = [normal](const double x[3], double n[3]) { Read3(normal(x[0], x[1], x[2]), n); };
  s.MaxDistanceToTriangles = [distance](const std::vector<double>& points,
                               const std::vector<Id>& tris, const std::vector<double>& query,
                               Id stride) {
    // every stride-th query point, as the VTK build's service measures
    std::vector<double> every;
    for (size_t i = 0; i < query.size() / 3; i += static_cast<size_t>(stride))
      every.insert(every.end(), &query[3 * i], &query[3 * i] + 3);
    return nb::cast<double>(distance(Copy(points.data(), points.size(), 3),
      Copy(tris.data(), tris.size(), 3), Take(std::move(every), 3)));
  };
  s.ExtraCheck = [check](const double* x10) { return nb::cast<bool>(check(Copy(x10, 30, 3))); };
  return s;
}

nb::dict MeshSurface(const In& points, const In& vertOffsets, const In& vertConn,
  const In& lineOffsets, const In& lineConn, const In& polyOffsets, const In& polyConn,
  const In& stripOffsets, const In& stripConn, const nb::dict& opts, Id maximumElements,
  nb::object services, nb::object progress)
{
  hoembed::SurfaceInput in;
  in.NumberOfPoints = static_cast<Id>(points.size() / 3);
  in.Points = in.NumberOfPoints ? Data<double>(points, "points") : nullptr;
  in.Verts = Cells(vertOffsets, vertConn, "vertices");
  in.Lines = Cells(lineOffsets, lineConn, "lines");
  in.Polys = Cells(polyOffsets, polyConn, "polygons");
  in.Strips = Cells(stripOffsets, stripConn, "strips");

  hoembed::MesherOptions o;
  o.TargetNumberOfElements = nb::cast<int>(opts["TargetNumberOfElements"]);
  o.TargetEdgeLength = nb::cast<double>(opts["TargetEdgeLength"]);
  o.ElementOrder = nb::cast<int>(opts["ElementOrder"]);
  o.CurveBoundary = nb::cast<bool>(opts["CurveBoundary"]);
  o.RadiusEdgeRatio = nb::cast<double>(opts["RadiusEdgeRatio"]);
  o.MinDihedralAngle = nb::cast<double>(opts["MinDihedralAngle"]);
  o.CurvedQualityTarget = nb::cast<double>(opts["CurvedQualityTarget"]);
  o.MinimumQuality = nb::cast<double>(opts["MinimumQuality"]);

  // The read step, in vtkTet10Mesher's order: ids, size, then the surface itself.
  std::string error = hoembed::CheckSurfacePointIds(in);
  if (error.empty())
    error = hoembed::CheckEstimatedSize(
      in, o.TargetEdgeLength, o.TargetNumberOfElements, maximumElements, "MaximumNumberOfElements");
  if (!error.empty())
    throw std::runtime_error(error);
  hoembed::SurfaceReadServices read;
  nb::object earCut = services.attr("ear_cut"), merge = services.attr("merge");
  read.EarCut = [earCut](const Id* ids, Id n, const double* xyz, std::vector<Id>& local) {
    nb::object r = earCut(Copy(ids, n, 1), Copy(xyz, 3 * n, 3));
    if (r.is_none())
      return false;
    Read(r, local, "ear_cut");
    return true;
  };
  read.Merge = [merge](
                 const std::vector<Id>& tris, std::vector<double>& pts, std::vector<Id>& out) {
    return ReadSurface(merge(Copy(tris.data(), tris.size(), 3)), pts, out, "merge");
  };
  std::vector<double> finePoints;
  std::vector<Id> fineTris;
  error = hoembed::ReadSurface(in, read, finePoints, fineTris);
  if (!error.empty())
    throw std::runtime_error(error);

  std::function<void(double)> report;
  if (!progress.is_none())
    report = [progress](double f) { progress(f); };
  hoembed::MesherResult r = hoembed::RunMesher(finePoints, fineTris, o, Services(services), report);
  if (!r.Error.empty())
  {
    nb::dict failed;
    failed["error"] = r.Error;
    failed["warnings"] = r.Warnings;
    return failed;
  }
  nb::dict out;
  const size_t npc = static_cast<size_t>(r.NodesPerCell);
  out["error"] = std::string();
  out["warnings"] = r.Warnings;
  out["points"] = Take(std::move(r.Points), 3);
  out["connectivity"] = Take(std::move(r.Conn), npc);
  out["nodes_per_cell"] = r.NodesPerCell;
  // the output arrays by their names (hoembedArrayNames.h)
  namespace N = hoembed::ArrayNames;
  out[N::MinScaledJacobian] = Take(std::move(r.MinScaledJacobian), 1);
  out[N::BoundaryNode] = Take(std::move(r.BoundaryNode), 1);
  out[N::RelaxedNodeCount] = r.RelaxedNodeCount;
  out[N::CurvedNodeCount] = r.CurvedNodeCount;
  out[N::EnvelopeNodeCount] = r.EnvelopeNodeCount;
  out[N::BoundaryCrossingsFound] = r.BoundaryCrossingsFound;
  out[N::BoundaryCrossingsLeft] = r.BoundaryCrossingsLeft;
  out[N::PoorElementCount] = r.PoorElementCount;
  out[N::MinScaledJacobianQuantiles] =
    nb::make_tuple(r.QualityQuantiles[0], r.QualityQuantiles[1], r.QualityQuantiles[2]);
  out[N::MaxSurfaceDeviation] = r.MaxSurfaceDeviation;
  out[N::EnvelopeOffset] = r.Wrapped ? r.EnvelopeOffset : 0.0;
  return out;
}
} // namespace

nb::dict MesherDefaults()
{
  // vtkTet10Mesher's property defaults by its property names (the members' names):
  // hoembed::MesherOptions and the read step's settings (hoembed::MesherServiceSettings)
  const hoembed::MesherOptions o;
  using S = hoembed::MesherServiceSettings;
  nb::dict d;
#define HOEMBED_DEFAULT(member) d[#member] = o.member
  HOEMBED_DEFAULT(TargetNumberOfElements);
  HOEMBED_DEFAULT(TargetEdgeLength);
  HOEMBED_DEFAULT(ElementOrder);
  HOEMBED_DEFAULT(CurveBoundary);
  HOEMBED_DEFAULT(ProjectCorners);
  HOEMBED_DEFAULT(PreserveBoundary);
  HOEMBED_DEFAULT(RadiusEdgeRatio);
  HOEMBED_DEFAULT(MinDihedralAngle);
  HOEMBED_DEFAULT(SurfaceDeviationWarning);
  HOEMBED_DEFAULT(CurvedQualityRatio);
  HOEMBED_DEFAULT(MinimumQuality);
  HOEMBED_DEFAULT(CurvedQualityTarget);
  HOEMBED_DEFAULT(EnvelopeTolerance);
#undef HOEMBED_DEFAULT
  d["MergeTolerance"] = S::MergeTolerance;
  d["MaximumNumberOfElements"] = S::MaximumNumberOfElements;
  return d;
}

void BindMesher(nb::module_& m)
{
  m.def("mesh_surface", &MeshSurface, nb::arg("points"), nb::arg("vert_offsets"),
    nb::arg("vert_connectivity"), nb::arg("line_offsets"), nb::arg("line_connectivity"),
    nb::arg("poly_offsets"), nb::arg("poly_connectivity"), nb::arg("strip_offsets"),
    nb::arg("strip_connectivity"), nb::arg("options"), nb::arg("maximum_elements"),
    nb::arg("services"), nb::arg("progress").none(),
    "vtkTet10Mesher's read step and hoembed::RunMesher on numpy arrays, with the VTK "
    "services given by a Python object; returns a dict of the result's arrays and counts "
    "('error' non-empty when the driver failed; read-step errors raise RuntimeError)");
  using S = hoembed::MesherServiceSettings;
  nb::dict settings;
  settings["smoothing_iterations"] = S::SmoothingIterations;
  settings["smoothing_pass_band"] = S::SmoothingPassBand;
  settings["cell_check_tolerance"] = S::CellCheckTolerance;
  settings["refused_cell_states"] = S::RefusedCellStates;
  settings["merge_tolerance"] = S::MergeTolerance;
  settings["maximum_number_of_elements"] = S::MaximumNumberOfElements;
  m.attr("MESHER_SERVICE_SETTINGS") = settings;
}
