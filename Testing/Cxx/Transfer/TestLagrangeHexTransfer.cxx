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
#include "hoembedTransferFramesTestUtilities.h"

#include "vtkLagrangeHexahedron.h"
#include "vtkQuadraticHexahedron.h"
#include "vtkTriQuadraticHexahedron.h"

#include <algorithm>
#include <random>

using namespace hoembed_test;

namespace
{
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
  std::mt19937 rng(3 + npc);
  std::uniform_real_distribution<double> u(-0.5, 2.5);
  std::vector<double> points(3 * 120);
  for (double& x : points)
    x = u(rng);
  double lo[3] = { 1e300, 1e300, 1e300 }, hi[3] = { -1e300, -1e300, -1e300 };
  for (std::size_t i = 0; i < hm.Points.size() / 3; ++i)
    for (int d = 0; d < 3; ++d)
      lo[d] = std::min(lo[d], hm.Points[3 * i + d]), hi[d] = std::max(hi[d], hm.Points[3 * i + d]);
  const double diag = std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) +
    (hi[1] - lo[1]) * (hi[1] - lo[1]) + (hi[2] - lo[2]) * (hi[2] - lo[2]));
  vtkSmartPointer<vtkNonLinearCell> cell = VTKCell(type, npc);
  CheckTransferFrames(AsPlainMesh(hm), npc, points, diag, cell,
    "type " + std::to_string(type) + ", " + std::to_string(npc) + " nodes",
    "not implemented for hexahedra:");
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
