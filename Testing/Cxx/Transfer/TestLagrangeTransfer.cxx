// The transfer on VTK_LAGRANGE_TETRAHEDRON meshes of order 1-4, through both drivers (the
// embedding's arrays handed to the transfer as a binding would): the rest frame rebuilds
// the surface (the residual), a rigid motion of the mesh moves it rigidly (1e-9 of the
// diagonal), and a smooth non-rigid deformation moves the inside points exactly as VTK's
// own vtkLagrangeTetra interpolates the deformed cell (EvaluateLocation).
#include "hoembedEmbeddingDriver.h"
#include "hoembedLagrangeTestUtilities.h"
#include "hoembedTransferDriver.h"

#include "vtkLagrangeTetra.h"

#include <algorithm>
#include <random>

using namespace hoembed_test;

namespace
{
struct Embedded
{
  std::vector<double> Cell, PC, Distance, Face, Offset, Residual;
  std::vector<unsigned char> Fallback;
};

std::string EmbedPoints(const PlainTetMesh& mesh, const std::vector<double>& points, Embedded& r)
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

void TestOrder(int p)
{
  LagrangeBox box =
    MakeLagrangeBox(2, p, [](const double* c, std::int64_t, const double pc[3], double x[3]) {
      StraightPoint(c, pc, x);
      Curve(x);
    });
  const PlainTetMesh mesh = AsPlainMesh(box);
  std::mt19937 rng(3 + p);
  std::uniform_real_distribution<double> u(-0.5, 2.5);
  std::vector<double> points(3 * 150);
  for (double& x : points)
    x = u(rng);
  Embedded em;
  std::string e = EmbedPoints(mesh, points, em);
  HOEMBED_CHECK(e.empty(), "order %d: %s", p, e.c_str());
  if (!e.empty())
    return;
  const std::int64_t nv = static_cast<std::int64_t>(points.size() / 3);
  hoembed::TransferDriver t;
  bool rebuilt = false;
  e = t.SetMeshTopology(mesh.View(), rebuilt);
  HOEMBED_CHECK(e.empty() && rebuilt, "order %d topology: %s", p, e.c_str());
  hoembed::TransferEmbedding te;
  te.NumberOfVertices = nv;
  te.CellIds = em.Cell.data();
  te.ParametricCoords = em.PC.data();
  te.Distances = em.Distance.data();
  te.Faces = em.Face.data();
  te.FallbackOffsets = em.Offset.data();
  const double diag = 2.4 * std::sqrt(3.0);
  e = t.BuildPlan(te, hoembed::TransferOptions().FaceTolerance, diag);
  HOEMBED_CHECK(e.empty(), "order %d plan: %s", p, e.c_str());
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
  HOEMBED_CHECK(e.empty(), "order %d rest frame: %s", p, e.c_str());
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
  HOEMBED_CHECK(e.empty() && warnings.empty(), "order %d rigid frame: %s", p, e.c_str());
  double worstRigid = 0;
  for (std::int64_t i = 0; i < nv; ++i)
  {
    double y[3];
    rigid(&points[3 * i], y);
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
  HOEMBED_CHECK(e.empty(), "order %d bent frame: %s", p, e.c_str());
  const int npc = box.NodesPerCell;
  vtkNew<vtkLagrangeTetra> cell;
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
      cell->GetPoints()->SetPoint(k, &bent[3 * box.Connectivity[npc * c + k]]);
    }
    cell->Initialize();
    double x[3];
    int sub = 0;
    cell->EvaluateLocation(sub, &em.PC[3 * i], x, w.data());
    for (int d = 0; d < 3; ++d)
      worstVTK = std::max(worstVTK, std::abs(out[3 * i + d] - x[d]) / diag);
  }
  std::printf("order %d: rest %.2e, rigid %.2e, vs vtkLagrangeTetra %.2e (%d inside points)\n", p,
    rest, worstRigid, worstVTK, inside);
  HOEMBED_CHECK(rest <= 1e-10, "order %d: rest frame off by %g", p, rest);
  HOEMBED_CHECK(worstRigid <= 1e-9, "order %d: rigid motion off by %g", p, worstRigid);
  HOEMBED_CHECK(inside > 5 && worstVTK <= 1e-12, "order %d: vs VTK %g", p, worstVTK);
  // a rotation mode falls back to recomputed normals with a warning
  hoembed::TransferFrame f;
  f.Points = moved.data();
  f.Normals = hoembed::TransferNormals::Deform;
  warnings.clear();
  e = t.EvaluateFrame(f, out.data(), nullptr, warnings);
  if (p > 2)
    HOEMBED_CHECK(e.empty() && warnings.size() == 1 &&
        warnings[0].find("not implemented for VTK_LAGRANGE_TETRAHEDRON") != std::string::npos,
      "order %d: deform mode", p);
}
} // namespace

int main(int, char*[])
{
  for (int p = 1; p <= 4; ++p)
    TestOrder(p);
  return Report("TestLagrangeTransfer");
}
