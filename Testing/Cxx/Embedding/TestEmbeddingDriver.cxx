// hoembedEmbeddingDriver alone, on plain arrays (what a binding gives it; no VTK filter in
// the loop): its defaults, its results against geometry known in closed form and VTK's
// own tet10 interpolation, the same results for any number of partitions, its warnings
// (the barycentric method outside a curved mesh) and its error sentences.
#include "hoembedDriverTestUtilities.h"
#include "hoembedEmbeddingDriver.h"
#include "hoembedTestUtilities.h"

#include "vtkQuadraticTetra.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

namespace
{
using hoembed_test::MakeBoxTetMesh;
using hoembed_test::PlainTetMesh;
using hoembed_test::SurfacePatch;

struct Results
{
  std::vector<std::int64_t> CellId;
  std::vector<double> PCoords, Distance, Residual, Closest;
  std::vector<signed char> Face;
  std::vector<int> Iterations, Visited;
  std::vector<unsigned char> Fallback;
  hoembed::EmbeddingSummary Summary;
  std::string Error;
};

Results Embed(const PlainTetMesh& mesh, const SurfacePatch& surface, int method, int partitions)
{
  Results r;
  hoembed::EmbeddingDriver d;
  r.Error = d.SetSurface(surface.Points.data(), nullptr, surface.NumberOfPoints(),
    surface.Polygons(), hoembed::CellArrayView());
  const hoembed::TetMeshArrays view = mesh.View();
  if (r.Error.empty())
    r.Error = d.PrepareAndOrder(&view, true, partitions);
  if (!r.Error.empty())
    return r;
  d.Embed(method, {});
  const std::size_t n = static_cast<std::size_t>(surface.NumberOfPoints());
  r.CellId.resize(n);
  r.PCoords.resize(3 * n);
  r.Distance.resize(n);
  r.Residual.resize(n);
  r.Closest.resize(n);
  r.Face.resize(n);
  r.Iterations.resize(n);
  r.Visited.resize(n);
  r.Fallback.resize(n);
  hoembed::EmbeddingOutputArrays out;
  out.CellId = r.CellId.data();
  out.ParametricCoords = r.PCoords.data();
  out.Distance = r.Distance.data();
  out.Residual = r.Residual.data();
  out.ClosestDistance = r.Closest.data();
  out.Face = r.Face.data();
  out.Iterations = r.Iterations.data();
  out.Visited = r.Visited.data();
  out.Fallback = r.Fallback.data();
  r.Error = d.WriteArrays(out, r.Summary);
  return r;
}

// p = sum_i N_i(r, s, t) x_i with VTK's own quadratic tetra functions (not HOEmbed's).
void MapPoint(const PlainTetMesh& mesh, std::int64_t cell, const double* pc, double p[3])
{
  double w[10];
  vtkQuadraticTetra::InterpolationFunctions(pc, w);
  p[0] = p[1] = p[2] = 0.0;
  for (int a = 0; a < 10; ++a)
  {
    const double* x = &mesh.Points[3 * mesh.Connectivity[mesh.Offsets[cell] + a]];
    for (int k = 0; k < 3; ++k)
      p[k] += w[a] * x[k];
  }
}

// The box [0,4]x[0,4]x[0,2] in tet10: a patch above its top face, away from the box's
// edges (the smooth normal there is the face's, (0, 0, 1)), is embedded with its
// vertical projection and the height above the face; a patch inside with d = 0.
void TestKnownGeometry()
{
  const PlainTetMesh mesh(MakeBoxTetMesh(4, 4, 2, 4.0, 4.0, 2.0, 2));
  const double h = 0.15;
  const SurfacePatch above(9, 1.2, 2.8, 1.3, 2.7, [h](double u, double v, double x[3]) {
    x[0] = u;
    x[1] = v;
    x[2] = 2.0 + h * (1.0 + 0.5 * u * v / 8.0); // heights 0.15 .. 0.27, not one value
  });
  Results r = Embed(mesh, above, hoembed::EMBED_NORMAL_OFFSET, 0);
  HOEMBED_CHECK(r.Error.empty(), "embedding failed: %s", r.Error.c_str());
  if (!r.Error.empty())
    return;
  HOEMBED_CHECK(r.Summary.Uncertified == 0 && r.Summary.Fallbacks == 0 && r.Summary.Inexact == 0,
    "%lld uncertified, %lld fallbacks, %lld inexact", (long long)r.Summary.Uncertified,
    (long long)r.Summary.Fallbacks, (long long)r.Summary.Inexact);
  HOEMBED_CHECK(hoembed::EmbeddingWarnings(r.Summary).empty(), "warnings on a clean embedding");
  for (std::int64_t i = 0; i < above.NumberOfPoints(); ++i)
  {
    const double* v = &above.Points[3 * i];
    const double height = v[2] - 2.0;
    double p[3];
    MapPoint(mesh, r.CellId[i], &r.PCoords[3 * i], p);
    HOEMBED_CHECK(std::abs(p[0] - v[0]) < 1e-12 && std::abs(p[1] - v[1]) < 1e-12 &&
        std::abs(p[2] - 2.0) < 1e-12,
      "point %lld: foot (%g %g %g) is not the projection of (%g %g %g)", (long long)i, p[0], p[1],
      p[2], v[0], v[1], v[2]);
    HOEMBED_CHECK(
      std::abs(r.Distance[i] - height) < 1e-12 && std::abs(r.Closest[i] - height) < 1e-12,
      "point %lld: d = %.17g, closest %.17g, height %.17g", (long long)i, r.Distance[i],
      r.Closest[i], height);
    HOEMBED_CHECK(r.Face[i] >= 0 && r.Fallback[i] == 0 && r.Residual[i] < 1e-12,
      "point %lld: face %d, fallback %d, residual %g", (long long)i, r.Face[i], r.Fallback[i],
      r.Residual[i]);
  }

  const SurfacePatch inside(7, 0.3, 3.7, 0.4, 3.6, [](double u, double v, double x[3]) {
    x[0] = u;
    x[1] = v;
    x[2] = 0.7 + 0.1 * u;
  });
  r = Embed(mesh, inside, hoembed::EMBED_NORMAL_OFFSET, 0);
  HOEMBED_CHECK(r.Error.empty(), "embedding failed: %s", r.Error.c_str());
  for (std::int64_t i = 0; r.Error.empty() && i < inside.NumberOfPoints(); ++i)
  {
    const double* v = &inside.Points[3 * i];
    const double* pc = &r.PCoords[3 * i];
    double p[3];
    MapPoint(mesh, r.CellId[i], pc, p);
    const double err = std::hypot(p[0] - v[0], p[1] - v[1], p[2] - v[2]);
    const double tol = 1e-9;
    HOEMBED_CHECK(err < 1e-12 && r.Distance[i] == 0.0 && pc[0] > -tol && pc[1] > -tol &&
        pc[2] > -tol && pc[0] + pc[1] + pc[2] < 1.0 + tol,
      "inside point %lld: |p - v| = %g, d = %g, pc (%g %g %g)", (long long)i, err, r.Distance[i],
      pc[0], pc[1], pc[2]);
  }
}

// The flood's partitions are fixed by the surface; their number changes the walks' start
// points only: the same feet and distances to round-off (a point on a face shared by two
// cells may name either cell).
void TestPartitionsDoNotChangeResults()
{
  const PlainTetMesh mesh(MakeBoxTetMesh(3, 3, 2, 3.0, 3.0, 2.0, 2));
  const SurfacePatch s(25, -0.3, 3.3, -0.2, 3.4, [](double u, double v, double x[3]) {
    x[0] = u;
    x[1] = v;
    x[2] = 1.0 + 1.4 * std::sin(u) * std::cos(v); // in and out of the box
  });
  const Results a = Embed(mesh, s, hoembed::EMBED_NORMAL_OFFSET, 1);
  for (int partitions : { 0, 3, 17 })
  {
    const Results b = Embed(mesh, s, hoembed::EMBED_NORMAL_OFFSET, partitions);
    HOEMBED_CHECK(a.Error.empty() && b.Error.empty(), "embedding failed");
    double worst = 0.0;
    for (std::int64_t i = 0; a.Error.empty() && b.Error.empty() && i < s.NumberOfPoints(); ++i)
    {
      double pa[3], pb[3];
      MapPoint(mesh, a.CellId[i], &a.PCoords[3 * i], pa);
      MapPoint(mesh, b.CellId[i], &b.PCoords[3 * i], pb);
      worst = std::max({ worst, std::hypot(pa[0] - pb[0], pa[1] - pb[1], pa[2] - pb[2]),
        std::abs(a.Distance[i] - b.Distance[i]) });
    }
    HOEMBED_CHECK(
      worst < 1e-12, "%d partitions: feet or distances differ by %g", partitions, worst);
  }
}

// The warnings' rule (what the filter and embed() report): one sentence per kind of
// point that is not certified, not offset, or not reproduced, with the count, the first
// point and, for the barycentric method, why (its extrapolation outside a curved mesh;
// test_embedding.py makes such points on a real curved mesh); none for a clean summary.
void TestWarnings()
{
  hoembed::EmbeddingSummary clean;
  HOEMBED_CHECK(hoembed::EmbeddingWarnings(clean).empty(), "warnings for a clean summary");
  hoembed::EmbeddingSummary s;
  s.Uncertified = 2;
  s.FirstUncertified = 5;
  s.Fallbacks = 1;
  s.FirstFallback = 9;
  s.Inexact = 3;
  s.FirstInexact = 7;
  s.MaxResidual = 0.25;
  s.Method = hoembed::EMBED_BARYCENTRIC;
  const std::vector<std::string> w = hoembed::EmbeddingWarnings(s);
  HOEMBED_CHECK(w.size() == 3, "%zu warnings", w.size());
  if (w.size() == 3)
  {
    HOEMBED_CHECK(w[0].rfind("2 surface point(s) (e.g. point 5): the closest-point search", 0) == 0,
      "'%s'", w[0].c_str());
    HOEMBED_CHECK(w[1].rfind("1 surface point(s) (e.g. point 9) have no normal offset", 0) == 0,
      "'%s'", w[1].c_str());
    HOEMBED_CHECK(w[2].rfind("3 surface point(s) (e.g. point 7) are not reproduced by their "
                             "embedding: EmbeddingResidual up to 0.25 of the mesh's diagonal",
                    0) == 0 &&
        w[2].find("barycentric method extrapolates") != std::string::npos,
      "'%s'", w[2].c_str());
  }
  s.Method = hoembed::EMBED_NORMAL_OFFSET;
  const std::vector<std::string> n = hoembed::EmbeddingWarnings(s);
  HOEMBED_CHECK(
    n.size() == 3 && n[2].find("barycentric") == std::string::npos && n[2].back() == '.',
    "normal-offset inexact warning: '%s'", n.size() == 3 ? n[2].c_str() : "");
}

void TestErrors()
{
  PlainTetMesh mesh(MakeBoxTetMesh(2, 2, 1, 2.0, 2.0, 1.0, 2));
  SurfacePatch s(4, 0.2, 1.8, 0.2, 1.8, [](double u, double v, double x[3]) {
    x[0] = u;
    x[1] = v;
    x[2] = 1.3;
  });
  const int normal = hoembed::EMBED_NORMAL_OFFSET;

  SurfacePatch nan = s;
  nan.Points[3 * 3 + 1] = std::numeric_limits<double>::quiet_NaN();
  std::string e = Embed(mesh, nan, normal, 0).Error;
  HOEMBED_CHECK(e == "The surface has a non-finite (NaN or infinite) coordinate at point 3.",
    "got '%s'", e.c_str());

  SurfacePatch outOfRange = s;
  outOfRange.Connectivity[4] = 99;
  e = Embed(mesh, outOfRange, normal, 0).Error;
  HOEMBED_CHECK(
    e == "A surface polygon refers to point 99, out of range [0, 16).", "got '%s'", e.c_str());

  // cell 2 inverted: two corners swapped (with their mid-edge nodes as they are)
  PlainTetMesh inverted = mesh;
  std::swap(
    inverted.Connectivity[inverted.Offsets[2]], inverted.Connectivity[inverted.Offsets[2] + 1]);
  e = Embed(inverted, s, normal, 0).Error;
  HOEMBED_CHECK(e ==
      "The FE mesh has an inverted or degenerate element: cell 2 has a "
      "non-positive Jacobian determinant somewhere inside it.",
    "got '%s'", e.c_str());
  // the mesh's error before the surface's
  e = Embed(inverted, outOfRange, normal, 0).Error;
  HOEMBED_CHECK(e.find("cell 2") != std::string::npos, "mesh error not first: '%s'", e.c_str());
  // without the validation the inverted cell is not reported
  {
    hoembed::EmbeddingDriver d;
    d.SetSurface(s.Points.data(), nullptr, s.NumberOfPoints(), s.Polygons(), {});
    const hoembed::TetMeshArrays view = inverted.View();
    e = d.PrepareAndOrder(&view, false, 0);
    HOEMBED_CHECK(e.find("inverted") == std::string::npos, "validation off: '%s'", e.c_str());
  }

  // a cell that is not a tetrahedron (VTK_HEXAHEDRON = 12)
  PlainTetMesh hex = mesh;
  hex.Types[1] = 12;
  e = Embed(hex, s, normal, 0).Error;
  HOEMBED_CHECK(e ==
      "the FE mesh mixes cell types: cell 1 has type 12, cell 0 has type 24; "
      "use only VTK_QUADRATIC_TETRA or only VTK_TETRA cells.",
    "non-tet cell: '%s'", e.c_str());
}

// The defaults the filter and the package take (hoembed::EmbeddingOptions): the paper's
// method, automatic partitions, validation and the kept preparation on.
void TestDefaults()
{
  const hoembed::EmbeddingOptions o;
  HOEMBED_CHECK(o.Method == hoembed::EMBED_NORMAL_OFFSET && o.NumberOfPartitions == 0 &&
      o.ValidateElements && o.ReuseMeshPreparation,
    "defaults: method %d, partitions %d, validate %d, reuse %d", o.Method, o.NumberOfPartitions,
    int(o.ValidateElements), int(o.ReuseMeshPreparation));
}
} // namespace

int main(int, char*[])
{
  TestDefaults();
  TestKnownGeometry();
  TestPartitionsDoNotChangeResults();
  TestWarnings();
  TestErrors();
  return hoembed_test::Report("TestEmbeddingDriver");
}
