// Small helpers shared by the C++ tests: checks, generated meshes, the data folder.
#ifndef hoembedTestUtilities_h
#define hoembedTestUtilities_h

#include "vtkCellArray.h"
#include "vtkCellType.h"
#include "vtkDoubleArray.h"
#include "vtkNew.h"
#include "vtkPoints.h"
#include "vtkSmartPointer.h"
#include "vtkUnstructuredGrid.h"

#include <array>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <map>
#include <string>
#include <sys/stat.h>
#include <utility>
#include <vector>

namespace hoembed_test
{
inline int& Failures()
{
  static int failures = 0;
  return failures;
}

#define HOEMBED_CHECK(cond, ...)                                                                   \
  do                                                                                               \
  {                                                                                                \
    if (!(cond))                                                                                   \
    {                                                                                              \
      std::fprintf(stderr, "%s:%d: check failed: %s: ", __FILE__, __LINE__, #cond);                \
      std::fprintf(stderr, __VA_ARGS__);                                                           \
      std::fprintf(stderr, "\n");                                                                  \
      ++hoembed_test::Failures();                                                                  \
    }                                                                                              \
  } while (0)

/// Exit code for main(): 0 if no check failed, 1 otherwise (prints a summary line).
inline int Report(const char* name)
{
  std::printf("%s: %s (%d failed checks)\n", name, Failures() ? "FAILED" : "passed", Failures());
  return Failures() ? EXIT_FAILURE : EXIT_SUCCESS;
}

/// The real-mesh folder given as argv[1] (ctest passes ../shared/data/meshes), or "" if
/// absent: tests that need it return 125 (skipped) then.
inline std::string DataDir(int argc, char* argv[])
{
  if (argc < 2)
  {
    return std::string();
  }
  struct stat st;
  return stat(argv[1], &st) == 0 && S_ISDIR(st.st_mode) ? std::string(argv[1]) : std::string();
}

/// Cell connectivity of a tet4 / tet10 grid, flattened; `npc` gets the nodes per cell.
inline std::vector<std::int64_t> MeshConnectivity(vtkUnstructuredGrid* mesh, int& npc)
{
  npc = mesh->GetCellType(0) == VTK_QUADRATIC_TETRA ? 10 : 4;
  std::vector<std::int64_t> conn;
  for (vtkIdType c = 0; c < mesh->GetNumberOfCells(); ++c)
  {
    vtkIdType n;
    const vtkIdType* ids;
    mesh->GetCells()->GetCellAtId(c, n, ids);
    for (int a = 0; a < n; ++a)
      conn.push_back(ids[a]);
  }
  return conn;
}

/// Point coordinates of a grid, 3 doubles per point.
inline std::vector<double> PointsOf(vtkUnstructuredGrid* mesh)
{
  std::vector<double> p(3 * mesh->GetNumberOfPoints());
  for (vtkIdType i = 0; i < mesh->GetNumberOfPoints(); ++i)
    mesh->GetPoint(i, &p[3 * i]);
  return p;
}

/// One unit-cube VTK_HEXAHEDRON: a mesh of a cell type the FE stages refuse.
inline vtkSmartPointer<vtkUnstructuredGrid> MakeUnitHexahedron()
{
  auto hex = vtkSmartPointer<vtkUnstructuredGrid>::New();
  vtkNew<vtkPoints> pts;
  for (int k = 0; k < 8; ++k)
    pts->InsertNextPoint(k & 1, (k >> 1) & 1, (k >> 2) & 1);
  hex->SetPoints(pts);
  vtkIdType ids[8] = { 0, 1, 3, 2, 4, 5, 7, 6 };
  hex->InsertNextCell(VTK_HEXAHEDRON, 8, ids);
  return hex;
}

/**
 * A box [0,lx]x[0,ly]x[0,lz] split into nx*ny*nz cubes of 6 conforming (Kuhn) tets each,
 * as VTK_TETRA (order 1) or VTK_QUADRATIC_TETRA (order 2, straight mid-edge nodes).
 * `map`, when given, moves every node afterwards (e.g. to curve the mesh).
 */
inline vtkSmartPointer<vtkUnstructuredGrid> MakeBoxTetMesh(int nx, int ny, int nz, double lx,
  double ly, double lz, int order,
  const std::function<void(double[3])>& map = std::function<void(double[3])>())
{
  std::vector<std::array<double, 3>> pts;
  auto gid = [&](int i, int j, int k) { return (k * (ny + 1) + j) * (nx + 1) + i; };
  for (int k = 0; k <= nz; ++k)
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i)
        pts.push_back({ lx * i / nx, ly * j / ny, lz * k / nz });
  std::vector<std::array<vtkIdType, 4>> tets;
  const int perms[6][3] = { { 0, 1, 2 }, { 0, 2, 1 }, { 1, 0, 2 }, { 1, 2, 0 }, { 2, 0, 1 },
    { 2, 1, 0 } };
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
        for (const auto& p : perms)
        {
          int c[3] = { 0, 0, 0 };
          std::array<vtkIdType, 4> t;
          t[0] = gid(i, j, k);
          for (int s = 0; s < 3; ++s)
          {
            c[p[s]] = 1;
            t[s + 1] = gid(i + c[0], j + c[1], k + c[2]);
          }
          // orientation: make det > 0
          const auto& a = pts[t[0]];
          double e[3][3];
          for (int r = 0; r < 3; ++r)
            for (int d = 0; d < 3; ++d)
              e[r][d] = pts[t[r + 1]][d] - a[d];
          const double det = e[0][0] * (e[1][1] * e[2][2] - e[1][2] * e[2][1]) -
            e[0][1] * (e[1][0] * e[2][2] - e[1][2] * e[2][0]) +
            e[0][2] * (e[1][0] * e[2][1] - e[1][1] * e[2][0]);
          if (det < 0)
            std::swap(t[1], t[2]);
          tets.push_back(t);
        }
  vtkNew<vtkCellArray> cells;
  std::map<std::pair<vtkIdType, vtkIdType>, vtkIdType> mids;
  const int edges[6][2] = { { 0, 1 }, { 1, 2 }, { 2, 0 }, { 0, 3 }, { 1, 3 }, { 2, 3 } };
  for (const auto& t : tets)
  {
    vtkIdType ids[10];
    for (int a = 0; a < 4; ++a)
      ids[a] = t[a];
    if (order == 2)
    {
      for (int e = 0; e < 6; ++e)
      {
        vtkIdType u = t[edges[e][0]], v = t[edges[e][1]];
        auto key = std::make_pair(std::min(u, v), std::max(u, v));
        auto it = mids.find(key);
        if (it == mids.end())
        {
          const auto& pu = pts[u];
          const auto& pv = pts[v];
          pts.push_back({ 0.5 * (pu[0] + pv[0]), 0.5 * (pu[1] + pv[1]), 0.5 * (pu[2] + pv[2]) });
          it = mids.emplace(key, static_cast<vtkIdType>(pts.size() - 1)).first;
        }
        ids[4 + e] = it->second;
      }
    }
    cells->InsertNextCell(order == 2 ? 10 : 4, ids);
  }
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(static_cast<vtkIdType>(pts.size()));
  for (size_t i = 0; i < pts.size(); ++i)
  {
    double x[3] = { pts[i][0], pts[i][1], pts[i][2] };
    if (map)
      map(x);
    points->SetPoint(static_cast<vtkIdType>(i), x);
  }
  auto grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
  grid->SetPoints(points);
  grid->SetCells(order == 2 ? VTK_QUADRATIC_TETRA : VTK_TETRA, cells);
  return grid;
}
} // namespace hoembed_test

#endif
