// The deformation transfer's per-frame cost by configuration, on one bent frame of a
// saved embedded surface and its FE mesh (bench_live.py --save DIR writes the live
// benchmark's): positions only, with recomputed or transformed point normals, double or
// float output points, the plain and the AVX2 kernel (hoembed::SetTransferKernelSimd).
// The configurations are alternated repeat by repeat, so a loaded machine slows all alike;
// prints the median and minimum wall and process CPU ms per transfer.
//
//     build/bin/hoembedTransferBench DIR/embedded.vtp DIR/fe.vtu [threads] [repeats]
#include "hoembedTransferKernel.h"
#include "vtkDeformationTransferFilter.h"
#include "vtkXMLPolyDataReader.h"
#include "vtkXMLUnstructuredGridReader.h"
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
