// hoembed._hoembed: the nanobind binding of the drivers, the compiled module of the hoembed
// package in both builds (the pip wheel: linked with the VTK-free kernels, Wrapping/Pip;
// the VTK build: linked with its HOEmbed modules, Wrapping/Python/CMakeLists.txt).
//
// The drivers are the ones vtkEmbeddingCoordinatesFilter, vtkDeformationTransferFilter
// and vtkCorotationalFEMStepper call (hoembedEmbeddingDriver.h, hoembedTransferDriver.h,
// hoembedStepperDriver.h); this file only turns numpy
// arrays into the drivers' plain views and back. Output arrays are allocated by the
// Python side (Wrapping/Python/hoembed) and written in place. Errors: the drivers' sentences
// are raised as RuntimeError; the Python side turns them into hoembed.HOEmbedError.
#include "hoembedArrayNames.h"
#include "hoembedEmbeddingDriver.h"
#include "hoembedMesherDriver.h"
#include "hoembedParallel.h"
#include "hoembedStepperDriver.h"
#include "hoembedTetMeshInput.h"
#include "hoembedTransferDriver.h"

#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>
#include <nanobind/stl/pair.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/vector.h>

#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace nb = nanobind;

// hoembedPipSeries.cxx
void BindSeries(nb::module_& m);
// the mesher's bindings and vtkTet10Mesher's defaults (hoembedPipMesher.cxx)
void BindMesher(nb::module_& m);
nb::dict MesherDefaults();

namespace
{
// inputs may be read-only numpy arrays (views of VTK arrays); outputs are written
using In = nb::ndarray<nb::ro, nb::c_contig, nb::device::cpu>;
using Array = nb::ndarray<nb::c_contig, nb::device::cpu>;

template <typename A, typename T>
bool IsT(const A& a)
{
  return a.dtype() == nb::dtype<T>();
}
template <typename T>
bool Is(const In& a)
{
  return IsT<In, T>(a);
}

template <typename T>
const T* Data(const In& a, const char* what, std::size_t count)
{
  if (!Is<T>(a))
    throw std::invalid_argument(std::string(what) + ": wrong dtype");
  if (a.size() != count)
    throw std::invalid_argument(std::string(what) + ": wrong size");
  return static_cast<const T*>(a.data());
}

template <typename T>
T* Out(Array& a, const char* what, std::size_t count)
{
  if (!IsT<Array, T>(a))
    throw std::invalid_argument(std::string(what) + ": wrong dtype");
  if (a.size() != count)
    throw std::invalid_argument(std::string(what) + ": wrong size");
  return static_cast<T*>(a.data());
}

// A cell array (VTK layout) from int64 offsets and connectivity.
hoembed::CellArrayView Cells(const In& offsets, const In& conn)
{
  hoembed::CellArrayView v;
  if (offsets.size() < 2)
    return v;
  v.NumberOfCells = static_cast<std::int64_t>(offsets.size()) - 1;
  v.Offsets64 = Data<std::int64_t>(offsets, "offsets", offsets.size());
  v.Connectivity64 = Data<std::int64_t>(conn, "connectivity", conn.size());
  return v;
}

// The FE mesh as TetMeshArrays; `points` may be None (topology only).
hoembed::TetMeshArrays Mesh(
  std::int64_t numberOfPoints, const In* points, const In& types, const In& offsets, const In& conn)
{
  hoembed::TetMeshArrays m;
  m.NumberOfPoints = numberOfPoints;
  if (points)
  {
    if (Is<double>(*points))
      m.PointsDouble = Data<double>(*points, "mesh points", 3 * numberOfPoints);
    else
      m.PointsFloat = Data<float>(*points, "mesh points", 3 * numberOfPoints);
  }
  m.NumberOfCells = static_cast<std::int64_t>(types.size());
  m.CellTypes = Data<std::uint8_t>(types, "cell types", types.size());
  if (offsets.size() != types.size() + 1)
    throw std::invalid_argument("cell offsets: wrong size");
  m.Offsets64 = Data<std::int64_t>(offsets, "cell offsets", offsets.size());
  m.Connectivity64 = Data<std::int64_t>(conn, "cell connectivity", conn.size());
  return m;
}

void Check(const std::string& error)
{
  if (!error.empty())
    throw std::runtime_error(error);
}

// The transfer driver's loops on hoembedParallel.h (std::thread in this build).
void PoolFor(
  std::int64_t n, std::int64_t grain, const std::function<void(std::int64_t, std::int64_t)>& body)
{
  hoembed::ParallelLoop(std::int64_t(0), n, grain, body);
}

// A point array's shape for the transfer driver's checks: (components, tuples), or None.
hoembed::TransferArrayShape Shape(const nb::object& o)
{
  hoembed::TransferArrayShape shape;
  if (!o.is_none())
  {
    const auto ct = nb::cast<std::pair<int, std::int64_t>>(o);
    shape.Present = true;
    shape.Components = ct.first;
    shape.Tuples = ct.second;
  }
  return shape;
}

// A driver's range table as {name: (min, max, min_open, max_open, integer)}, None for
// no bound (hoembed::NoLimit).
template <std::size_t N>
nb::dict Ranges(const hoembed::PropertyRange (&table)[N])
{
  nb::dict d;
  auto bound = [](double v) -> nb::object {
    if (v == hoembed::NoLimit || v == -hoembed::NoLimit)
      return nb::object(nb::none());
    return nb::object(nb::float_(v));
  };
  for (const hoembed::PropertyRange& r : table)
    d[r.Name] = nb::make_tuple(bound(r.Min), bound(r.Max), r.MinOpen, r.MaxOpen, r.Integer);
  return d;
}

struct Transfer
{
  hoembed::TransferDriver Driver{ PoolFor };
};

// The surface's polygons (int64 VTK offsets/connectivity) into the transfer driver.
void SetPolygons(Transfer& t, const In& offsets, const In& conn)
{
  const std::int64_t nv = t.Driver.GetNumberOfVertices();
  const std::int64_t npoly = offsets.size() > 0 ? static_cast<std::int64_t>(offsets.size()) - 1 : 0;
  const std::int64_t zero = 0;
  t.Driver.SetPolygons(npoly > 0 ? Data<std::int64_t>(offsets, "offsets", offsets.size()) : &zero,
    Data<std::int64_t>(conn, "connectivity", conn.size()), npoly, nv);
}

// An optional float64 array of `count` values (None: nullptr); `keep` holds the view.
const double* Optional(const nb::object& o, In& keep, const char* what, std::size_t count)
{
  if (o.is_none())
    return nullptr;
  keep = nb::cast<In>(o);
  return Data<double>(keep, what, count);
}

// vtkCorotationalFEMStepper's BuildSolver and Advance on numpy arrays; the frame's arrays
// are written as the filter's WriteOutput writes them.
struct Stepper
{
  hoembed::StepperDriver Driver;
  hoembed::StepperParameters Parameters;
  long long NumberOfPoints = 0;
  long long NumberOfCells = 0;
  bool Static = false;
  bool Built = false;
  // the loads a live advance applies (the filter's Gravity and PrescribedSpeedLimit; set
  // by build)
  double Gravity[3] = { 0.0, 0.0, 0.0 };
  double SpeedLimit = hoembed::StepperOptions().PrescribedSpeedLimit;
};

// Every filter's property defaults by its property names (enumerations as their int
// values, vectors as tuples): the drivers' options structs, which the filters' constructors
// copy too; the package's keyword defaults are read from here. The options' members carry
// the properties' names, so the keys are the members' names.
#define HOEMBED_DEFAULT(dict, options, member) dict[#member] = options.member
#define HOEMBED_DEFAULT_ENUM(dict, options, member) dict[#member] = static_cast<int>(options.member)
#define HOEMBED_DEFAULT_VECTOR3(dict, options, member)                                             \
  dict[#member] = nb::make_tuple(options.member[0], options.member[1], options.member[2])
nb::dict Defaults()
{
  nb::dict all;
  all["mesher"] = MesherDefaults();

  const hoembed::EmbeddingOptions e;
  nb::dict embedding;
  HOEMBED_DEFAULT(embedding, e, Method);
  HOEMBED_DEFAULT(embedding, e, NumberOfPartitions);
  HOEMBED_DEFAULT(embedding, e, ValidateElements);
  HOEMBED_DEFAULT(embedding, e, ReuseMeshPreparation);
  all["embedding"] = embedding;

  const hoembed::TransferOptions t;
  nb::dict transfer;
  HOEMBED_DEFAULT_ENUM(transfer, t, NormalMode);
  HOEMBED_DEFAULT(transfer, t, ComputePointNormals);
  HOEMBED_DEFAULT_ENUM(transfer, t, PointNormalsMode);
  HOEMBED_DEFAULT(transfer, t, CheckInvertedElements);
  HOEMBED_DEFAULT(transfer, t, FaceTolerance);
  all["transfer"] = transfer;

  const hoembed::StepperParameters p;
  const hoembed::StepperOptions o;
  nb::dict stepper;
  HOEMBED_DEFAULT(stepper, p, YoungModulus);
  HOEMBED_DEFAULT(stepper, p, PoissonRatio);
  HOEMBED_DEFAULT(stepper, p, Density);
  HOEMBED_DEFAULT(stepper, p, LumpedMass);
  HOEMBED_DEFAULT(stepper, p, TimeStep);
  HOEMBED_DEFAULT(stepper, p, RayleighMass);
  HOEMBED_DEFAULT(stepper, p, RayleighStiffness);
  HOEMBED_DEFAULT(stepper, p, SolverTolerance);
  HOEMBED_DEFAULT(stepper, p, MaxSolverIterations);
  HOEMBED_DEFAULT(stepper, p, UseClampPlane);
  HOEMBED_DEFAULT_VECTOR3(stepper, p, ClampPlaneOrigin);
  HOEMBED_DEFAULT_VECTOR3(stepper, p, ClampPlaneNormal);
  HOEMBED_DEFAULT(stepper, p, UseClampBox);
  HOEMBED_DEFAULT(stepper, p, Material);
  HOEMBED_DEFAULT(stepper, p, MooneyRivlinC10);
  HOEMBED_DEFAULT(stepper, p, MooneyRivlinC01);
  HOEMBED_DEFAULT(stepper, p, NewtonTolerance);
  HOEMBED_DEFAULT(stepper, p, MaxNewtonIterations);
  stepper["ClampBox"] = nb::make_tuple(
    p.ClampBox[0], p.ClampBox[1], p.ClampBox[2], p.ClampBox[3], p.ClampBox[4], p.ClampBox[5]);
  HOEMBED_DEFAULT_VECTOR3(stepper, o, Gravity);
  HOEMBED_DEFAULT(stepper, o, NumberOfTimeSteps);
  HOEMBED_DEFAULT(stepper, o, StaticSolve);
  HOEMBED_DEFAULT(stepper, o, PrescribedSpeedLimit);
  HOEMBED_DEFAULT(stepper, o, LiveMode);
  HOEMBED_DEFAULT(stepper, o, ComputeDiagnostics);
  HOEMBED_DEFAULT(stepper, o, BackgroundFactorization);
  HOEMBED_DEFAULT(stepper, o, FactorizationLag);
  stepper["FixedArrayName"] = hoembed::ArrayNames::Fixed;
  all["stepper"] = stepper;
  return all;
}
#undef HOEMBED_DEFAULT
#undef HOEMBED_DEFAULT_ENUM
#undef HOEMBED_DEFAULT_VECTOR3

std::string Error(const std::string& where, const std::string& error)
{
  return error.empty() ? error : where + error;
}
} // namespace

NB_MODULE(_hoembed, m)
{
  m.doc() = "HOEmbed's VTK-free drivers (embedding, deformation transfer) for the pip package";
  BindMesher(m);

  nb::class_<hoembed::EmbeddingDriver>(m, "EmbeddingDriver")
    .def(nb::init<>())
    .def(
      "set_surface",
      [](hoembed::EmbeddingDriver& d, const In& points, const In& polyOffsets, const In& polyConn,
        const In& stripOffsets, const In& stripConn) {
        const std::int64_t n = static_cast<std::int64_t>(points.size() / 3);
        const double* pd = Is<double>(points) ? Data<double>(points, "points", 3 * n) : nullptr;
        const float* pf = pd ? nullptr : Data<float>(points, "points", 3 * n);
        Check(
          d.SetSurface(pd, pf, n, Cells(polyOffsets, polyConn), Cells(stripOffsets, stripConn)));
      },
      nb::arg("points"), nb::arg("poly_offsets"), nb::arg("poly_connectivity"),
      nb::arg("strip_offsets"), nb::arg("strip_connectivity"))
    .def(
      "prepare_and_order",
      [](hoembed::EmbeddingDriver& d, std::int64_t numberOfPoints, const In& points,
        const In& types, const In& offsets, const In& conn, bool validate, int partitions,
        const nb::object& degrees) {
        hoembed::TetMeshArrays mesh = Mesh(numberOfPoints, &points, types, offsets, conn);
        In keepDegrees;
        mesh.HigherOrderDegrees = Optional(degrees, keepDegrees, "higher_order_degrees",
          3 * static_cast<std::size_t>(mesh.NumberOfCells));
        std::string error;
        {
          nb::gil_scoped_release release;
          error = d.PrepareAndOrder(&mesh, validate, partitions);
        }
        Check(error);
      },
      nb::arg("number_of_points"), nb::arg("points"), nb::arg("cell_types"),
      nb::arg("cell_offsets"), nb::arg("cell_connectivity"), nb::arg("validate"),
      nb::arg("partitions"), nb::arg("higher_order_degrees") = nb::none())
    .def(
      "embed",
      [](hoembed::EmbeddingDriver& d, int method, nb::object progress) {
        // progress comes from the calling thread only (hoembed::FloodSurface)
        std::function<void(double)> report;
        if (!progress.is_none())
          report = [&progress](double x) {
            nb::gil_scoped_acquire acquire;
            progress(x);
          };
        nb::gil_scoped_release release;
        d.Embed(method, report);
      },
      nb::arg("method"), nb::arg("progress").none())
    .def("write_arrays",
      [](const hoembed::EmbeddingDriver& d, Array cellId, Array pcoords, Array distance,
        Array residual, Array closest, Array face, Array iterations, Array visited,
        Array fallback) {
        const std::size_t n = static_cast<std::size_t>(d.GetNumberOfPoints());
        hoembed::EmbeddingOutputArrays out;
        out.CellId = Out<std::int64_t>(cellId, "cell ids", n);
        out.ParametricCoords = Out<double>(pcoords, "parametric coordinates", 3 * n);
        out.Distance = Out<double>(distance, "distances", n);
        out.Residual = Out<double>(residual, "residuals", n);
        out.ClosestDistance = Out<double>(closest, "closest distances", n);
        out.Face = Out<std::int8_t>(face, "faces", n);
        out.Iterations = Out<std::int32_t>(iterations, "iterations", n);
        out.Visited = Out<std::int32_t>(visited, "visited", n);
        out.Fallback = Out<std::uint8_t>(fallback, "fallback", n);
        hoembed::EmbeddingSummary s;
        Check(d.WriteArrays(out, s));
        // the counts and the driver's warning sentences
        return nb::make_tuple(s.Uncertified, s.Fallbacks, hoembed::EmbeddingWarnings(s));
      })
    .def("write_fallback_offsets",
      [](const hoembed::EmbeddingDriver& d, Array out) {
        d.WriteFallbackOffsets(Out<double>(
          out, "fallback offsets", 3 * static_cast<std::size_t>(d.GetNumberOfPoints())));
      })
    .def_prop_ro("fingerprint", &hoembed::EmbeddingDriver::GetFingerprint);

  nb::class_<Transfer>(m, "TransferDriver")
    .def(nb::init<>())
    .def(
      "set_mesh_topology",
      [](Transfer& t, std::int64_t numberOfPoints, const In& types, const In& offsets,
        const In& conn, const nb::object& degrees) {
        bool rebuilt = false;
        hoembed::TetMeshArrays mesh = Mesh(numberOfPoints, nullptr, types, offsets, conn);
        In keepDegrees;
        mesh.HigherOrderDegrees = Optional(degrees, keepDegrees, "higher_order_degrees",
          3 * static_cast<std::size_t>(mesh.NumberOfCells));
        Check(t.Driver.SetMeshTopology(mesh, rebuilt));
      },
      nb::arg("number_of_points"), nb::arg("cell_types"), nb::arg("cell_offsets"),
      nb::arg("cell_connectivity"), nb::arg("higher_order_degrees") = nb::none())
    .def_prop_ro("fingerprint", [](const Transfer& t) { return t.Driver.GetFingerprint(); })
    .def_static(
      "check_mesh_size",
      [](std::int64_t numberOfPoints, std::int64_t numberOfCells, bool hasCells) {
        Check(hoembed::TransferDriver::CheckMeshSize(numberOfPoints, numberOfCells, hasCells));
      },
      nb::arg("number_of_points"), nb::arg("number_of_cells"), nb::arg("has_cells"))
    .def(
      "check_surface",
      [](const Transfer& t, std::int64_t numberOfVertices, nb::object method,
        nb::object fingerprint, nb::object cellIds, nb::object pcoords, nb::object distances,
        nb::object faces, nb::object fallback) {
        // strings: None when absent; arrays: (components, tuples) or None when absent
        hoembed::TransferSurfaceInfo info;
        info.NumberOfVertices = numberOfVertices;
        std::string m, f;
        if (!method.is_none())
          info.Method = (m = nb::cast<std::string>(method)).c_str();
        if (!fingerprint.is_none())
          info.Fingerprint = (f = nb::cast<std::string>(fingerprint)).c_str();
        info.CellIds = Shape(cellIds);
        info.ParametricCoords = Shape(pcoords);
        info.Distances = Shape(distances);
        info.Faces = Shape(faces);
        info.FallbackOffsets = Shape(fallback);
        hoembed::EmbeddingMethod em;
        hoembed::TransferArraysUsed used;
        Check(t.Driver.CheckSurface(info, em, used));
        return nb::make_tuple(used.Distances, used.Faces, used.FallbackOffsets);
      },
      nb::arg("number_of_vertices"), nb::arg("method").none(), nb::arg("fingerprint").none(),
      nb::arg("cell_ids").none(), nb::arg("pcoords").none(), nb::arg("distances").none(),
      nb::arg("faces").none(), nb::arg("fallback_offsets").none(),
      "The driver's checks of the embedded surface (shapes (components, tuples) or None); "
      "returns which of distances, faces, fallback offsets the plan reads.")
    .def_static(
      "frame_arrays_used",
      [](int normals, std::int64_t numberOfPoints, nb::object displacements, nb::object rotations,
        int pointNormals) {
        bool d = false, r = false;
        hoembed::TransferDriver::FrameArraysUsed(static_cast<hoembed::TransferNormals>(normals),
          static_cast<hoembed::TransferPointNormals>(pointNormals), numberOfPoints,
          Shape(displacements), Shape(rotations), d, r);
        return nb::make_tuple(d, r);
      },
      nb::arg("normals"), nb::arg("number_of_points"), nb::arg("displacements").none(),
      nb::arg("rotations").none(),
      nb::arg("point_normals_mode") = static_cast<int>(hoembed::TransferOptions().PointNormalsMode),
      "Which of Displacement, NodalRotation a frame reads (point_normals_mode: the "
      "TransferPointNormals of a frame that writes point normals, 0 recompute, 1 transform).")
    .def(
      "build_plan",
      [](Transfer& t, const std::string& method, const In& cellIds, const In& pcoords,
        nb::object distances, nb::object faces, nb::object fallback, double faceTolerance,
        double meshLength) {
        hoembed::TransferEmbedding em;
        if (!hoembed::ParseEmbeddingMethod(method.c_str(), em.Method))
          throw std::invalid_argument(
            "build_plan: method '" + method + "' (check_surface judges the surface first)");
        const std::size_t n = cellIds.size();
        em.NumberOfVertices = static_cast<std::int64_t>(n);
        em.CellIds = Data<double>(cellIds, "EmbeddingCellId", n);
        em.ParametricCoords = Data<double>(pcoords, "EmbeddingParametricCoords", 3 * n);
        In a;
        if (!distances.is_none())
          em.Distances = Data<double>(a = nb::cast<In>(distances), "EmbeddingDistance", n);
        In f;
        if (!faces.is_none())
          em.Faces = Data<double>(f = nb::cast<In>(faces), "EmbeddingFace", n);
        In q;
        if (!fallback.is_none())
          em.FallbackOffsets =
            Data<double>(q = nb::cast<In>(fallback), "EmbeddingFallbackOffset", 3 * n);
        std::string error;
        {
          nb::gil_scoped_release release;
          error = t.Driver.BuildPlan(em, faceTolerance, meshLength);
        }
        Check(error);
      },
      nb::arg("method"), nb::arg("cell_ids"), nb::arg("pcoords"), nb::arg("distances").none(),
      nb::arg("faces").none(), nb::arg("fallback_offsets").none(), nb::arg("face_tolerance"),
      nb::arg("mesh_length"))
    .def(
      "evaluate_frame",
      [](Transfer& t, const In& points, int normals, nb::object displacements, nb::object rotations,
        bool countInverted, Array out, nb::object pointNormals, int pointNormalsMode) {
        const std::size_t np = static_cast<std::size_t>(t.Driver.GetNumberOfPoints());
        hoembed::TransferFrame frame;
        frame.Points = Data<double>(points, "deformed mesh points", 3 * np);
        frame.Normals = static_cast<hoembed::TransferNormals>(normals);
        frame.CountInverted = countInverted;
        In d, r;
        if (!displacements.is_none())
          frame.Displacements =
            Data<double>(d = nb::cast<In>(displacements), "Displacement", 3 * np);
        if (!rotations.is_none())
          frame.Rotations = Data<double>(r = nb::cast<In>(rotations), "NodalRotation", 9 * np);
        const std::size_t nv = static_cast<std::size_t>(t.Driver.GetNumberOfVertices());
        double* outDouble =
          IsT<Array, double>(out) ? Out<double>(out, "output points", 3 * nv) : nullptr;
        float* outFloat = outDouble ? nullptr : Out<float>(out, "output points", 3 * nv);
        // point normals in the same pass (the driver's TransferFrame.PointNormals): float32,
        // 3 per vertex; the mode (and its fallback to recompute) is the driver's
        Array pn;
        if (pointNormalsMode != 0 && pointNormalsMode != 1)
          throw std::invalid_argument("evaluate_frame: point_normals_mode must be 0 or 1");
        if (!pointNormals.is_none())
        {
          pn = nb::cast<Array>(pointNormals);
          frame.PointNormals = Out<float>(pn, "point normals", 3 * nv);
          frame.PointNormalsMode = static_cast<hoembed::TransferPointNormals>(pointNormalsMode);
        }
        std::vector<std::string> warnings;
        std::string error;
        {
          nb::gil_scoped_release release;
          error = t.Driver.EvaluateFrame(frame, outDouble, outFloat, warnings);
        }
        Check(error);
        return warnings;
      },
      nb::arg("points"), nb::arg("normals"), nb::arg("displacements").none(),
      nb::arg("rotations").none(), nb::arg("count_inverted"), nb::arg("out"),
      nb::arg("point_normals").none() = nb::none(),
      nb::arg("point_normals_mode") = static_cast<int>(hoembed::TransferOptions().PointNormalsMode),
      "One frame into `out` (and unit point normals into `point_normals`, float32 (n, 3), "
      "when given: set_polygons first, and for mode 1 (transform) set_rest_surface_points). "
      "Returns the driver's warnings.")
    .def_prop_ro("number_of_inverted_cells",
      [](const Transfer& t) { return t.Driver.GetNumberOfInvertedCells(); })
    .def_prop_ro(
      "number_of_folded_normals",
      [](const Transfer& t) { return t.Driver.GetNumberOfFoldedNormals(); },
      "Transform point normals: the vertices of the last frame recomputed where the map folds.")
    .def(
      "set_polygons",
      [](Transfer& t, const In& offsets, const In& conn) { SetPolygons(t, offsets, conn); },
      nb::arg("offsets"), nb::arg("connectivity"),
      "The surface's polygons (VTK offsets/connectivity, int64) for point normals (after "
      "build_plan; forgets the rest surface normals).")
    .def(
      "set_rest_surface_points",
      [](Transfer& t, const In& points) {
        const std::size_t nv = static_cast<std::size_t>(t.Driver.GetNumberOfVertices());
        if (Is<double>(points))
          t.Driver.SetRestSurfacePoints(Data<double>(points, "rest surface points", 3 * nv));
        else
          t.Driver.SetRestSurfacePoints(Data<float>(points, "rest surface points", 3 * nv));
      },
      nb::arg("points"),
      "The surface's rest points (after set_polygons) for transform point normals.")
    .def_prop_ro("has_rest_surface_normals",
      [](const Transfer& t) { return t.Driver.HasRestSurfaceNormals(); })
    .def(
      "compute_vertex_normals",
      [](Transfer& t, const In& points, Array out) {
        const std::size_t nv = static_cast<std::size_t>(t.Driver.GetNumberOfVertices());
        float* n = Out<float>(out, "normals", 3 * nv);
        if (Is<double>(points))
          t.Driver.ComputeVertexNormals(Data<double>(points, "points", 3 * nv), n);
        else
          t.Driver.ComputeVertexNormals(Data<float>(points, "points", 3 * nv), n);
      },
      nb::arg("points"), nb::arg("out"),
      "Area-weighted unit vertex normals of the polygons given to set_polygons at `points`.")
    .def("vertex_normals",
      [](Transfer& t, const In& offsets, const In& conn, const In& points, Array out) {
        SetPolygons(t, offsets, conn);
        const std::int64_t nv = t.Driver.GetNumberOfVertices();
        float* n = Out<float>(out, "normals", 3 * static_cast<std::size_t>(nv));
        if (Is<double>(points))
          t.Driver.ComputeVertexNormals(Data<double>(points, "points", 3 * nv), n);
        else
          t.Driver.ComputeVertexNormals(Data<float>(points, "points", 3 * nv), n);
      });

  nb::class_<Stepper>(m, "StepperDriver")
    .def(nb::init<>())
    .def(
      "build",
      [](Stepper& st, std::int64_t numberOfPoints, const In& points, const In& types,
        const In& offsets, const In& conn, const std::vector<double>& material, bool lumpedMass,
        bool staticSolve, const std::vector<double>& gravity, const std::vector<double>& clampPlane,
        const std::vector<double>& clampBox, nb::object fixed, nb::object forces, nb::object u0,
        nb::object v0, nb::object prescribedMask, nb::object prescribedTargets,
        double prescribedSpeedLimit, nb::object materialName, nb::object hyperelastic) {
        // material: E, nu, density, dt, Rayleigh mass, Rayleigh stiffness, solver tolerance
        if (material.size() != 7 || gravity.size() != 3 ||
          (!clampPlane.empty() && clampPlane.size() != 6) ||
          (!clampBox.empty() && clampBox.size() != 6))
          throw std::invalid_argument("StepperDriver.build: wrong number of parameters");
        hoembed::StepperParameters& p = st.Parameters;
        p.YoungModulus = material[0];
        p.PoissonRatio = material[1];
        p.Density = material[2];
        p.TimeStep = material[3];
        p.RayleighMass = material[4];
        p.RayleighStiffness = material[5];
        p.SolverTolerance = material[6];
        // the law (None: the driver's defaults): its name, and Mooney-Rivlin's C10, C01,
        // Newton's tolerance and iteration cap
        const hoembed::StepperParameters defaults;
        p.Material = defaults.Material;
        p.MooneyRivlinC10 = defaults.MooneyRivlinC10;
        p.MooneyRivlinC01 = defaults.MooneyRivlinC01;
        p.NewtonTolerance = defaults.NewtonTolerance;
        p.MaxNewtonIterations = defaults.MaxNewtonIterations;
        if (!materialName.is_none())
          Check(
            hoembed::StepperDriver::ParseMaterial(nb::cast<std::string>(materialName), p.Material));
        if (!hyperelastic.is_none())
        {
          const auto h = nb::cast<std::vector<double>>(hyperelastic);
          if (h.size() != 4)
            throw std::invalid_argument("StepperDriver.build: wrong number of parameters");
          p.MooneyRivlinC10 = h[0];
          p.MooneyRivlinC01 = h[1];
          p.NewtonTolerance = h[2];
          // out of int's range: refused by the driver's rule as below 1
          p.MaxNewtonIterations =
            (h[3] >= 1.0 && h[3] <= 2147483647.0) ? static_cast<int>(h[3]) : 0;
        }
        p.LumpedMass = lumpedMass;
        p.UseClampPlane = !clampPlane.empty();
        for (int i = 0; p.UseClampPlane && i < 3; ++i)
        {
          p.ClampPlaneOrigin[i] = clampPlane[i];
          p.ClampPlaneNormal[i] = clampPlane[3 + i];
        }
        p.UseClampBox = !clampBox.empty();
        for (int i = 0; p.UseClampBox && i < 6; ++i)
          p.ClampBox[i] = clampBox[i];
        st.Static = staticSolve;
        const hoembed::TetMeshArrays arrays = Mesh(numberOfPoints, &points, types, offsets, conn);
        const std::size_t n = static_cast<std::size_t>(numberOfPoints);
        In keepFixed, keepForces, keepU, keepV;
        const double* fixedValues = Optional(fixed, keepFixed, "fixed", n);
        const double* f = Optional(forces, keepForces, "external_force", 3 * n);
        const double* u = Optional(u0, keepU, "initial_displacement", 3 * n);
        const double* v = Optional(v0, keepV, "initial_velocity", 3 * n);
        // prescribed motion: a float64 mask (nonzero = prescribed) and its targets
        In keepPM, keepPT;
        const double* pm = Optional(prescribedMask, keepPM, "prescribed mask", n);
        const double* pt = Optional(prescribedTargets, keepPT, "prescribed displacement", 3 * n);
        if (pm && !pt)
          throw std::invalid_argument("StepperDriver.build: prescribed mask without targets");
        for (int i = 0; i < 3; ++i)
          st.Gravity[i] = gravity[i];
        st.SpeedLimit = prescribedSpeedLimit;
        const double* g = st.Gravity;
        st.Built = false;
        std::string error;
        {
          nb::gil_scoped_release release;
          // the filter's BuildSolver: read, then the driver's set-up (the prescribed
          // motion first, as the filter has it from SetPrescribedMotion)
          hoembed::TetMeshInput mesh;
          error = mesh.Read(arrays, hoembed::TetMeshInput::KeepPoints);
          if (!error.empty())
            error += ".";
          if (error.empty())
            error =
              Error("SetPrescribedMotion: ", st.Driver.SetPrescribedMotion(numberOfPoints, pm, pt));
          if (error.empty())
          {
            hoembed::StepperInputs in;
            in.FixedValues = fixedValues;
            in.Forces = f;
            in.InitialDisplacement = u;
            in.InitialVelocity = v;
            for (int i = 0; i < 3; ++i)
              in.Gravity[i] = g[i];
            in.PrescribedSpeedLimit = prescribedSpeedLimit;
            error = st.Driver.Build(mesh, p, in);
          }
          if (error.empty())
          {
            st.NumberOfPoints = mesh.NumberOfPoints;
            st.NumberOfCells = mesh.NumberOfCells;
            st.Built = true;
          }
        }
        Check(error);
      },
      nb::arg("number_of_points"), nb::arg("points"), nb::arg("cell_types"),
      nb::arg("cell_offsets"), nb::arg("cell_connectivity"), nb::arg("material"),
      nb::arg("lumped_mass"), nb::arg("static"), nb::arg("gravity"), nb::arg("clamp_plane"),
      nb::arg("clamp_box"), nb::arg("fixed").none(), nb::arg("external_force").none(),
      nb::arg("initial_displacement").none(), nb::arg("initial_velocity").none(),
      nb::arg("prescribed_mask").none() = nb::none(),
      nb::arg("prescribed_displacement").none() = nb::none(),
      nb::arg("prescribed_speed_limit") = hoembed::StepperOptions().PrescribedSpeedLimit,
      nb::arg("material_name").none() = nb::none(), nb::arg("hyperelastic").none() = nb::none())
    .def(
      "advance",
      [](Stepper& st, long long k) {
        std::string error;
        {
          nb::gil_scoped_release release;
          error = st.Driver.Advance(k, st.Static, st.Parameters.TimeStep, {});
        }
        Check(error);
      },
      nb::arg("step"))
    .def(
      "write_frame",
      [](const Stepper& st, Array points, nb::object displacement, nb::object velocity,
        nb::object rotation, nb::object vonMises) {
        // the arrays the caller wants (None: not computed; the live loop needs the points
        // only, or with rotate/deform normals the displacements and rotations too)
        const std::size_t np = static_cast<std::size_t>(st.NumberOfPoints);
        auto out = [](nb::object o, const char* what, std::size_t count) -> double* {
          if (o.is_none())
            return nullptr;
          Array a = nb::cast<Array>(o);
          return Out<double>(a, what, count);
        };
        const hoembed::CorotationalSolver& s = st.Driver.Solver;
        st.Driver.WriteFrame(Out<double>(points, "points", 3 * np),
          out(displacement, "Displacement", 3 * np), out(velocity, "Velocity", 3 * np),
          out(rotation, "NodalRotation", 9 * np),
          out(vonMises, "VonMisesStress", static_cast<std::size_t>(st.NumberOfCells)));
        if (vonMises.is_none())
          return nb::make_tuple(nb::none(), nb::none(), s.GetLastIterations());
        return nb::make_tuple(s.KineticEnergy(), s.StrainEnergy(), s.GetLastIterations());
      },
      nb::arg("points"), nb::arg("displacement").none() = nb::none(),
      nb::arg("velocity").none() = nb::none(), nb::arg("rotation").none() = nb::none(),
      nb::arg("von_mises").none() = nb::none())
    .def_static(
      "check_fixed_array",
      [](const std::string& name, const std::string& kind, long long tuples,
        long long numberOfPoints) {
        using Kind = hoembed::StepperDriver::FixedArrayKind;
        Kind k = Kind::Absent;
        if (kind == "numeric")
          k = Kind::Numeric;
        else if (kind == "not numeric")
          k = Kind::NotNumeric;
        else if (kind == "cell or field")
          k = Kind::CellOrField;
        else if (kind != "absent")
          throw std::invalid_argument("check_fixed_array: kind '" + kind + "'");
        Check(hoembed::StepperDriver::CheckFixedArray(name.c_str(), k, tuples, numberOfPoints));
      },
      nb::arg("name"), nb::arg("kind"), nb::arg("tuples"), nb::arg("number_of_points"),
      "The clamps' array rule (the filter's FixedArrayName): kind is 'absent', 'numeric', "
      "'not numeric' or 'cell or field'; raises the refusal's sentence.")
    // live mode: the driver's clock, loads set between steps, background factorisation
    .def(
      "set_prescribed_motion",
      [](Stepper& st, nb::object mask, nb::object targets) {
        const std::size_t n = static_cast<std::size_t>(st.NumberOfPoints);
        In keepM, keepT;
        const double* m = Optional(mask, keepM, "prescribed mask", n);
        const double* t = Optional(targets, keepT, "prescribed displacement", 3 * n);
        if (m && !t)
          throw std::invalid_argument("set_prescribed_motion: a mask without targets");
        Check(
          Error("SetPrescribedMotion: ", st.Driver.SetPrescribedMotion(st.NumberOfPoints, m, t)));
      },
      nb::arg("mask").none(), nb::arg("targets").none())
    .def_prop_rw(
      "prescribed_speed_limit", [](const Stepper& st) { return st.SpeedLimit; },
      [](Stepper& st, double v) {
        if (!(v >= 0.0) || !std::isfinite(v))
          throw std::invalid_argument("prescribed_speed_limit must be finite and >= 0");
        st.SpeedLimit = v;
      })
    .def(
      "set_background_factorization",
      [](Stepper& st, bool on, int lag) { st.Driver.Solver.SetBackgroundFactorization(on, lag); },
      nb::arg("on"), nb::arg("lag") = hoembed::StepperOptions().FactorizationLag)
    .def("request_steps",
      [](Stepper& st, long long n) {
        if (n < 0)
          throw std::invalid_argument("request_steps: the number of steps must be >= 0");
        st.Driver.RequestSteps(n);
      })
    .def("request_reset", [](Stepper& st) { st.Driver.RequestReset(); })
    .def_prop_ro("clock_step", [](const Stepper& st) { return st.Driver.ClockStep(); })
    .def_prop_ro(
      "timings",
      [](const Stepper& st) {
        // the last advance's (the filter's Last* properties)
        const auto& t = st.Driver.Solver.GetTimings();
        nb::dict d;
        d["steps"] = t.Steps;
        d["rotation"] = t.Rotation;
        d["assembly"] = t.Assembly;
        d["solve"] = t.Solve;
        d["iterations"] = t.Iterations;
        d["factorizations"] = t.Factorizations;
        d["factorization"] = t.Factorization;
        d["background_factorizations"] = t.BackgroundFactorizations;
        return d;
      },
      "Seconds and counts of the last advance: steps, rotation, assembly, solve, "
      "iterations, factorizations, factorization, background_factorizations.")
    .def_prop_ro(
      "traffic",
      [](const Stepper& st) {
        const auto t = st.Driver.Solver.GetTraffic();
        nb::dict d;
        d["product_bytes"] = t.ProductBytes;
        d["preconditioner_bytes"] = t.PreconditionerBytes;
        d["assembly_bytes"] = t.AssemblyBytes;
        d["guess_products"] = t.GuessProducts;
        return d;
      },
      "Bytes a step's CG reads at the least (the solver's Traffic): per product, per "
      "preconditioner application, per assembly; guess_products per step.")
    .def(
      "advance_live",
      [](Stepper& st) {
        // the filter's LiveMode update: pending reset, loads, then the pending steps
        std::string error;
        {
          nb::gil_scoped_release release;
          long long target = 0;
          error = st.Driver.PrepareLiveStep(
            st.Gravity, st.SpeedLimit, st.NumberOfPoints, false, 0, target);
          if (error.empty())
            error = st.Driver.Advance(target, st.Static, st.Parameters.TimeStep, {});
        }
        Check(error);
      },
      "Apply the loads as they are now and advance by the steps requested since the last "
      "call (after a requested reset, from the initial state).");

  BindSeries(m);

  // the array names of hoembedArrayNames.h (the contract between the stages), by their
  // C++ names
  namespace N = hoembed::ArrayNames;
  nb::dict names;
#define HOEMBED_NAME(x) names[#x] = N::x
  HOEMBED_NAME(MinScaledJacobian);
  HOEMBED_NAME(BoundaryNode);
  HOEMBED_NAME(RelaxedNodeCount);
  HOEMBED_NAME(CurvedNodeCount);
  HOEMBED_NAME(EnvelopeNodeCount);
  HOEMBED_NAME(BoundaryCrossingsFound);
  HOEMBED_NAME(BoundaryCrossingsLeft);
  HOEMBED_NAME(PoorElementCount);
  HOEMBED_NAME(MinScaledJacobianQuantiles);
  HOEMBED_NAME(MaxSurfaceDeviation);
  HOEMBED_NAME(EnvelopeOffset);
  HOEMBED_NAME(Fixed);
  HOEMBED_NAME(Displacement);
  HOEMBED_NAME(Velocity);
  HOEMBED_NAME(NodalRotation);
  HOEMBED_NAME(VonMisesStress);
  HOEMBED_NAME(KineticEnergy);
  HOEMBED_NAME(StrainEnergy);
  HOEMBED_NAME(SolverIterations);
  HOEMBED_NAME(TimeValue);
  HOEMBED_NAME(EmbeddingCellId);
  HOEMBED_NAME(EmbeddingParametricCoords);
  HOEMBED_NAME(EmbeddingDistance);
  HOEMBED_NAME(EmbeddingResidual);
  HOEMBED_NAME(EmbeddingFace);
  HOEMBED_NAME(Normals);
  HOEMBED_NAME(EmbeddingClosestDistance);
  HOEMBED_NAME(EmbeddingIterations);
  HOEMBED_NAME(EmbeddingElementsVisited);
  HOEMBED_NAME(EmbeddingFallback);
  HOEMBED_NAME(EmbeddingFallbackOffset);
  HOEMBED_NAME(EmbeddingPrefix);
  HOEMBED_NAME(EmbeddingMethod);
  HOEMBED_NAME(EmbeddingMeshFingerprint);
  HOEMBED_NAME(NumberOfFallbackPoints);
#undef HOEMBED_NAME
  m.attr("ARRAY_NAMES") = names;
  m.attr("DEFAULTS") = Defaults();
  // the stepper's material names by index (its Material property's enumeration)
  nb::list materials;
  for (const std::string& name : hoembed::StepperDriver::MaterialNames())
  {
    materials.append(name);
  }
  m.attr("MATERIALS") = nb::tuple(materials);
  // The drivers' valid ranges (hoembed::MesherRanges, StepperRanges) and their check, so
  // that the package refuses a bad argument with the driver's sentence before any work.
  nb::dict ranges;
  ranges["mesher"] = Ranges(hoembed::MesherRanges);
  ranges["stepper"] = Ranges(hoembed::StepperRanges);
  ranges["embedding"] = Ranges(hoembed::EmbeddingRanges);
  ranges["transfer"] = Ranges(hoembed::TransferRanges);
  m.attr("RANGES") = ranges;
  m.def(
    "check_range",
    [](const std::string& driver, const std::string& name, double value) {
      using hoembed::FindPropertyRange;
      const hoembed::PropertyRange* r = driver == "mesher"
        ? FindPropertyRange(hoembed::MesherRanges, name)
        : driver == "stepper"   ? FindPropertyRange(hoembed::StepperRanges, name)
        : driver == "embedding" ? FindPropertyRange(hoembed::EmbeddingRanges, name)
        : driver == "transfer"  ? FindPropertyRange(hoembed::TransferRanges, name)
                                : nullptr;
      if (!r)
        throw std::invalid_argument(
          "check_range: the " + driver + " driver has no range of " + name);
      return hoembed::CheckPropertyRange(*r, value);
    },
    "The driver's sentence refusing `value` for its property `name` ('' when valid).");

  m.def(
    "transfer_kernel_simd", [](int mode) { return hoembed::SetTransferKernelSimd(mode); },
    nb::arg("mode") = -1,
    "Which code the transfer's per-vertex kernel runs: 1 its AVX2 copy (where the build has "
    "it and the CPU has AVX2), 0 the plain one, -1 (default) chosen from the CPU; both give "
    "the same bits. Returns whether the AVX2 copy is now used (for tests and timings).");

  m.def(
    "number_of_threads", [] { return hoembed::ParallelThreadCount(); },
    "Threads the kernels' loops use (the wheel: HOEMBED_NUM_THREADS, else the hardware's; "
    "the VTK build: vtkSMPTools' estimate).");
}
