// hoembed::TetMeshInput, the one reader of the FE mesh: against vtkUnstructuredGrid's own
// accessors (connectivity, cell sizes), hoembed::MeshFingerprint fed cell by cell through
// vtkIdList (the reference the embedding and the transfer used before), and every error
// the reader must give (empty, other or mixed types, wrong sizes, node ids out of range,
// non-finite coordinates, ghost cells) for 32- and 64-bit cell storage and float and
// double points.
#include "hoembedMeshFingerprint.h"
#include "hoembedTestUtilities.h"
#include "hoembedTetMeshInputVTK.h"

#include "vtkCellArray.h"
#include "vtkCellType.h"
#include "vtkDataSetAttributes.h"
#include "vtkIdList.h"
#include "vtkNew.h"
#include "vtkPoints.h"
#include "vtkSmartPointer.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnstructuredGrid.h"

#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace
{
using hoembed_test::MakeBoxTetMesh;

std::string Read(vtkUnstructuredGrid* g, hoembed::TetMeshInput& in, bool points = true)
{
  std::vector<double> scratch;
  return in.Read(hoembed::ViewTetMesh(g, points, scratch),
    hoembed::TetMeshInput::KeepPoints * points | hoembed::TetMeshInput::KeepFingerprint);
}

bool Has(const std::string& s, const char* what)
{
  return s.find(what) != std::string::npos;
}

void TestValid(int order, bool use32, int pointType)
{
  auto g = MakeBoxTetMesh(3, 2, 2, 3.0, 1.0, 1.0, order);
  if (use32)
  {
    g->GetCells()->ConvertTo32BitStorage();
  }
  if (pointType != VTK_DOUBLE)
  {
    vtkNew<vtkPoints> p;
    p->SetDataType(pointType);
    p->DeepCopy(g->GetPoints());
    vtkNew<vtkPoints> q;
    q->SetDataType(pointType);
    q->SetNumberOfPoints(g->GetNumberOfPoints());
    for (vtkIdType i = 0; i < g->GetNumberOfPoints(); ++i)
      q->SetPoint(i, g->GetPoint(i));
    g->SetPoints(q);
  }
  hoembed::TetMeshInput in;
  const std::string err = Read(g, in);
  HOEMBED_CHECK(err.empty(), "order %d: valid mesh refused: %s", order, err.c_str());
  const int npc = order == 2 ? 10 : 4;
  HOEMBED_CHECK(
    in.NodesPerCell == npc && in.CellType == g->GetCellType(0), "order %d: type", order);
  HOEMBED_CHECK(
    in.NumberOfCells == g->GetNumberOfCells() && in.NumberOfPoints == g->GetNumberOfPoints(),
    "order %d: sizes", order);
  hoembed::MeshFingerprint ref(g->GetNumberOfPoints(), g->GetNumberOfCells());
  vtkNew<vtkIdList> ids;
  bool same = true;
  for (vtkIdType c = 0; c < g->GetNumberOfCells(); ++c)
  {
    g->GetCellPoints(c, ids);
    std::vector<std::int64_t> v(ids->GetPointer(0), ids->GetPointer(0) + ids->GetNumberOfIds());
    for (int a = 0; a < npc; ++a)
      same = same && in.Connectivity[npc * c + a] == v[a];
    ref.AddCell(g->GetCellType(c), v.data(), static_cast<int>(v.size()));
  }
  HOEMBED_CHECK(same, "order %d: connectivity differs from GetCellPoints", order);
  HOEMBED_CHECK(in.Fingerprint == ref.Hex(), "order %d: fingerprint %s, expected %s", order,
    in.Fingerprint.c_str(), ref.Hex().c_str());
  bool pts = in.Points.size() == 3 * static_cast<size_t>(g->GetNumberOfPoints());
  for (vtkIdType i = 0; pts && i < g->GetNumberOfPoints(); ++i)
  {
    double x[3];
    g->GetPoint(i, x);
    pts = x[0] == in.Points[3 * i] && x[1] == in.Points[3 * i + 1] && x[2] == in.Points[3 * i + 2];
  }
  HOEMBED_CHECK(pts, "order %d: points differ from GetPoint", order);
}

void TestErrors(bool use32)
{
  hoembed::TetMeshInput in;
  {
    vtkNew<vtkUnstructuredGrid> empty;
    HOEMBED_CHECK(Has(Read(empty, in), "empty"), "empty mesh accepted");
  }
  auto base = MakeBoxTetMesh(2, 1, 1, 2.0, 1.0, 1.0, 2);
  auto fresh = [&]() {
    auto g = vtkSmartPointer<vtkUnstructuredGrid>::New();
    g->DeepCopy(base);
    if (use32)
      g->GetCells()->ConvertTo32BitStorage();
    return g;
  };
  {
    auto hex = hoembed_test::MakeUnitHexahedron();
    const std::string e = Read(hex, in);
    HOEMBED_CHECK(
      Has(e, "Unsupported cell type 12") && Has(e, "VTK_TETRA"), "hexahedron: %s", e.c_str());
  }
  {
    auto g = fresh();
    vtkIdType ids[4] = { 0, 1, 2, 3 };
    g->InsertNextCell(VTK_TETRA, 4, ids);
    const std::string e = Read(g, in);
    HOEMBED_CHECK(Has(e, "mixes cell types"), "mixed types: %s", e.c_str());
  }
  for (vtkIdType bad : { vtkIdType(-1), vtkIdType(1) << 40, vtkIdType(0) })
  {
    auto g = fresh();
    const vtkIdType n = g->GetNumberOfPoints();
    const vtkIdType id = bad == 0 ? n : bad; // one past the end, negative, huge
    if (use32 && id > std::numeric_limits<std::int32_t>::max())
      continue;
    vtkNew<vtkIdList> ids;
    g->GetCellPoints(2, ids);
    ids->SetId(7, id);
    g->GetCells()->ReplaceCellAtId(2, ids);
    const std::string e = Read(g, in, false);
    HOEMBED_CHECK(Has(e, "cell 2") && Has(e, "out of range"), "node id %lld: %s",
      static_cast<long long>(id), e.c_str());
  }
  {
    auto g = fresh();
    g->GetPoints()->SetPoint(5, 0.0, std::nan(""), 0.0);
    const std::string e = Read(g, in);
    HOEMBED_CHECK(Has(e, "non-finite") && Has(e, "node 5"), "NaN point: %s", e.c_str());
    g->GetPoints()->SetPoint(5, 0.0, std::numeric_limits<double>::infinity(), 0.0);
    HOEMBED_CHECK(Has(Read(g, in), "non-finite"), "infinite point accepted");
    HOEMBED_CHECK(Read(g, in, false).empty(), "topology-only read looked at the points");
  }
  {
    // Ghost cells (vtkGhostType, as D3 or GhostCellsGenerator mark them): a distributed
    // mesh, refused by every reader; other flags (here exterior) are not ghosts.
    auto g = fresh();
    vtkUnsignedCharArray* ghosts = g->AllocateCellGhostArray();
    ghosts->SetValue(0, vtkDataSetAttributes::EXTERIORCELL);
    HOEMBED_CHECK(
      Read(g, in).empty(), "a mesh without ghost cells refused: %s", Read(g, in).c_str());
    ghosts->SetValue(1, vtkDataSetAttributes::DUPLICATECELL | vtkDataSetAttributes::EXTERIORCELL);
    ghosts->SetValue(3, vtkDataSetAttributes::DUPLICATECELL);
    for (bool points : { true, false })
    {
      const std::string e = Read(g, in, points);
      HOEMBED_CHECK(Has(e, "has 2 ghost cells of") && Has(e, "cell 1") && Has(e, "whole mesh"),
        "ghost cells: %s", e.c_str());
    }
  }
}
} // namespace

int main(int, char*[])
{
  for (int order : { 1, 2 })
    for (bool use32 : { false, true })
      for (int type : { VTK_DOUBLE, VTK_FLOAT, VTK_INT })
        TestValid(order, use32, type);
  TestErrors(false);
  TestErrors(true);
  return hoembed_test::Report("TestTetMeshInput");
}
