// The embedding and the transfer on hexahedral meshes (VTK_LAGRANGE_HEXAHEDRON of order
// 1-3, VTK_TRIQUADRATIC_HEXAHEDRON, VTK_QUADRATIC_HEXAHEDRON) through both drivers (the
// embedding's arrays handed to the transfer as a binding would): the rest frame rebuilds
// the surface (the residual), a rigid motion of the mesh moves it rigidly (1e-9 of the
// diagonal), and a smooth non-rigid deformation moves the inside points exactly as VTK's
// own cells interpolate the deformed cell (EvaluateLocation). The drivers' messages: a
// mixed mesh, an unsupported node count, a folded cell.
#include "hoembedEmbeddingDriver.h"
#include "hoembedHexTestUtilities.h"
#include "hoembedTestUtilities.h"
#include "hoembedTransferDriver.h"

#include "vtkLagrangeHexahedron.h"
#include "vtkQuadraticHexahedron.h"
#include "vtkTriQuadraticHexahedron.h"

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

vtkSmartPointer<vtkNonLinearCell> VTKCell(int type, int npc)
{
  if (type == hoembed::QuadraticHexahedronCellType)
    return vtkSmartPointer<vtkQuadraticHexahedron>::New();
  if (type == hoembed::TriQuadraticHexahedronCellType)
    return vtkSmartPointer<vtkTriQuadraticHexahedron>::New();
  auto c = vtkSmartPointer<vtkLagrangeHexahedron>::New();
  c->SetUniformOrderFromNumPoints(npc);
  return c;
}

void TestType(int type, int npc)
{
  const HexMesh hm = MakeMesh(type, npc, 0.15);
  const PlainTetMesh mesh = AsPlainMesh(hm);
  std::mt19937 rng(3 + npc);
  std::uniform_real_distribution<double> u(-0.5, 2.5);
  std::vector<double> points(3 * 120);
  for (double& x : points)
    x = u(rng);
  Embedded em;
  std::string e = EmbedPoints(mesh, points, em);
  HOEMBED_CHECK(e.empty(), "type %d n %d: %s", type, npc, e.c_str());
  if (!e.empty())
    return;
  const std::int64_t nv = static_cast<std::int64_t>(points.size() / 3);
  hoembed::TransferDriver t;
  bool rebuilt = false;
  e = t.SetMeshTopology(mesh.View(), rebuilt);
  HOEMBED_CHECK(e.empty() && rebuilt, "type %d topology: %s", type, e.c_str());
  hoembed::TransferEmbedding te;
  te.NumberOfVertices = nv;
  te.CellIds = em.Cell.data();
  te.ParametricCoords = em.PC.data();
  te.Distances = em.Distance.data();
  te.Faces = em.Face.data();
  te.FallbackOffsets = em.Offset.data();
  double lo[3] = { 1e300, 1e300, 1e300 }, hi[3] = { -1e300, -1e300, -1e300 };
  for (std::size_t i = 0; i < hm.Points.size() / 3; ++i)
    for (int d = 0; d < 3; ++d)
      lo[d] = std::min(lo[d], hm.Points[3 * i + d]), hi[d] = std::max(hi[d], hm.Points[3 * i + d]);
  const double diag = std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) +
    (hi[1] - lo[1]) * (hi[1] - lo[1]) + (hi[2] - lo[2]) * (hi[2] - lo[2]));
  e = t.BuildPlan(te, hoembed::TransferOptions().FaceTolerance, diag);
  HOEMBED_CHECK(e.empty(), "type %d plan: %s", type, e.c_str());
  std::vector<double> out(3 * nv);
  std::vector<std::string> warnings;
  auto frame = [&](const std::vector<double>& pts) {
    hoembed::TransferFrame f;
    f.Points = pts.data();
    warnings.clear();
    return t.EvaluateFrame(f, out.data(), nullptr, warnings);
  };
  e = frame(hm.Points);
  HOEMBED_CHECK(e.empty(), "type %d rest frame: %s", type, e.c_str());
  double rest = 0;
  for (std::int64_t i = 0; i < 3 * nv; ++i)
    rest = std::max(rest, std::abs(out[i] - points[i]) / diag);
  const double a = 1.1, ca = std::cos(a), sa = std::sin(a);
  const double R[3][3] = { { ca, 0, sa }, { 0, 1, 0 }, { -sa, 0, ca } };
  const double tr[3] = { -2.0, 0.3, 4.0 };
  auto rigid = [&](const double* x, double* y) {
    for (int r = 0; r < 3; ++r)
      y[r] = tr[r] + R[r][0] * x[0] + R[r][1] * x[1] + R[r][2] * x[2];
  };
  std::vector<double> moved(hm.Points.size());
  for (std::size_t i = 0; i < moved.size() / 3; ++i)
    rigid(&hm.Points[3 * i], &moved[3 * i]);
  e = frame(moved);
  HOEMBED_CHECK(e.empty() && warnings.empty(), "type %d rigid frame: %s", type, e.c_str());
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
  std::vector<double> bent(hm.Points.size());
  for (std::size_t i = 0; i < bent.size() / 3; ++i)
  {
    const double* x = &hm.Points[3 * i];
    bent[3 * i] = x[0] + 0.1 * x[2] * x[2];
    bent[3 * i + 1] = x[1] + 0.05 * std::sin(x[0]);
    bent[3 * i + 2] = x[2] - 0.08 * x[0] * x[1];
  }
  e = frame(bent);
  HOEMBED_CHECK(e.empty(), "type %d bent frame: %s", type, e.c_str());
  vtkSmartPointer<vtkNonLinearCell> cell = VTKCell(type, npc);
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
      cell->GetPoints()->SetPoint(k, &bent[3 * hm.Conn[npc * c + k]]);
    }
    cell->Initialize();
    double x[3];
    int sub = 0;
    cell->EvaluateLocation(sub, &em.PC[3 * i], x, w.data());
    for (int d = 0; d < 3; ++d)
      worstVTK = std::max(worstVTK, std::abs(out[3 * i + d] - x[d]) / diag);
  }
  std::printf("type %d, %d nodes: rest %.2e, rigid %.2e (%d offset points), vs VTK's cell %.2e "
              "(%d inside points)\n",
    type, npc, rest, worstRigid, offsets, worstVTK, inside);
  HOEMBED_CHECK(rest <= 1e-10, "type %d: rest frame off by %g", type, rest);
  HOEMBED_CHECK(
    worstRigid <= 1e-9 && offsets > 20, "type %d: rigid motion off by %g", type, worstRigid);
  HOEMBED_CHECK(inside > 5 && worstVTK <= 1e-12, "type %d: vs VTK %g", type, worstVTK);
  // a rotation mode falls back to recomputed normals with a warning naming the cells
  hoembed::TransferFrame f;
  f.Points = moved.data();
  f.Normals = hoembed::TransferNormals::Deform;
  warnings.clear();
  e = t.EvaluateFrame(f, out.data(), nullptr, warnings);
  HOEMBED_CHECK(e.empty() && warnings.size() == 1 &&
      warnings[0].find("not implemented for hexahedra:") != std::string::npos,
    "type %d: deform mode", type);
}

std::string PrepareOnly(const PlainTetMesh& mesh, const double* degrees = nullptr)
{
  hoembed::EmbeddingDriver d;
  const double v[3] = { 0, 0, 0 };
  std::string e = d.SetSurface(v, nullptr, 1, {}, {});
  hoembed::TetMeshArrays view = mesh.View();
  view.HigherOrderDegrees = degrees;
  return e.empty() ? d.PrepareAndOrder(&view, true, 0) : e;
}

void TestErrors()
{
  const HexMesh hm = MakeMesh(hoembed::LagrangeHexahedronCellType, 27, 0.1);
  PlainTetMesh mixed = AsPlainMesh(hm);
  mixed.Types[3] = hoembed::TriQuadraticHexahedronCellType;
  std::string e = PrepareOnly(mixed);
  HOEMBED_CHECK(e.find("mixes cell types") != std::string::npos &&
      e.find("one hexahedron type") != std::string::npos,
    "mixed: %s", e.c_str());
  bool rebuilt = false;
  hoembed::TransferDriver t;
  e = t.SetMeshTopology(mixed.View(), rebuilt);
  HOEMBED_CHECK(e.find("mixes cell types") != std::string::npos, "transfer mixed: %s", e.c_str());
  // a Lagrange hexahedron of 12 points (not a uniform order 1-3)
  PlainTetMesh odd = AsPlainMesh(hm);
  odd.Connectivity.resize(12);
  odd.Types.resize(1);
  odd.Offsets = { 0, 12 };
  e = PrepareOnly(odd);
  HOEMBED_CHECK(
    e.find("VTK_LAGRANGE_HEXAHEDRON of 12 points") != std::string::npos, "12: %s", e.c_str());
  // a serendipity cell of 27 points
  PlainTetMesh wrong = AsPlainMesh(hm);
  for (auto& ty : wrong.Types)
    ty = hoembed::QuadraticHexahedronCellType;
  e = PrepareOnly(wrong);
  HOEMBED_CHECK(e.find("VTK_QUADRATIC_HEXAHEDRON of 27 points: it needs 20") != std::string::npos,
    "hex20 of 27: %s", e.c_str());
  // HigherOrderDegrees: (2, 2, 2) is the order the node count gives; (1, 3, 7) has 64 nodes
  // too, so a cubic mesh whose cell 5 says (1, 3, 7) is refused, not read as order 3
  const PlainTetMesh quadratic = AsPlainMesh(hm);
  std::vector<double> degrees(3 * quadratic.Types.size(), 2.0);
  e = PrepareOnly(quadratic, degrees.data());
  HOEMBED_CHECK(e.empty(), "uniform degrees: %s", e.c_str());
  const PlainTetMesh cubic = AsPlainMesh(MakeMesh(hoembed::LagrangeHexahedronCellType, 64, 0.1));
  degrees.assign(3 * cubic.Types.size(), 3.0);
  degrees[15] = 1, degrees[16] = 3, degrees[17] = 7;
  e = PrepareOnly(cubic, degrees.data());
  HOEMBED_CHECK(e.find("cell 5 of the FE mesh is a VTK_LAGRANGE_HEXAHEDRON of orders (1, 3, 7)") !=
      std::string::npos,
    "degrees: %s", e.c_str());
  hoembed::TetMeshArrays cubicView = cubic.View();
  cubicView.HigherOrderDegrees = degrees.data();
  e = t.SetMeshTopology(cubicView, rebuilt);
  HOEMBED_CHECK(
    e.find("HigherOrderDegrees") != std::string::npos, "transfer degrees: %s", e.c_str());
  // a folded cell
  PlainTetMesh folded = AsPlainMesh(hm);
  folded.Points[3 * folded.Connectivity[8] + 1] += 3.0;
  e = PrepareOnly(folded);
  HOEMBED_CHECK(e.find("cell 0 (VTK_LAGRANGE_HEXAHEDRON of order 2)") != std::string::npos,
    "folded: %s", e.c_str());
}
} // namespace

int main(int, char*[])
{
  for (int p = 1; p <= 3; ++p)
    TestType(hoembed::LagrangeHexahedronCellType, (p + 1) * (p + 1) * (p + 1));
  TestType(hoembed::TriQuadraticHexahedronCellType, 27);
  TestType(hoembed::QuadraticHexahedronCellType, 20);
  TestErrors();
  return Report("TestLagrangeHexTransfer");
}
