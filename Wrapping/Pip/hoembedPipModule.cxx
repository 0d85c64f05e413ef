// hoembed._hoembed: the nanobind binding of the VTK-free drivers for the pip wheel.
//
// The drivers are the ones vtkEmbeddingCoordinatesFilter and vtkDeformationTransferFilter
// call (hoembedEmbeddingDriver.h, hoembedTransferDriver.h); this file only turns numpy
// arrays into the drivers' plain views and back. Output arrays are allocated by the
// Python side (Wrapping/Pip/hoembed) and written in place. Errors: the drivers' sentences
// are raised as RuntimeError; the Python side turns them into hoembed.HOEmbedError.
#include "hoembedEmbeddingDriver.h"
#include "hoembedParallel.h"
#include "hoembedTransferDriver.h"

#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/vector.h>

#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace nb = nanobind;

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
hoembed::TetMeshArrays Mesh(std::int64_t numberOfPoints, const In* points,
  const In& types, const In& offsets, const In& conn)
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
void PoolFor(std::int64_t n, std::int64_t grain,
  const std::function<void(std::int64_t, std::int64_t)>& body)
{
  hoembed::ParallelLoop(std::int64_t(0), n, grain, body);
}

struct Transfer
{
  hoembed::TransferDriver Driver{ PoolFor };
};
} // namespace

NB_MODULE(_hoembed, m)
{
  m.doc() = "HOEmbed's VTK-free drivers (embedding, deformation transfer) for the pip package";

  nb::class_<hoembed::EmbeddingDriver>(m, "EmbeddingDriver")
    .def(nb::init<>())
    .def(
      "set_surface",
      [](hoembed::EmbeddingDriver& d, const In& points, const In& polyOffsets,
        const In& polyConn, const In& stripOffsets, const In& stripConn) {
        const std::int64_t n = static_cast<std::int64_t>(points.size() / 3);
        const double* pd = Is<double>(points) ? Data<double>(points, "points", 3 * n) : nullptr;
        const float* pf = pd ? nullptr : Data<float>(points, "points", 3 * n);
        Check(d.SetSurface(pd, pf, n, Cells(polyOffsets, polyConn), Cells(stripOffsets, stripConn)));
      },
      nb::arg("points"), nb::arg("poly_offsets"), nb::arg("poly_connectivity"),
      nb::arg("strip_offsets"), nb::arg("strip_connectivity"))
    .def(
      "prepare_and_order",
      [](hoembed::EmbeddingDriver& d, std::int64_t numberOfPoints, const In& points,
        const In& types, const In& offsets, const In& conn, bool validate,
        int partitions) {
        const hoembed::TetMeshArrays mesh = Mesh(numberOfPoints, &points, types, offsets, conn);
        std::string error;
        {
          nb::gil_scoped_release release;
          error = d.PrepareAndOrder(&mesh, validate, partitions);
        }
        Check(error);
      },
      nb::arg("number_of_points"), nb::arg("points"), nb::arg("cell_types"),
      nb::arg("cell_offsets"), nb::arg("cell_connectivity"), nb::arg("validate"),
      nb::arg("partitions"))
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
    .def(
      "write_arrays",
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
        return nb::make_tuple(s.Uncertified, s.FirstUncertified, s.Fallbacks, s.FirstFallback);
      })
    .def("write_fallback_offsets",
      [](const hoembed::EmbeddingDriver& d, Array out) {
        d.WriteFallbackOffsets(
          Out<double>(out, "fallback offsets", 3 * static_cast<std::size_t>(d.GetNumberOfPoints())));
      })
    .def_prop_ro("fingerprint", &hoembed::EmbeddingDriver::GetFingerprint);

  nb::class_<Transfer>(m, "TransferDriver")
    .def(nb::init<>())
    .def(
      "set_mesh_topology",
      [](Transfer& t, std::int64_t numberOfPoints, const In& types, const In& offsets,
        const In& conn) {
        bool rebuilt = false;
        Check(t.Driver.SetMeshTopology(Mesh(numberOfPoints, nullptr, types, offsets, conn), rebuilt));
      })
    .def_prop_ro("fingerprint", [](const Transfer& t) { return t.Driver.GetFingerprint(); })
    .def(
      "build_plan",
      [](Transfer& t, const std::string& method, const In& cellIds, const In& pcoords,
        nb::object distances, nb::object faces, nb::object fallback, double faceTolerance,
        double meshLength) {
        hoembed::TransferEmbedding em;
        if (!hoembed::ParseEmbeddingMethod(method.c_str(), em.Method))
          throw std::runtime_error("unknown EmbeddingMethod '" + method +
            "' (expected normal-offset or barycentric)");
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
      [](Transfer& t, const In& points, int normals, nb::object displacements,
        nb::object rotations, bool countInverted, Array out) {
        const std::size_t np = static_cast<std::size_t>(t.Driver.GetNumberOfPoints());
        hoembed::TransferFrame frame;
        frame.Points = Data<double>(points, "deformed mesh points", 3 * np);
        frame.Normals = static_cast<hoembed::TransferNormals>(normals);
        frame.CountInverted = countInverted;
        In d, r;
        if (!displacements.is_none())
          frame.Displacements = Data<double>(d = nb::cast<In>(displacements), "Displacement", 3 * np);
        if (!rotations.is_none())
          frame.Rotations = Data<double>(r = nb::cast<In>(rotations), "NodalRotation", 9 * np);
        const std::size_t nv = static_cast<std::size_t>(t.Driver.GetNumberOfVertices());
        double* outDouble = IsT<Array, double>(out) ? Out<double>(out, "output points", 3 * nv) : nullptr;
        float* outFloat = outDouble ? nullptr : Out<float>(out, "output points", 3 * nv);
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
      nb::arg("rotations").none(), nb::arg("count_inverted"), nb::arg("out"))
    .def_prop_ro("number_of_inverted_cells",
      [](const Transfer& t) { return t.Driver.GetNumberOfInvertedCells(); })
    .def("vertex_normals",
      [](Transfer& t, const In& offsets, const In& conn, const In& points, Array out) {
        const std::int64_t nv = t.Driver.GetNumberOfVertices();
        const std::int64_t npoly = offsets.size() > 0 ? static_cast<std::int64_t>(offsets.size()) - 1 : 0;
        const std::int64_t zero = 0;
        t.Driver.SetPolygons(npoly > 0 ? Data<std::int64_t>(offsets, "offsets", offsets.size()) : &zero,
          Data<std::int64_t>(conn, "connectivity", conn.size()), npoly, nv);
        float* n = Out<float>(out, "normals", 3 * static_cast<std::size_t>(nv));
        if (Is<double>(points))
          t.Driver.ComputeVertexNormals(Data<double>(points, "points", 3 * nv), n);
        else
          t.Driver.ComputeVertexNormals(Data<float>(points, "points", 3 * nv), n);
      });

  m.def("number_of_threads", [] { return hoembed::parallel_detail::NumberOfThreads(); },
    "Threads the kernels' loops use (HOEMBED_NUM_THREADS, else the hardware's).");
}
