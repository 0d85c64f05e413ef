// The deformation transfer's per-frame cost by configuration, on one bent frame of a
// saved embedded surface and its FE mesh (bench_live.py --save DIR writes the live
// benchmark's): positions only, with recomputed or transformed point normals, double or
// float output points, the plain and the AVX2 kernel (hoembed::SetTransferKernelSimd).
// The configurations are alternated repeat by repeat, so a loaded machine slows all alike;
// prints the median and minimum wall and process CPU ms per transfer.
//
// `kernel` (or `both`) as a fifth argument times hoembed::EvaluateTransfer alone on the
// same frame (plan, coefficient tables and output arrays made once, as in the live loop):
// plain and AVX2, positions only or with transformed normals, double or float points.
//
//     build/bin/hoembedTransferBench DIR/embedded.vtp DIR/fe.vtu [threads] [repeats]
//       [filter|kernel|both]
#include "hoembedTransferKernel.h"
#include "vtkDeformationTransferFilter.h"
#include "vtkXMLPolyDataReader.h"
#include "vtkXMLUnstructuredGridReader.h"
#include "hoembedTetMeshTopology.h"
#include "vtkCellArray.h"
#include "vtkDataArray.h"
#include <cstring>
#include <string>
#include <random>
#include "vtkUnstructuredGrid.h"
#include "vtkPolyData.h"
#include "vtkPoints.h"
#include "vtkPointData.h"
#include "vtkDoubleArray.h"
#include "vtkSMPTools.h"
#include "vtkNew.h"
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <vector>
#include <algorithm>
#include <cmath>
#include <ctime>
namespace
{
// The kernel alone: a plan made from the embedding arrays, the bent frame's tables
void KernelBench(
  vtkPolyData* surface, vtkUnstructuredGrid* rest, vtkUnstructuredGrid* bent, int reps)
{
  const vtkIdType nc = rest->GetNumberOfCells();
  const int npc = static_cast<int>(rest->GetCell(0)->GetNumberOfPoints());
  std::vector<std::int64_t> conn(static_cast<size_t>(npc) * nc);
  for (vtkIdType c = 0; c < nc; ++c)
  {
    vtkIdType n;
    const vtkIdType* ids;
    rest->GetCellPoints(c, n, ids);
    for (int a = 0; a < npc; ++a)
      conn[npc * c + a] = ids[a];
  }
  const vtkIdType np = rest->GetNumberOfPoints();
  hoembed::TetMeshTopology topo;
  topo.Build(conn.data(), nc, npc, np);
  auto* pd = surface->GetPointData();
  vtkDataArray* cell = pd->GetArray("EmbeddingCellId");
  vtkDataArray* pcs = pd->GetArray("EmbeddingParametricCoords");
  vtkDataArray* dist = pd->GetArray("EmbeddingDistance");
  vtkDataArray* face = pd->GetArray("EmbeddingFace");
  const std::int64_t nv = surface->GetNumberOfPoints();
  std::vector<hoembed::TransferEntry> plan(nv);
  for (std::int64_t i = 0; i < nv; ++i)
  {
    auto& e = plan[i];
    pcs->GetTuple(i, e.PC);
    e.Distance = dist->GetComponent(i, 0);
    e.Cell = static_cast<std::int32_t>(cell->GetComponent(i, 0));
    const int f = static_cast<int>(face->GetComponent(i, 0));
    const auto b = f >= 0 ? topo.CellBoundaryFace[4 * e.Cell + f] : -1;
    e.Face = b >= 0 ? static_cast<std::int32_t>(4 * b + f) : -1;
  }
  auto points = [](vtkUnstructuredGrid* g) {
    std::vector<double> x(3 * g->GetNumberOfPoints());
    for (vtkIdType i = 0; i < g->GetNumberOfPoints(); ++i)
      g->GetPoint(i, &x[3 * i]);
    return x;
  };
  const std::vector<double> x0 = points(rest), x1 = points(bent);
  const int cs = hoembed::CellCoefficientSize(npc), fs = hoembed::FaceCoefficientSize(npc);
  std::vector<double> k0(cs * nc), k1(cs * nc), fk(fs * topo.GetNumberOfBoundaryFaces());
  hoembed::ComputeCellMapCoefficients(conn.data(), npc, x0.data(), 0, nc, k0.data());
  hoembed::ComputeCellMapCoefficients(conn.data(), npc, x1.data(), 0, nc, k1.data());
  // nodal normals: unit vectors of a fixed random draw (the cost does not depend on them)
  std::mt19937 rng(1);
  std::normal_distribution<double> g;
  std::vector<double> nn(3 * np);
  for (vtkIdType i = 0; i < np; ++i)
  {
    double v[3] = { g(rng), g(rng), g(rng) };
    const double l = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    for (int d = 0; d < 3; ++d)
      nn[3 * i + d] = v[d] / l;
  }
  hoembed::ComputeFaceNormalCoefficients(
    topo, nn.data(), 0, topo.GetNumberOfBoundaryFaces(), fk.data());
  std::vector<float> n0(3 * nv), cov(3 * nv);
  for (std::int64_t i = 0; i < 3 * nv; ++i)
    n0[i] = static_cast<float>(g(rng));
  hoembed::ComputeNormalCovectors(plan.data(), npc, k0.data(), n0.data(), 0, nv, cov.data());
  std::vector<unsigned char> folded(nc);
  hoembed::MarkInvertedCells(conn.data(), npc, x1.data(), 0, nc, folded.data());
  std::vector<double> outd(3 * nv);
  std::vector<float> outf(3 * nv), normals(3 * nv);
  struct KCfg
  {
    const char* name;
    int simd, normals, dbl;
  };
  const KCfg cfgs[] = { { "kernel plain, positions", 0, 0, 1 },
    { "kernel avx2, positions", 1, 0, 1 }, { "kernel plain, positions float", 0, 0, 0 },
    { "kernel avx2, positions float", 1, 0, 0 }, { "kernel plain, + normals", 0, 1, 1 },
    { "kernel avx2, + normals", 1, 1, 1 }, { "kernel plain, + normals, float", 0, 1, 0 },
    { "kernel avx2, + normals, float", 1, 1, 0 } };
  const int ncfg = 8;
  std::vector<std::vector<double>> wall(ncfg), cpu(ncfg);
  std::vector<std::vector<unsigned char>> bits(ncfg);
  for (int r = 0; r < reps; ++r)
    for (int c = 0; c < ncfg; ++c)
    {
      const KCfg& k = cfgs[c];
      hoembed::SetTransferKernelSimd(k.simd);
      auto t0 = std::chrono::steady_clock::now();
      std::clock_t c0 = std::clock();
      // the driver's split: blocks of 8192 vertices over the threads
      vtkSMPTools::For(0, nv, 8192, [&](vtkIdType b, vtkIdType e) {
        if (k.normals && k.dbl)
          hoembed::EvaluateTransfer(plan.data(), npc, k1.data(), fk.data(), cov.data(),
            folded.data(), b, e, outd.data(), normals.data());
        else if (k.normals)
          hoembed::EvaluateTransfer(plan.data(), npc, k1.data(), fk.data(), cov.data(),
            folded.data(), b, e, outf.data(), normals.data());
        else if (k.dbl)
          hoembed::EvaluateTransfer(plan.data(), npc, k1.data(), fk.data(), b, e, outd.data());
        else
          hoembed::EvaluateTransfer(plan.data(), npc, k1.data(), fk.data(), b, e, outf.data());
      });
      cpu[c].push_back(1e3 * double(std::clock() - c0) / CLOCKS_PER_SEC);
      wall[c].push_back(
        1e3 * std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
      if (r == 0)
      { // the outputs' bytes, to compare plain with AVX2
        auto& v = bits[c];
        const auto* p = k.dbl ? reinterpret_cast<const unsigned char*>(outd.data())
                              : reinterpret_cast<const unsigned char*>(outf.data());
        v.assign(p, p + 3 * nv * (k.dbl ? sizeof(double) : sizeof(float)));
        if (k.normals)
        {
          const auto* q = reinterpret_cast<const unsigned char*>(normals.data());
          v.insert(v.end(), q, q + 3 * nv * sizeof(float));
        }
      }
    }
  hoembed::SetTransferKernelSimd(-1);
  for (int c = 0; c < ncfg; ++c)
  {
    auto w = wall[c], k = cpu[c];
    std::sort(w.begin(), w.end());
    std::sort(k.begin(), k.end());
    std::printf("%-42s wall median %6.2f min %6.2f  cpu median %6.2f min %6.2f ms%s\n",
      cfgs[c].name, w[w.size() / 2], w[0], k[k.size() / 2], k[0],
      cfgs[c].simd ? (bits[c] == bits[c - 1] ? "  (plain's bits)" : "  (BITS DIFFER)") : "");
  }
}
} // namespace

int main(int argc, char** argv)
{
  if (argc < 3)
  {
    std::fprintf(stderr, "usage: %s embedded.vtp fe.vtu [threads] [repeats]\n", argv[0]);
    return 2;
  }
  int threads = argc > 3 ? atoi(argv[3]) : 1;
  vtkSMPTools::Initialize(threads);
  vtkNew<vtkXMLPolyDataReader> rs;
  rs->SetFileName(argv[1]);
  rs->Update();
  vtkNew<vtkXMLUnstructuredGridReader> rm;
  rm->SetFileName(argv[2]);
  rm->Update();
  vtkUnstructuredGrid* rest = rm->GetOutput();
  // a bent copy with Displacement
  vtkNew<vtkUnstructuredGrid> bent;
  bent->CopyStructure(rest);
  vtkNew<vtkPoints> p;
  p->SetDataTypeToDouble();
  p->SetNumberOfPoints(rest->GetNumberOfPoints());
  vtkNew<vtkDoubleArray> u;
  u->SetName("Displacement");
  u->SetNumberOfComponents(3);
  u->SetNumberOfTuples(rest->GetNumberOfPoints());
  for (vtkIdType i = 0; i < rest->GetNumberOfPoints(); ++i)
  {
    double x[3], y[3];
    rest->GetPoint(i, x);
    const double R = 8.0, th = x[0] / R;
    y[0] = (R + x[2]) * std::sin(th);
    y[1] = x[1];
    y[2] = (R + x[2]) * std::cos(th) - R;
    p->SetPoint(i, y);
    u->SetTuple3(i, y[0] - x[0], y[1] - x[1], y[2] - x[2]);
  }
  bent->SetPoints(p);
  bent->GetPointData()->AddArray(u);
  const std::string what = argc > 5 ? argv[5] : "filter";
  if (what == "kernel" || what == "both")
  {
    KernelBench(rs->GetOutput(), rest, bent, argc > 4 ? atoi(argv[4]) : 11);
    if (what == "kernel")
      return 0;
  }
  struct Cfg
  {
    const char* name;
    int simd;
    int normals;
    int precision;
  };
  Cfg cfgs[] = { { "plain, no normals", 0, -1, 1 }, { "avx2, no normals", 1, -1, 1 },
    { "plain, recompute normals", 0, 0, 1 }, { "avx2, recompute normals", 1, 0, 1 },
    { "plain, transform normals", 0, 1, 1 }, { "avx2, transform normals", 1, 1, 1 },
    { "avx2, transform normals, float points", 1, 1, 0 },
    { "avx2, no normals, float points", 1, -1, 0 } };
  const int ncfg = 8, reps = argc > 4 ? atoi(argv[4]) : 11;
  std::vector<std::vector<double>> wall(ncfg), cpu(ncfg);
  vtkNew<vtkDeformationTransferFilter> f[8];
  for (int c = 0; c < ncfg; ++c)
  {
    f[c]->SetInputData(0, rs->GetOutput());
    f[c]->SetInputData(1, bent);
    f[c]->SetComputePointNormals(cfgs[c].normals >= 0);
    f[c]->SetPointNormalsMode(cfgs[c].normals > 0 ? 1 : 0);
    f[c]->SetOutputPointsPrecision(cfgs[c].precision);
    hoembed::SetTransferKernelSimd(cfgs[c].simd);
    f[c]->Update();
  }
  for (int r = 0; r < reps; ++r)
    for (int c = 0; c < ncfg; ++c)
    { // alternated: the load hits every configuration alike
      hoembed::SetTransferKernelSimd(cfgs[c].simd);
      f[c]->Modified();
      auto t0 = std::chrono::steady_clock::now();
      std::clock_t c0 = std::clock();
      f[c]->Update();
      cpu[c].push_back(1e3 * double(std::clock() - c0) / CLOCKS_PER_SEC);
      wall[c].push_back(
        1e3 * std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    }
  for (int c = 0; c < ncfg; ++c)
  {
    auto w = wall[c], k = cpu[c];
    std::sort(w.begin(), w.end());
    std::sort(k.begin(), k.end());
    std::printf("%-42s wall median %6.2f min %6.2f  cpu median %6.2f min %6.2f ms\n", cfgs[c].name,
      w[w.size() / 2], w[0], k[k.size() / 2], k[0]);
  }
}
