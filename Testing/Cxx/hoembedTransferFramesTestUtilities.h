// The any-order transfer tests' shared check (TestLagrangeTransfer: tetrahedra,
// TestLagrangeHexTransfer: hexahedra): points embedded by the embedding driver, their
// arrays handed to the transfer driver as a binding would, then the rest frame rebuilds
// the points, a rigid motion of the mesh moves them rigidly, and a smooth non-rigid
// deformation moves the inside points exactly as VTK's own cell interpolates the deformed
// cell (EvaluateLocation).
#ifndef hoembedTransferFramesTestUtilities_h
#define hoembedTransferFramesTestUtilities_h

#include "hoembedDriverTestUtilities.h"
#include "hoembedEmbeddingDriver.h"
#include "hoembedTestUtilities.h"
#include "hoembedTransferDriver.h"

#include "vtkIdList.h"
#include "vtkNonLinearCell.h"
#include "vtkPoints.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace hoembed_test
{
/// The embedding driver's arrays for a set of points, as a binding hands them on.
struct Embedded
{
  std::vector<double> Cell, PC, Distance, Face, Offset, Residual;
  std::vector<unsigned char> Fallback;
};

/// Embeds `points` (normal-offset) in `mesh`; returns the driver's error ("" on success).
inline std::string EmbedPoints(
  const PlainTetMesh& mesh, const std::vector<double>& points, Embedded& r)
{
  hoembed::EmbeddingDriver d;
  const std::int64_t n = static_cast<std::int64_t>(points.size() / 3);
  std::string e = d.SetSurface(points.data(), nullptr, n, {}, {});
  const hoembed::TetMeshArrays view = mesh.View();
  if (e.empty())
    e = d.PrepareAndOrder(&view, true, 0);
  if (!e.empty())
    return e;
  d.Embed(hoembed::EMBED_NORMAL_OFFSET, {});
  std::vector<std::int64_t> cell(n);
  std::vector<signed char> face(n);
  std::vector<int> its(n), vis(n);
  std::vector<double> closest(n);
  r.PC.resize(3 * n);
  r.Distance.resize(n);
  r.Residual.resize(n);
  r.Fallback.resize(n);
  r.Offset.resize(3 * n);
  hoembed::EmbeddingOutputArrays out;
  out.CellId = cell.data();
  out.ParametricCoords = r.PC.data();
  out.Distance = r.Distance.data();
  out.Residual = r.Residual.data();
  out.ClosestDistance = closest.data();
  out.Face = face.data();
  out.Iterations = its.data();
  out.Visited = vis.data();
  out.Fallback = r.Fallback.data();
  hoembed::EmbeddingSummary summary;
  e = d.WriteArrays(out, summary);
  d.WriteFallbackOffsets(r.Offset.data());
  r.Cell.assign(cell.begin(), cell.end());
  r.Face.assign(face.begin(), face.end());
  return e;
}

/// The frames' checks on `points` in `mesh` (NodesPerCell nodes a cell, `cell` VTK's
/// cell of that type; errors relative to `diag`): rest 1e-10, rigid 1e-9 (with more than
/// 20 points off the mesh), inside points against VTK 1e-12 (more than 5 inside). A "deform" frame
/// warns `deformWarning` (not checked when null). `label` names the case.
inline void CheckTransferFrames(const PlainTetMesh& mesh, int npc,
  const std::vector<double>& points, double diag, vtkNonLinearCell* cell, const std::string& label,
  const char* deformWarning)
{
  const char* name = label.c_str();
  Embedded em;
  std::string e = EmbedPoints(mesh, points, em);
  HOEMBED_CHECK(e.empty(), "%s: %s", name, e.c_str());
  if (!e.empty())
    return;
  const std::int64_t nv = static_cast<std::int64_t>(points.size() / 3);
  hoembed::TransferDriver t;
  bool rebuilt = false;
  e = t.SetMeshTopology(mesh.View(), rebuilt);
  HOEMBED_CHECK(e.empty() && rebuilt, "%s topology: %s", name, e.c_str());
  hoembed::TransferEmbedding te;
  te.NumberOfVertices = nv;
  te.CellIds = em.Cell.data();
  te.ParametricCoords = em.PC.data();
  te.Distances = em.Distance.data();
  te.Faces = em.Face.data();
  te.FallbackOffsets = em.Offset.data();
  e = t.BuildPlan(te, hoembed::TransferOptions().FaceTolerance, diag);
  HOEMBED_CHECK(e.empty(), "%s plan: %s", name, e.c_str());
  std::vector<double> out(3 * nv);
  std::vector<std::string> warnings;
  auto frame = [&](const std::vector<double>& pts) {
    hoembed::TransferFrame f;
    f.Points = pts.data();
    warnings.clear();
    return t.EvaluateFrame(f, out.data(), nullptr, warnings);
  };
  // rest frame
  e = frame(mesh.Points);
  HOEMBED_CHECK(e.empty(), "%s rest frame: %s", name, e.c_str());
  double rest = 0;
  for (std::int64_t i = 0; i < 3 * nv; ++i)
    rest = std::max(rest, std::abs(out[i] - points[i]) / diag);
  // rigid motion
  const double a = 1.1, ca = std::cos(a), sa = std::sin(a);
  const double R[3][3] = { { ca, 0, sa }, { 0, 1, 0 }, { -sa, 0, ca } };
  const double tr[3] = { -2.0, 0.3, 4.0 };
  auto rigid = [&](const double* x, double* y) {
    for (int r = 0; r < 3; ++r)
      y[r] = tr[r] + R[r][0] * x[0] + R[r][1] * x[1] + R[r][2] * x[2];
  };
  std::vector<double> moved(mesh.Points.size());
  for (std::size_t i = 0; i < moved.size() / 3; ++i)
    rigid(&mesh.Points[3 * i], &moved[3 * i]);
  e = frame(moved);
  HOEMBED_CHECK(e.empty() && warnings.empty(), "%s rigid frame: %s", name, e.c_str());
  double worstRigid = 0;
  int offsets = 0;
  for (std::int64_t i = 0; i < nv; ++i)
  {
    double y[3];
    rigid(&points[3 * i], y);
    offsets += em.Distance[i] != 0.0;
    for (int d = 0; d < 3; ++d)
      worstRigid = std::max(worstRigid, std::abs(out[3 * i + d] - y[d]) / diag);
  }
  // a non-rigid deformation: inside points against VTK's cell
  std::vector<double> bent(mesh.Points.size());
  for (std::size_t i = 0; i < bent.size() / 3; ++i)
  {
    const double* x = &mesh.Points[3 * i];
    bent[3 * i] = x[0] + 0.1 * x[2] * x[2];
    bent[3 * i + 1] = x[1] + 0.05 * std::sin(x[0]);
    bent[3 * i + 2] = x[2] - 0.08 * x[0] * x[1];
  }
  e = frame(bent);
  HOEMBED_CHECK(e.empty(), "%s bent frame: %s", name, e.c_str());
  cell->GetPointIds()->SetNumberOfIds(npc);
  cell->GetPoints()->SetNumberOfPoints(npc);
  double worstVTK = 0;
  int inside = 0;
  std::vector<double> w(npc);
  for (std::int64_t i = 0; i < nv; ++i)
  {
    if (em.Distance[i] != 0.0 || em.Fallback[i])
      continue;
    ++inside;
    const std::int64_t c = static_cast<std::int64_t>(em.Cell[i]);
    for (int k = 0; k < npc; ++k)
    {
      cell->GetPointIds()->SetId(k, k);
      cell->GetPoints()->SetPoint(k, &bent[3 * mesh.Connectivity[npc * c + k]]);
    }
    cell->Initialize();
    double x[3];
    int sub = 0;
    cell->EvaluateLocation(sub, &em.PC[3 * i], x, w.data());
    for (int d = 0; d < 3; ++d)
      worstVTK = std::max(worstVTK, std::abs(out[3 * i + d] - x[d]) / diag);
  }
  std::printf("%s: rest %.2e, rigid %.2e (%d offset points), vs VTK's cell %.2e (%d inside "
              "points)\n",
    name, rest, worstRigid, offsets, worstVTK, inside);
  HOEMBED_CHECK(rest <= 1e-10, "%s: rest frame off by %g", name, rest);
  HOEMBED_CHECK(worstRigid <= 1e-9 && offsets > 20, "%s: rigid motion off by %g (%d offset points)",
    name, worstRigid, offsets);
  HOEMBED_CHECK(inside > 5 && worstVTK <= 1e-12, "%s: vs VTK %g", name, worstVTK);
  if (!deformWarning)
    return;
  // a rotation mode falls back to recomputed normals with a warning
  hoembed::TransferFrame f;
  f.Points = moved.data();
  f.Normals = hoembed::TransferNormals::Deform;
  warnings.clear();
  e = t.EvaluateFrame(f, out.data(), nullptr, warnings);
  HOEMBED_CHECK(
    e.empty() && warnings.size() == 1 && warnings[0].find(deformWarning) != std::string::npos,
    "%s: deform mode", name);
}
} // namespace hoembed_test

#endif
