// hoembedEmbeddingExact: all-vertices exactness check of vtkEmbeddingCoordinatesFilter
// against an independent, certified brute force (hoembedExactDistance.h).
//
//   hoembedEmbeddingExact surface.vtp mesh.vtu [normal-offset|barycentric] [threads]
//
// Runs the filter on the surface and the tet4/tet10 mesh, then, for every surface vertex
// in parallel (vtkSMPTools), the brute-force distance to the mesh (certified interval
// [Lower, Upper] for the boundary distance; 0 when some cell contains the vertex), and
// the reconstruction residual |v - (p + d n)| with p from VTK's own vtkQuadraticTetra /
// vtkTetra interpolation at the output (cell, parametric coordinates) and n the smooth
// normal field (hoembed::InterpolateBoundaryNormal). Prints one JSON object on stdout.
// A benchmark tool: not installed, not a test (Benchmarks/bench_embedding_exact.py runs it).
#include "hoembedExactDistance.h"

#include "hoembedBoundaryNormals.h"
#include "hoembedEmbeddingMesh.h"
#include "hoembedShapeFunctions.h"
#include "vtkEmbeddingCoordinatesFilter.h"

#include "vtkDoubleArray.h"
#include "vtkIdList.h"
#include "vtkIdTypeArray.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkSMPTools.h"
#include "vtkSignedCharArray.h"
#include "vtkUnstructuredGrid.h"
#include "vtkXMLPolyDataReader.h"
#include "vtkXMLUnstructuredGridReader.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <string>
#include <vector>

namespace
{
using hoembed_exact::Id;

struct PerVertex
{
  double Brute = 0, Lower = 0, Upper = 0;
  bool Inside = false, InsideVtk = false;
  int VtkDisagree = 0, DepthLimited = 0;
  bool NodeLimited = false;
  long Nodes = 0;
  long InsideNodes = 0;
  int InsideUndecided = 0;
  int Candidates = 0;
};

double Seconds(std::chrono::steady_clock::time_point t0)
{
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}
} // namespace

int main(int argc, char* argv[])
{
  if (argc < 3)
  {
    std::fprintf(stderr,
      "usage: %s surface.vtp mesh.vtu [normal-offset|barycentric] [threads] [vertex to explain]\n",
      argv[0]);
    return 2;
  }
  const int method = (argc > 3 && std::strcmp(argv[3], "barycentric") == 0) ? 1 : 0;
  const int threads = argc > 4 ? std::atoi(argv[4]) : 0;
  const long explain = argc > 5 ? std::atol(argv[5]) : -1; // a vertex id: print its inside test
  if (threads > 0)
    vtkSMPTools::Initialize(threads);

  vtkNew<vtkXMLPolyDataReader> sr;
  sr->SetFileName(argv[1]);
  sr->Update();
  vtkPolyData* surface = sr->GetOutput();
  vtkNew<vtkXMLUnstructuredGridReader> gr;
  gr->SetFileName(argv[2]);
  gr->Update();
  vtkUnstructuredGrid* grid = gr->GetOutput();
  if (surface->GetNumberOfPoints() == 0 || grid->GetNumberOfCells() == 0)
  {
    std::fprintf(stderr, "empty surface or mesh\n");
    return 1;
  }
  const int npc = grid->GetCellType(0) == VTK_QUADRATIC_TETRA ? 10 : 4;

  // the filter
  vtkNew<vtkEmbeddingCoordinatesFilter> filter;
  filter->SetInputData(0, surface);
  filter->SetMeshData(grid);
  filter->SetMethod(method);
  auto t0 = std::chrono::steady_clock::now();
  const std::clock_t c0 = std::clock();
  filter->Update();
  const double filterWall = Seconds(t0);
  const double filterCpu = double(std::clock() - c0) / CLOCKS_PER_SEC;
  vtkPolyData* out = filter->GetOutput();
  vtkPointData* pd = out->GetPointData();
  auto* closest = vtkDoubleArray::SafeDownCast(pd->GetArray("EmbeddingClosestDistance"));
  auto* cellId = vtkIdTypeArray::SafeDownCast(pd->GetArray("EmbeddingCellId"));
  auto* pcs = vtkDoubleArray::SafeDownCast(pd->GetArray("EmbeddingParametricCoords"));
  auto* dist = vtkDoubleArray::SafeDownCast(pd->GetArray("EmbeddingDistance"));
  auto* res = vtkDoubleArray::SafeDownCast(pd->GetArray("EmbeddingResidual"));
  auto* face = vtkSignedCharArray::SafeDownCast(pd->GetArray("EmbeddingFace"));
  if (!closest || !cellId || !pcs || !dist || !res || !face ||
    out->GetNumberOfPoints() != surface->GetNumberOfPoints())
  {
    std::fprintf(stderr, "filter output incomplete\n");
    return 1;
  }

  // the brute force
  const Id np = grid->GetNumberOfPoints(), nc = grid->GetNumberOfCells();
  std::vector<double> pts(3 * np);
  for (Id i = 0; i < np; ++i)
    grid->GetPoint(i, &pts[3 * i]);
  std::vector<Id> conn;
  conn.reserve(npc * nc);
  vtkNew<vtkIdList> ids;
  for (Id c = 0; c < nc; ++c)
  {
    grid->GetCellPoints(c, ids);
    for (int a = 0; a < npc; ++a)
      conn.push_back(ids->GetId(a));
  }
  hoembed_exact::ExactMesh em;
  const std::string err = em.Build(pts.data(), np, conn.data(), nc, npc);
  if (!err.empty())
  {
    std::fprintf(stderr, "brute-force mesh: %s\n", err.c_str());
    return 1;
  }
  const double diag = em.Diagonal;
  const Id nv = surface->GetNumberOfPoints();
  std::vector<PerVertex> pv(nv);
  hoembed_exact::ExactOptions opt;
  t0 = std::chrono::steady_clock::now();
  vtkSMPTools::For(0, nv, 16, [&](vtkIdType begin, vtkIdType end) {
    hoembed_exact::ExactScratch scratch;
    hoembed_exact::ExactResult r;
    for (vtkIdType i = begin; i < end; ++i)
    {
      double v[3];
      surface->GetPoint(i, v);
      hoembed_exact::ExactDistance(em, v, opt, scratch, r);
      PerVertex& q = pv[i];
      q.Brute = r.Distance();
      q.Lower = r.Lower;
      q.Upper = r.Upper;
      q.Inside = r.Inside;
      q.InsideVtk = r.InsideVtk;
      q.VtkDisagree = r.VtkDisagreements;
      q.DepthLimited = r.DepthLimited;
      q.NodeLimited = r.NodeLimited;
      q.Nodes = r.Nodes;
      q.InsideNodes = r.InsideNodes;
      q.InsideUndecided = r.InsideUndecided;
      q.Candidates = r.CandidateCells;
    }
  });
  const double bruteWall = Seconds(t0);
  if (explain >= 0 && explain < nv)
  {
    double v[3];
    surface->GetPoint(explain, v);
    std::fprintf(stderr,
      "vertex %ld at %.17g %.17g %.17g: filter distance %.17g cell %lld face %d\n", explain, v[0],
      v[1], v[2], closest->GetValue(explain), static_cast<long long>(cellId->GetValue(explain)),
      int(face->GetValue(explain)));
    hoembed_exact::ExplainInside(em, v);
  }

  // residual with VTK's own cell interpolation and the smooth normal field
  hoembed::EmbeddingMesh hm;
  const std::string herr = hm.Build(pts.data(), np, conn.data(), nc, npc);
  if (!herr.empty())
  {
    std::fprintf(stderr, "normal field: %s\n", herr.c_str());
    return 1;
  }
  std::vector<double> residual(nv, 0.0);
  vtkSMPTools::For(0, nv, 256, [&](vtkIdType begin, vtkIdType end) {
    vtkNew<vtkQuadraticTetra> qt;
    vtkNew<vtkTetra> t4;
    vtkCell* cell = npc == 10 ? static_cast<vtkCell*>(qt) : static_cast<vtkCell*>(t4);
    for (vtkIdType i = begin; i < end; ++i)
    {
      const Id c = cellId->GetValue(i);
      for (int a = 0; a < npc; ++a)
      {
        cell->GetPoints()->SetPoint(a, &pts[3 * conn[npc * c + a]]);
        cell->GetPointIds()->SetId(a, a);
      }
      double r[3], p[3], w[10], v[3], n[3] = { 0, 0, 0 };
      pcs->GetTypedTuple(i, r);
      int sub;
      cell->EvaluateLocation(sub, r, p, w);
      const int fc = face->GetValue(i);
      if (fc >= 0)
      {
        const Id bf = hm.Topology.CellBoundaryFace[4 * c + fc];
        const double L[4] = { 1 - r[0] - r[1] - r[2], r[0], r[1], r[2] };
        const double uv[2] = { L[hoembed::TetFaceNodes[fc][1]], L[hoembed::TetFaceNodes[fc][2]] };
        if (bf >= 0)
          hoembed::InterpolateBoundaryNormal(hm.Topology, hm.NodalNormals.data(), bf, uv, n);
        else
          n[0] = n[1] = n[2] = std::nan(""); // p claimed on an interior face
      }
      surface->GetPoint(i, v);
      const double d = dist->GetValue(i);
      double s = 0.0;
      for (int k = 0; k < 3; ++k)
        s += (v[k] - p[k] - d * n[k]) * (v[k] - p[k] - d * n[k]);
      residual[i] = std::sqrt(s);
    }
  });

  // statistics
  long above8 = 0, above10 = 0, above12 = 0, outsideCert = 0, insideMismatch = 0,
       insideMismatchMaterial = 0, bruteInside = 0, filterInside = 0, vtkDis = 0, depthLim = 0,
       nodeLim = 0, belowLower = 0, vtkVertexDis = 0, vtkOnlyInside = 0, res10 = 0, resReported = 0,
       nanCount = 0;
  double maxErr = 0.0, maxRes = 0.0, maxCert = 0.0, maxResDiff = 0.0;
  long totalNodes = 0, maxNodes = 0, insideUndecided = 0, maxInsideNodes = 0;
  std::vector<std::pair<double, Id>> worst;
  std::vector<Id> vtkVerdict; // vertices where VTK's inside verdict differs
  for (Id i = 0; i < nv; ++i)
  {
    const PerVertex& q = pv[i];
    const double df = closest->GetValue(i);
    const double e = std::fabs(df - q.Brute) / diag;
    if (!std::isfinite(df) || !std::isfinite(residual[i]))
      ++nanCount;
    maxErr = std::max(maxErr, std::isfinite(e) ? e : 1e300);
    above8 += !(e <= 1e-8);
    above10 += !(e <= 1e-10);
    above12 += !(e <= 1e-12);
    worst.emplace_back(std::isfinite(e) ? e : 1e300, i);
    // outside the certified interval (when the vertex is outside)
    if (!q.Inside && (df < q.Lower - 1e-8 * diag || df > q.Upper + 1e-8 * diag))
      ++outsideCert;
    // nearer than the certified lower bound: impossible for a point on the mesh
    if (!q.Inside && df > 0.0 && df < q.Lower - 1e-12 * diag)
      ++belowLower;
    maxCert = std::max(maxCert, (q.Upper - q.Lower) / diag);
    const bool fIn = df == 0.0;
    bruteInside += q.Inside;
    filterInside += fIn;
    if (fIn != q.Inside)
    {
      ++insideMismatch;
      if (q.Upper > 1e-8 * diag)
        ++insideMismatchMaterial;
    }
    vtkDis += q.VtkDisagree > 0;
    if (q.InsideVtk != q.Inside && vtkVerdict.size() < 5)
      vtkVerdict.push_back(i);
    vtkVertexDis += q.InsideVtk != q.Inside;
    vtkOnlyInside += q.InsideVtk && !q.Inside;
    depthLim += q.DepthLimited > 0;
    nodeLim += q.NodeLimited;
    totalNodes += q.Nodes;
    maxNodes = std::max(maxNodes, q.Nodes);
    insideUndecided += q.InsideUndecided > 0;
    maxInsideNodes = std::max(maxInsideNodes, q.InsideNodes);
    const double rr = residual[i] / diag;
    maxRes = std::max(maxRes, std::isfinite(rr) ? rr : 1e300);
    res10 += !(rr <= 1e-10);
    resReported += !(res->GetValue(i) <= 1e-10 * diag);
    maxResDiff = std::max(maxResDiff, std::fabs(res->GetValue(i) - residual[i]) / diag);
  }
  std::partial_sort(worst.begin(), worst.begin() + std::min<size_t>(8, worst.size()), worst.end(),
    [](const std::pair<double, Id>& a, const std::pair<double, Id>& b) {
      return a.first > b.first;
    });
  std::printf("{\n  \"method\": \"%s\", \"cell_type\": \"tet%d\", \"cells\": %lld, "
              "\"boundary_faces\": %lld, \"diagonal\": %.17g,\n",
    method ? "barycentric" : "normal-offset", npc, static_cast<long long>(nc),
    static_cast<long long>(em.NumberOfFaces()), diag);
  std::printf("  \"surface_vertices\": %lld, \"vertices_checked\": %lld,\n",
    static_cast<long long>(nv), static_cast<long long>(nv));
  std::printf("  \"threads\": %d, \"filter_wall_s\": %.4f, \"filter_cpu_s\": %.4f, "
              "\"brute_wall_s\": %.3f, \"filter_uncertified_points\": %lld,\n",
    vtkSMPTools::GetEstimatedNumberOfThreads(), filterWall, filterCpu, bruteWall,
    static_cast<long long>(filter->GetNumberOfUncertifiedPoints()));
  std::printf("  \"max_dist_err_rel\": %.3e, \"count_dist_err_above_1e-8\": %ld, "
              "\"count_dist_err_above_1e-10\": %ld, \"count_dist_err_above_1e-12\": %ld,\n",
    maxErr, above8, above10, above12);
  std::printf(
    "  \"count_outside_certified_interval\": %ld, \"count_filter_below_lower_bound\": %ld, "
    "\"max_certificate_width_rel\": %.3e,\n",
    outsideCert, belowLower, maxCert);
  std::printf("  \"max_residual_rel\": %.3e, \"count_residual_above_1e-10\": %ld, "
              "\"count_reported_residual_above_1e-10\": %ld, "
              "\"max_reported_vs_recomputed_residual_rel\": %.3e, \"non_finite\": %ld,\n",
    maxRes, res10, resReported, maxResDiff, nanCount);
  std::printf(
    "  \"inside_brute\": %ld, \"inside_filter\": %ld, \"inside_mismatch\": %ld, "
    "\"inside_mismatch_beyond_1e-8\": %ld,\n  \"vertices_with_vtk_cell_disagreement\": %ld, "
    "\"vertices_vtk_inside_verdict_differs\": %ld, \"vertices_inside_only_for_vtk\": %ld,\n",
    bruteInside, filterInside, insideMismatch, insideMismatchMaterial, vtkDis, vtkVertexDis,
    vtkOnlyInside);
  std::printf("  \"bb_nodes_mean\": %.1f, \"bb_nodes_max\": %ld, \"vertices_depth_limited\": %ld, "
              "\"vertices_node_limited\": %ld,\n  \"vertices_inside_undecided\": %ld, "
              "\"inside_subtets_max\": %ld,\n",
    double(totalNodes) / double(nv), maxNodes, depthLim, nodeLim, insideUndecided, maxInsideNodes);
  std::printf("  \"vtk_verdict_differs\": [");
  for (size_t k = 0; k < vtkVerdict.size(); ++k)
  {
    const PerVertex& q = pv[vtkVerdict[k]];
    std::printf("%s{\"vertex\": %lld, \"inside_own\": %s, \"inside_vtk\": %s, "
                "\"boundary_distance_rel\": %.3e}",
      k ? ", " : "", static_cast<long long>(vtkVerdict[k]), q.Inside ? "true" : "false",
      q.InsideVtk ? "true" : "false", q.Upper / diag);
  }
  std::printf("],\n");
  std::printf("  \"worst\": [");
  for (size_t k = 0; k < std::min<size_t>(8, worst.size()); ++k)
  {
    const Id i = worst[k].second;
    const PerVertex& q = pv[i];
    std::printf("%s\n    {\"vertex\": %lld, \"err_rel\": %.3e, \"d_filter\": %.17g, "
                "\"d_brute\": %.17g, \"lower\": %.17g, \"upper\": %.17g, \"brute_inside\": %s, "
                "\"filter_cell\": %lld, \"filter_face\": %d, \"residual_rel\": %.3e}",
      k ? "," : "", static_cast<long long>(i), worst[k].first, closest->GetValue(i), q.Brute,
      q.Lower, q.Upper, q.Inside ? "true" : "false", static_cast<long long>(cellId->GetValue(i)),
      int(face->GetValue(i)), residual[i] / diag);
  }
  std::printf("\n  ]\n}\n");
  return 0;
}
