// hoembedTransferDriver alone, on plain arrays (what a binding gives it; no VTK filter in
// the loop), fed by the embedding driver's arrays: a rigid motion of the mesh moves the
// surface rigidly in every normal mode, an affine map moves inside points affinely (both
// known in closed form), the topology and plan caches, inverted cells counted, and its
// checks' sentences (mesh size, surface field data and arrays, plan values, frames).
#include "hoembedDriverTestUtilities.h"
#include "hoembedEmbeddingDriver.h"
#include "hoembedTestUtilities.h"
#include "hoembedTransferDriver.h"

#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace
{
using hoembed_test::MakeBoxTetMesh;
using hoembed_test::PlainTetMesh;
using hoembed_test::SurfacePatch;

// The embedding's arrays as the transfer reads them (doubles), and its fingerprint.
struct Embedded
{
  std::vector<double> CellIds, PCoords, Distances, Faces;
  std::string Fingerprint;
  std::int64_t N = 0;
  hoembed::TransferEmbedding View() const
  {
    hoembed::TransferEmbedding e;
    e.NumberOfVertices = this->N;
    e.CellIds = this->CellIds.data();
    e.ParametricCoords = this->PCoords.data();
    e.Distances = this->Distances.data();
    e.Faces = this->Faces.data();
    return e;
  }
};

Embedded Embed(const PlainTetMesh& mesh, const SurfacePatch& s)
{
  Embedded out;
  hoembed::EmbeddingDriver d;
  const hoembed::TetMeshArrays view = mesh.View();
  std::string e = d.SetSurface(s.Points.data(), nullptr, s.NumberOfPoints(), s.Polygons(), {});
  if (e.empty())
    e = d.PrepareAndOrder(&view, true, 0);
  HOEMBED_CHECK(e.empty(), "embedding failed: %s", e.c_str());
  d.Embed(hoembed::EMBED_NORMAL_OFFSET, {});
  const std::size_t n = static_cast<std::size_t>(s.NumberOfPoints());
  std::vector<std::int64_t> cell(n);
  std::vector<double> residual(n), closest(n), fallback3(3 * n);
  std::vector<signed char> face(n);
  std::vector<int> iterations(n), visited(n);
  std::vector<unsigned char> fallback(n);
  out.N = static_cast<std::int64_t>(n);
  out.PCoords.resize(3 * n);
  out.Distances.resize(n);
  hoembed::EmbeddingOutputArrays a;
  a.CellId = cell.data();
  a.ParametricCoords = out.PCoords.data();
  a.Distance = out.Distances.data();
  a.Residual = residual.data();
  a.ClosestDistance = closest.data();
  a.Face = face.data();
  a.Iterations = iterations.data();
  a.Visited = visited.data();
  a.Fallback = fallback.data();
  hoembed::EmbeddingSummary summary;
  e = d.WriteArrays(a, summary);
  HOEMBED_CHECK(e.empty() && summary.Fallbacks == 0, "embedding arrays: %s", e.c_str());
  out.CellIds.assign(cell.begin(), cell.end());
  out.Faces.assign(face.begin(), face.end());
  out.Fingerprint = d.GetFingerprint();
  return out;
}

hoembed::TransferSurfaceInfo Info(const Embedded& e, const char* method = "normal-offset")
{
  hoembed::TransferSurfaceInfo s;
  s.NumberOfVertices = e.N;
  s.Method = method;
  s.Fingerprint = e.Fingerprint.c_str();
  s.CellIds = { true, 1, e.N };
  s.ParametricCoords = { true, 3, e.N };
  s.Distances = { true, 1, e.N };
  s.Faces = { true, 1, e.N };
  return s;
}

// The driver's steps 1 and 2 as a binding calls them; the first error.
std::string Plan(hoembed::TransferDriver& d, const PlainTetMesh& mesh, const Embedded& e)
{
  std::string error = hoembed::TransferDriver::CheckMeshSize(
    mesh.NumberOfPoints(), static_cast<std::int64_t>(mesh.Types.size()), true);
  bool rebuilt = false;
  hoembed::TetMeshArrays cells = mesh.View();
  cells.PointsDouble = nullptr;
  if (error.empty())
    error = d.SetMeshTopology(cells, rebuilt);
  hoembed::EmbeddingMethod method;
  hoembed::TransferArraysUsed used;
  if (error.empty())
    error = d.CheckSurface(Info(e), method, used);
  if (error.empty())
    error = d.BuildPlan(e.View(), hoembed::TransferOptions().FaceTolerance, std::sqrt(36.0));
  return error;
}

double MaxDistance(const std::vector<double>& a, const std::vector<double>& b)
{
  double worst = 0.0;
  for (std::size_t i = 0; i + 2 < a.size(); i += 3)
    worst = std::max(worst, std::hypot(a[i] - b[i], a[i + 1] - b[i + 1], a[i + 2] - b[i + 2]));
  return worst;
}

// The box [0,4]x[0,4]x[0,2] (tet10) and a surface in and around it.
const PlainTetMesh& Box()
{
  static const PlainTetMesh mesh(MakeBoxTetMesh(4, 4, 2, 4.0, 4.0, 2.0, 2));
  return mesh;
}
SurfacePatch Wavy()
{
  return SurfacePatch(21, 0.4, 3.6, 0.5, 3.5, [](double u, double v, double x[3]) {
    x[0] = u;
    x[1] = v;
    x[2] = 1.7 + 0.8 * std::sin(1.3 * u) * std::cos(1.1 * v); // in and out of the top
  });
}

// x' = R x + t: v' = R v + t for every vertex, in every normal mode (rotate and deform
// read the nodal rotations R and the displacements x' - X).
void TestRigidMotion()
{
  const PlainTetMesh& mesh = Box();
  const SurfacePatch s = Wavy();
  const Embedded e = Embed(mesh, s);
  std::int64_t outside = 0;
  for (double d : e.Distances)
    outside += d != 0.0 ? 1 : 0;
  HOEMBED_CHECK(outside > 50 && outside < e.N - 50, "%lld of %lld vertices outside",
    (long long)outside, (long long)e.N);

  const double a = 0.7, c = std::cos(a), sn = std::sin(a);
  // rotation about the axis (1, 2, 2)/3 (Rodrigues), and a translation
  const double k[3] = { 1.0 / 3, 2.0 / 3, 2.0 / 3 };
  double R[9];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      R[3 * i + j] = (i == j ? c : 0.0) + (1 - c) * k[i] * k[j];
  R[1] -= sn * k[2];
  R[2] += sn * k[1];
  R[3] += sn * k[2];
  R[5] -= sn * k[0];
  R[6] -= sn * k[1];
  R[7] += sn * k[0];
  const double t[3] = { 3.0, -1.0, 0.5 };
  auto move = [&](const double* x, double* y) {
    for (int i = 0; i < 3; ++i)
      y[i] = R[3 * i] * x[0] + R[3 * i + 1] * x[1] + R[3 * i + 2] * x[2] + t[i];
  };
  const std::size_t np = mesh.Points.size() / 3;
  std::vector<double> x(3 * np), u(3 * np), rot(9 * np);
  for (std::size_t p = 0; p < np; ++p)
  {
    move(&mesh.Points[3 * p], &x[3 * p]);
    for (int i = 0; i < 3; ++i)
      u[3 * p + i] = x[3 * p + i] - mesh.Points[3 * p + i];
    std::copy(R, R + 9, &rot[9 * p]);
  }
  std::vector<double> expected(s.Points.size());
  for (std::int64_t i = 0; i < e.N; ++i)
    move(&s.Points[3 * i], &expected[3 * i]);

  hoembed::TransferDriver d;
  const std::string error = Plan(d, mesh, e);
  HOEMBED_CHECK(error.empty(), "plan: %s", error.c_str());
  for (auto mode : { hoembed::TransferNormals::Recompute, hoembed::TransferNormals::Rotate,
         hoembed::TransferNormals::Deform })
  {
    hoembed::TransferFrame f;
    f.Points = x.data();
    f.Normals = mode;
    f.Displacements = u.data();
    f.Rotations = rot.data();
    std::vector<double> out(s.Points.size());
    std::vector<std::string> warnings;
    const std::string frameError = d.EvaluateFrame(f, out.data(), nullptr, warnings);
    const double err = MaxDistance(out, expected);
    HOEMBED_CHECK(frameError.empty() && warnings.empty() && err < 1e-12 * 6.0,
      "rigid motion, mode %d: error %g (%s, %zu warnings)", int(mode), err, frameError.c_str(),
      warnings.size());
  }
}

// x' = A x + b (not rigid): the vertices inside the mesh (d = 0) move to A v + b, the
// isoparametric map of an affinely mapped tet10 being that affine map.
void TestAffineInside()
{
  const PlainTetMesh& mesh = Box();
  const SurfacePatch s(9, 0.3, 3.7, 0.2, 3.8, [](double u, double v, double x[3]) {
    x[0] = u;
    x[1] = v;
    x[2] = 0.3 + 0.3 * u;
  });
  const Embedded e = Embed(mesh, s);
  const double A[9] = { 1.3, 0.2, -0.1, 0.0, 0.8, 0.3, 0.1, -0.2, 1.1 };
  auto map = [&](const double* x, double* y) {
    for (int i = 0; i < 3; ++i)
      y[i] = A[3 * i] * x[0] + A[3 * i + 1] * x[1] + A[3 * i + 2] * x[2] + 0.25 * i;
  };
  std::vector<double> x(mesh.Points.size()), expected(s.Points.size());
  for (std::size_t p = 0; p < x.size() / 3; ++p)
    map(&mesh.Points[3 * p], &x[3 * p]);
  for (std::int64_t i = 0; i < e.N; ++i)
  {
    HOEMBED_CHECK(e.Distances[i] == 0.0, "vertex %lld not inside", (long long)i);
    map(&s.Points[3 * i], &expected[3 * i]);
  }
  hoembed::TransferDriver d;
  HOEMBED_CHECK(Plan(d, mesh, e).empty(), "plan failed");
  hoembed::TransferFrame f;
  f.Points = x.data();
  std::vector<double> out(s.Points.size());
  std::vector<std::string> warnings;
  HOEMBED_CHECK(d.EvaluateFrame(f, out.data(), nullptr, warnings).empty(), "frame failed");
  HOEMBED_CHECK(
    MaxDistance(out, expected) < 1e-12 * 6.0, "affine map: error %g", MaxDistance(out, expected));
}

// The topology is rebuilt only when the cells change; a new topology drops the plan.
// Mirrored points invert every cell: counted, with a warning (unless not asked for).
void TestCachesAndInvertedCells()
{
  const PlainTetMesh& mesh = Box();
  const SurfacePatch s = Wavy();
  const Embedded e = Embed(mesh, s);
  hoembed::TransferDriver d;
  HOEMBED_CHECK(Plan(d, mesh, e).empty() && d.HasPlan(), "plan failed");
  hoembed::TetMeshArrays cells = mesh.View();
  cells.PointsDouble = nullptr;
  bool rebuilt = true;
  HOEMBED_CHECK(d.SetMeshTopology(cells, rebuilt).empty() && !rebuilt && d.HasPlan(),
    "the same cells rebuilt the topology (%d) or dropped the plan", int(rebuilt));
  const PlainTetMesh other(MakeBoxTetMesh(2, 2, 2, 4.0, 4.0, 2.0, 2));
  hoembed::TetMeshArrays otherCells = other.View();
  otherCells.PointsDouble = nullptr;
  HOEMBED_CHECK(d.SetMeshTopology(otherCells, rebuilt).empty() && rebuilt && !d.HasPlan(),
    "other cells: rebuilt %d, plan kept %d", int(rebuilt), int(d.HasPlan()));
  std::vector<double> out(s.Points.size());
  std::vector<std::string> warnings;
  hoembed::TransferFrame f;
  f.Points = other.Points.data();
  std::string error = d.EvaluateFrame(f, out.data(), nullptr, warnings);
  HOEMBED_CHECK(
    error == "no transfer plan for this mesh (BuildPlan first)", "got '%s'", error.c_str());

  HOEMBED_CHECK(Plan(d, mesh, e).empty(), "plan failed");
  std::vector<double> mirrored(mesh.Points);
  for (std::size_t i = 0; i < mirrored.size(); i += 3)
    mirrored[i] = -mirrored[i];
  f.Points = mirrored.data();
  error = d.EvaluateFrame(f, out.data(), nullptr, warnings);
  const std::int64_t cellsCount = static_cast<std::int64_t>(mesh.Types.size());
  HOEMBED_CHECK(error.empty() && d.GetNumberOfInvertedCells() == cellsCount &&
      warnings.size() >= 1 && warnings[0].find("inverted") != std::string::npos,
    "mirrored: %lld of %lld inverted, %zu warnings ('%s')", (long long)d.GetNumberOfInvertedCells(),
    (long long)cellsCount, warnings.size(), error.c_str());
  f.CountInverted = false;
  warnings.clear();
  error = d.EvaluateFrame(f, out.data(), nullptr, warnings);
  HOEMBED_CHECK(error.empty() && d.GetNumberOfInvertedCells() == 0, "not counted: %lld",
    (long long)d.GetNumberOfInvertedCells());
}

void TestErrors()
{
  const PlainTetMesh& mesh = Box();
  const SurfacePatch s = Wavy();
  const Embedded e = Embed(mesh, s);
  std::string error = hoembed::TransferDriver::CheckMeshSize(3, 1, true);
  HOEMBED_CHECK(error == "the deformed FE mesh (port 1) is empty", "got '%s'", error.c_str());

  hoembed::TransferDriver d;
  HOEMBED_CHECK(Plan(d, mesh, e).empty(), "plan failed");
  hoembed::EmbeddingMethod method;
  hoembed::TransferArraysUsed used;
  hoembed::TransferSurfaceInfo info = Info(e);
  info.Method = nullptr;
  error = d.CheckSurface(info, method, used);
  HOEMBED_CHECK(error ==
      "the surface (port 0) has no field data EmbeddingMethod: is it the "
      "output of vtkEmbeddingCoordinatesFilter?",
    "got '%s'", error.c_str());
  error = d.CheckSurface(Info(e, "closest"), method, used);
  HOEMBED_CHECK(
    error == "unknown EmbeddingMethod 'closest' (expected normal-offset or barycentric)",
    "got '%s'", error.c_str());
  info = Info(e);
  info.Fingerprint = "0123";
  error = d.CheckSurface(info, method, used);
  HOEMBED_CHECK(
    error.rfind("the FE mesh (port 1) is not the mesh the surface was embedded in: ", 0) == 0 &&
      error.find("embedding fingerprint 0123") != std::string::npos,
    "got '%s'", error.c_str());
  info = Info(e);
  info.Distances = { true, 1, e.N - 1 };
  info.ParametricCoords = { true, 2, e.N };
  error = d.CheckSurface(info, method, used);
  HOEMBED_CHECK(error ==
      "the surface (port 0) lacks point data arrays, or they do not have one "
      "tuple per point: EmbeddingParametricCoords (3 components) "
      "EmbeddingDistance (1 component)",
    "got '%s'", error.c_str());
  // barycentric: no distances read
  info = Info(e, "barycentric");
  info.Distances = {};
  HOEMBED_CHECK(d.CheckSurface(info, method, used).empty() && !used.Distances &&
      method == hoembed::EmbeddingMethod::Barycentric,
    "barycentric surface refused");

  // plan values: a distance of 1e12 (far beyond any surface the mesh approximates) and a
  // cell id out of range are refused, naming the first bad vertex
  Embedded far = e;
  far.Distances[7] = 1e12;
  error = d.BuildPlan(far.View(), hoembed::TransferOptions().FaceTolerance, 6.0);
  HOEMBED_CHECK(error.rfind("invalid embedding for this mesh: ", 0) == 0 &&
      error.find("(first bad vertex 7)") != std::string::npos,
    "distance 1e12: '%s'", error.c_str());
  Embedded badCell = e;
  badCell.CellIds[5] = static_cast<double>(mesh.Types.size());
  error = d.BuildPlan(badCell.View(), hoembed::TransferOptions().FaceTolerance, 6.0);
  HOEMBED_CHECK(
    error.rfind("invalid embedding for this mesh: 1 vertices with a cell id outside", 0) == 0 &&
      error.find("(first bad vertex 5)") != std::string::npos,
    "cell id out of range: '%s'", error.c_str());

  // a frame with a NaN coordinate
  HOEMBED_CHECK(
    d.BuildPlan(e.View(), hoembed::TransferOptions().FaceTolerance, 6.0).empty(), "plan failed");
  std::vector<double> x(mesh.Points);
  x[3 * 11 + 2] = std::numeric_limits<double>::quiet_NaN();
  hoembed::TransferFrame f;
  f.Points = x.data();
  std::vector<double> out(s.Points.size());
  std::vector<std::string> warnings;
  error = d.EvaluateFrame(f, out.data(), nullptr, warnings);
  HOEMBED_CHECK(error == "the deformed FE mesh has non-finite (NaN or infinite) point coordinates",
    "got '%s'", error.c_str());
}

// The defaults the filter and the package take (hoembed::TransferOptions).
void TestDefaults()
{
  const hoembed::TransferOptions o;
  HOEMBED_CHECK(o.NormalMode == hoembed::TransferNormals::Recompute && !o.ComputePointNormals &&
      o.PointNormalsMode == hoembed::TransferPointNormals::Recompute && o.CheckInvertedElements &&
      o.FaceTolerance == 1e-6,
    "defaults changed");
}
} // namespace

int main(int, char*[])
{
  TestDefaults();
  TestRigidMotion();
  TestAffineInside();
  TestCachesAndInvertedCells();
  TestErrors();
  return hoembed_test::Report("TestTransferDriver");
}
