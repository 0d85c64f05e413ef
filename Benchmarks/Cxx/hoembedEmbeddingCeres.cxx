// hoembedEmbeddingCeres: vtkEmbeddingCoordinatesFilter next to the paper's own method (a
// bound-constrained Levenberg–Marquardt per candidate face, here Ceres on VTK's cells:
// hoembedCeresReference.h), speed and failures side by side.
//
//   hoembedEmbeddingCeres surface.vtp mesh.vtu [sample]
//
// Both run on one thread (vtkSMPTools::Initialize(1)). The filter embeds every vertex;
// the reference solves every k-th vertex (k chosen so that about `sample` vertices are
// solved, default 2000) and its time is scaled to vertices per second. On those vertices
// the closest distances are compared: a "miss" is a distance more than 1e-10 of the
// mesh's diagonal above the other's (a local minimum taken for the global one). Prints
// one JSON object on stdout. A benchmark tool: not installed, not a test
// (Benchmarks/bench_embedding_ceres.py runs it).
#include "hoembedCeresReference.h"

#include "vtkEmbeddingCoordinatesFilter.h"

#include "vtkDoubleArray.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkSMPTools.h"
#include "vtkUnstructuredGrid.h"
#include "vtkXMLPolyDataReader.h"
#include "vtkXMLUnstructuredGridReader.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace
{
double Seconds(std::chrono::steady_clock::time_point t0)
{
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}
} // namespace

int main(int argc, char* argv[])
{
  if (argc < 3)
  {
    std::fprintf(stderr, "usage: %s surface.vtp mesh.vtu [sample]\n", argv[0]);
    return 2;
  }
  const long sample = argc > 3 ? std::atol(argv[3]) : 2000;
  vtkSMPTools::Initialize(1);
  vtkNew<vtkXMLPolyDataReader> sr;
  sr->SetFileName(argv[1]);
  sr->Update();
  vtkPolyData* surface = sr->GetOutput();
  vtkNew<vtkXMLUnstructuredGridReader> mr;
  mr->SetFileName(argv[2]);
  mr->Update();
  vtkUnstructuredGrid* mesh = mr->GetOutput();
  const vtkIdType nv = surface->GetNumberOfPoints();
  if (nv == 0 || mesh->GetNumberOfCells() == 0)
  {
    std::fprintf(stderr, "hoembedEmbeddingCeres: empty surface or mesh\n");
    return 1;
  }

  auto t0 = std::chrono::steady_clock::now();
  vtkNew<vtkEmbeddingCoordinatesFilter> filter;
  filter->SetInputData(0, surface);
  filter->SetMeshData(mesh);
  filter->Update();
  const double filterSeconds = Seconds(t0);
  auto* closest = vtkDoubleArray::SafeDownCast(
    filter->GetOutput()->GetPointData()->GetArray("EmbeddingClosestDistance"));
  if (!closest)
  {
    std::fprintf(stderr, "hoembedEmbeddingCeres: the filter failed on this mesh\n");
    return 1;
  }

  t0 = std::chrono::steady_clock::now();
  hoembed_ceres::CeresOptions options;
  hoembed_ceres::CeresMesh reference;
  const std::string err = reference.Build(mesh, options);
  if (!err.empty())
  {
    std::fprintf(stderr, "hoembedEmbeddingCeres: %s\n", err.c_str());
    return 1;
  }
  const double buildSeconds = Seconds(t0);
  const vtkIdType step = std::max<vtkIdType>(1, nv / std::max(1L, sample));
  const double diag = reference.Diagonal;
  long solved = 0, ceresMisses = 0, filterMisses = 0, inside = 0;
  double maxDiff = 0.0, lmIterations = 0.0, facesSolved = 0.0;
  t0 = std::chrono::steady_clock::now();
  for (vtkIdType v = 0; v < nv; v += step)
  {
    hoembed_ceres::CeresResult r;
    hoembed_ceres::CeresDistance(reference, surface->GetPoint(v), options, r);
    const double d = closest->GetValue(v);
    ++solved;
    inside += r.Inside;
    lmIterations += r.Iterations;
    facesSolved += r.FacesSolved;
    maxDiff = std::max(maxDiff, std::fabs(r.Distance - d) / diag);
    ceresMisses += r.Distance > d + 1e-10 * diag;
    filterMisses += d > r.Distance + 1e-10 * diag;
  }
  const double ceresSeconds = Seconds(t0);
  const double filterRate = nv / filterSeconds;
  const double ceresRate = solved / ceresSeconds;
  std::printf("{\"cell_type\": %d, \"cells\": %lld, \"vertices\": %lld, \"solved\": %ld, "
              "\"inside\": %ld, \"filter_vertices_per_s\": %.6g, \"ceres_vertices_per_s\": %.6g, "
              "\"speed_ratio\": %.4g, \"ceres_build_s\": %.4g, \"max_diff_of_diagonal\": %.3e, "
              "\"ceres_misses\": %ld, \"filter_misses\": %ld, \"ceres_lm_iterations\": %.1f, "
              "\"ceres_faces\": %.2f}\n",
    mesh->GetCellType(0), static_cast<long long>(mesh->GetNumberOfCells()),
    static_cast<long long>(nv), solved, inside, filterRate, ceresRate, filterRate / ceresRate,
    buildSeconds, maxDiff, ceresMisses, filterMisses, lmIterations / solved, facesSolved / solved);
  return 0;
}
