// vtkDeformationTransferFilter's TRANSFORM_POINT_NORMALS (the shading normals carried by
// the deformation, cof(F) n0, fused with the position transfer):
// - the kernel against cof(F) n0 built from VTK's own tet10 / tet4 shape-function
//   derivatives (F = J' J0^-1, cof(F) = det(F) F^-T), on random points of curved cells;
// - positions bit for bit those of the recompute mode (same frames, both precisions);
// - at rest and under rigid motions, equal to the recomputed area-weighted normals to
//   float round-off;
// - on a bent and twisted model (a fine ellipsoid embedded with vtkEmbeddingCoordinatesFilter
//   in a curved box mesh), the angle to the recomputed area-weighted normals of the
//   deformed surface is bounded (distribution printed);
// - without the Displacement array: a warning, and the recomputed normals;
// - the AVX2 kernel (four vertices per register) against the plain one, bit for bit, on
//   random plans made to reach each of its paths (below).
#include "hoembedTestUtilities.h"
#include "hoembedTetMeshTopology.h"
#include "hoembedTransferKernel.h"
#include "hoembedTransferTestUtilities.h"
#include "vtkDeformationTransferFilter.h"
#include "vtkEmbeddingCoordinatesFilter.h"

#include "vtkCallbackCommand.h"
#include "vtkCommand.h"
#include "vtkFloatArray.h"
#include "vtkMath.h"
#include "vtkSphereSource.h"
#include "vtkTransform.h"
#include "vtkTransformPolyDataFilter.h"
#include "vtkTriangleFilter.h"

#include <algorithm>
#include <cstring>
#include <cmath>
#include <random>
#include <string>
#include <vector>

using namespace hoembed_test;

namespace
{
void Curve(double x[3])
{
  const double y = x[1], z = x[2];
  x[0] += 0.05 * std::sin(2.0 * y + z);
  x[1] += 0.08 * std::sin(1.3 * x[0]);
  x[2] += 0.06 * std::cos(1.7 * x[0] + y);
}

// Bend about the y axis (radius 3) and twist about x (0.4 rad per unit length).
void BendTwist(const double* x, double* y)
{
  const double R = 3.0, phi = 0.4 * x[0];
  const double c = std::cos(phi), s = std::sin(phi);
  const double yy = c * (x[1] - 0.5) - s * (x[2] - 0.5) + 0.5;
  const double zz = s * (x[1] - 0.5) + c * (x[2] - 0.5) + 0.5;
  const double th = x[0] / R;
  y[0] = (R + zz) * std::sin(th);
  y[1] = yy;
  y[2] = (R + zz) * std::cos(th) - R;
}

// Bend only (the tail's drag is mostly that).
void Bend(const double* x, double* y)
{
  const double R = 2.5, th = x[0] / R;
  y[0] = (R + x[2]) * std::sin(th);
  y[1] = x[1];
  y[2] = (R + x[2]) * std::cos(th) - R;
}

struct Warnings
{
  std::vector<std::string> All;
  static void Callback(vtkObject*, unsigned long, void* client, void* data)
  {
    static_cast<Warnings*>(client)->All.push_back(data ? static_cast<const char*>(data) : "");
  }
};

// `deformed` with the point array Displacement = its points - the rest mesh's.
vtkSmartPointer<vtkUnstructuredGrid> WithDisplacement(
  vtkUnstructuredGrid* deformed, vtkUnstructuredGrid* rest)
{
  auto out = vtkSmartPointer<vtkUnstructuredGrid>::New();
  out->ShallowCopy(deformed);
  vtkNew<vtkDoubleArray> u;
  u->SetName("Displacement");
  u->SetNumberOfComponents(3);
  u->SetNumberOfTuples(deformed->GetNumberOfPoints());
  for (vtkIdType i = 0; i < deformed->GetNumberOfPoints(); ++i)
  {
    double x[3], X[3];
    deformed->GetPoint(i, x);
    rest->GetPoint(i, X);
    u->SetTuple3(i, x[0] - X[0], x[1] - X[1], x[2] - X[2]);
  }
  out->GetPointData()->AddArray(u);
  return out;
}

// dx/d(r, s, t) of a VTK cell at pc from VTK's own shape-function derivatives.
void VtkJacobian(vtkUnstructuredGrid* mesh, vtkIdType cell, const double pc[3], double J[3][3])
{
  vtkCell* c = mesh->GetCell(cell);
  const int n = c->GetNumberOfPoints();
  double derivs[30];
  if (n == 10)
    vtkQuadraticTetra::InterpolationDerivs(pc, derivs);
  else
    vtkTetra::InterpolationDerivs(pc, derivs);
  for (int d = 0; d < 3; ++d)
    for (int k = 0; k < 3; ++k)
      J[d][k] = 0.0;
  for (int a = 0; a < n; ++a)
  {
    double x[3];
    c->GetPoints()->GetPoint(a, x);
    for (int d = 0; d < 3; ++d)
      for (int k = 0; k < 3; ++k)
        J[d][k] += derivs[k * n + a] * x[d];
  }
}

double AngleDegrees(const double* a, const float* b)
{
  const double bb[3] = { b[0], b[1], b[2] };
  return vtkMath::DegreesFromRadians(vtkMath::AngleBetweenVectors(a, bb));
}

// The kernel against cof(F) n0 from VTK's derivatives, on random points of random cells.
void TestKernel(int order)
{
  auto rest = MakeBoxTetMesh(4, 2, 2, 4.0, 1.0, 1.0, order, Curve);
  auto bent = Deformed(rest, BendTwist);
  int npc;
  auto conn = MeshConnectivity(rest, npc);
  auto restPts = PointsOf(rest);
  auto pts = PointsOf(bent);
  const std::int64_t nc = rest->GetNumberOfCells();
  const int cs = hoembed::CellCoefficientSize(npc);
  std::vector<double> restCoeffs(cs * nc), coeffs(cs * nc);
  hoembed::ComputeCellMapCoefficients(conn.data(), npc, restPts.data(), 0, nc, restCoeffs.data());
  hoembed::ComputeCellMapCoefficients(conn.data(), npc, pts.data(), 0, nc, coeffs.data());
  std::mt19937 rng(3 + order);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  std::normal_distribution<double> g(0.0, 1.0);
  const int n = 500;
  std::vector<hoembed::TransferEntry> plan(n);
  std::vector<float> n0(3 * n), cov(3 * n), normals(3 * n);
  std::vector<double> expect(3 * n);
  for (int i = 0; i < n; ++i)
  {
    auto& e = plan[i];
    e.Cell = static_cast<std::int32_t>(uni(rng) * nc) % static_cast<std::int32_t>(nc);
    double l[4], s = 0;
    for (double& x : l)
      s += (x = uni(rng));
    e.PC[0] = l[1] / s;
    e.PC[1] = l[2] / s;
    e.PC[2] = l[3] / s;
    e.Distance = 0.0;
    e.Face = -1;
    double m[3] = { g(rng), g(rng), g(rng) };
    vtkMath::Normalize(m);
    for (int d = 0; d < 3; ++d)
      n0[3 * i + d] = static_cast<float>(m[d]);
    // the reference: F = J' J0^-1, cof(F) n0 = det(F) F^-T n0
    double J0[3][3], J[3][3], J0inv[3][3], F[3][3], Finv[3][3];
    VtkJacobian(rest, e.Cell, e.PC, J0);
    VtkJacobian(bent, e.Cell, e.PC, J);
    vtkMath::Invert3x3(J0, J0inv);
    vtkMath::Multiply3x3(J, J0inv, F);
    vtkMath::Invert3x3(F, Finv);
    const double nf[3] = { n0[3 * i], n0[3 * i + 1], n0[3 * i + 2] };
    for (int r = 0; r < 3; ++r)
      expect[3 * i + r] = Finv[0][r] * nf[0] + Finv[1][r] * nf[1] + Finv[2][r] * nf[2];
  }
  hoembed::ComputeNormalCovectors(plan.data(), npc, restCoeffs.data(), n0.data(), 0, n, cov.data());
  std::vector<double> out(3 * n), plain(3 * n);
  hoembed::EvaluateTransfer(plan.data(), npc, coeffs.data(), nullptr, cov.data(), nullptr, 0, n,
    out.data(), normals.data());
  hoembed::EvaluateTransfer(plan.data(), npc, coeffs.data(), nullptr, 0, n, plain.data());
  double worst = 0.0;
  for (int i = 0; i < n; ++i)
  {
    worst = std::max(worst, AngleDegrees(&expect[3 * i], &normals[3 * i]));
    const double len = std::sqrt(normals[3 * i] * normals[3 * i] +
      normals[3 * i + 1] * normals[3 * i + 1] + normals[3 * i + 2] * normals[3 * i + 2]);
    HOEMBED_CHECK(std::fabs(len - 1.0) < 1e-6, "kernel tet%d: normal %d not unit (%g)",
      order == 2 ? 10 : 4, i, len);
  }
  HOEMBED_CHECK(
    out == plain, "kernel tet%d: positions differ with normals on", order == 2 ? 10 : 4);
  // the AVX2 copy of the kernel (where the CPU has it) against the plain one: same bits
  if (hoembed::SetTransferKernelSimd(0) == false)
  {
    std::vector<double> out0(3 * n);
    std::vector<float> normals0(3 * n);
    hoembed::EvaluateTransfer(plan.data(), npc, coeffs.data(), nullptr, cov.data(), nullptr, 0, n,
      out0.data(), normals0.data());
    const bool simd = hoembed::SetTransferKernelSimd(1);
    std::vector<double> out1(3 * n);
    std::vector<float> normals1(3 * n);
    hoembed::EvaluateTransfer(plan.data(), npc, coeffs.data(), nullptr, cov.data(), nullptr, 0, n,
      out1.data(), normals1.data());
    hoembed::SetTransferKernelSimd(-1);
    HOEMBED_CHECK(out0 == out1 && normals0 == normals1,
      "kernel tet%d: the AVX2 kernel's bits differ from the plain one's", order == 2 ? 10 : 4);
    std::printf("kernel tet%d: AVX2 copy %s\n", order == 2 ? 10 : 4,
      simd ? "compared bitwise with the plain one" : "not available here");
  }
  HOEMBED_CHECK(
    worst < 1e-4, "kernel tet%d: cof(F) n0 off VTK's by %g degrees", order == 2 ? 10 : 4, worst);
  std::printf("kernel tet%d: cof(F) n0 against VTK's derivatives: worst %.3g degrees\n",
    order == 2 ? 10 : 4, worst);
}

// The AVX2 kernel against the plain one, bit for bit (memcmp: NaN normals included), on
// a random plan that reaches each of its paths: runs of 1-9 consecutive entries in one
// cell (groups of four in one cell, and groups over 2-4 cells), vertices with a normal
// offset on one boundary face or on several, without one (Face -1, or d = 0), a zero
// normal field (nodal normals zero on some faces), zero covectors, cells flagged folded,
// cells inverted by the frame (det J' <= 0), points outside their cell (S <= 0); ranges
// whose start and length are not multiples of four (tails of 1-3); double and float
// points, with and without normals, offsets and flags.
void TestKernelSimd(int order)
{
  const int tet = order == 2 ? 10 : 4;
  if (!hoembed::SetTransferKernelSimd(1))
  {
    hoembed::SetTransferKernelSimd(-1);
    std::printf("kernel tet%d: no AVX2 kernel here (plain only)\n", tet);
    return;
  }
  auto rest = MakeBoxTetMesh(3, 2, 2, 3.0, 1.0, 1.0, order, Curve);
  int npc;
  auto conn = MeshConnectivity(rest, npc);
  const std::int64_t nc = rest->GetNumberOfCells();
  const std::int64_t np = rest->GetNumberOfPoints();
  hoembed::TetMeshTopology topo;
  topo.Build(conn.data(), nc, npc, np);
  std::mt19937 rng(11 + order);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  std::normal_distribution<double> g(0.0, 1.0);
  // the frame: bent and twisted, and a few nodes thrown far (cells inverted)
  auto pts = PointsOf(Deformed(rest, BendTwist));
  for (int k = 0; k < 4; ++k)
  {
    const std::int64_t node = static_cast<std::int64_t>(uni(rng) * np) % np;
    for (int d = 0; d < 3; ++d)
      pts[3 * node + d] += 2.0 * g(rng);
  }
  const int cs = hoembed::CellCoefficientSize(npc), fs = hoembed::FaceCoefficientSize(npc);
  auto restPts = PointsOf(rest);
  std::vector<double> restCoeffs(cs * nc), coeffs(cs * nc);
  hoembed::ComputeCellMapCoefficients(conn.data(), npc, restPts.data(), 0, nc, restCoeffs.data());
  hoembed::ComputeCellMapCoefficients(conn.data(), npc, pts.data(), 0, nc, coeffs.data());
  const std::int64_t nf = topo.GetNumberOfBoundaryFaces();
  std::vector<double> nodal(3 * np), faceCoeffs(fs * nf);
  for (double& v : nodal)
    v = g(rng);
  for (std::int64_t f = 0; f < nf; f += 7) // zero normal fields
    for (int a = 0; a < topo.GetNodesPerFace(); ++a)
      for (int d = 0; d < 3; ++d)
        nodal[3 * topo.BoundaryFaceNodes[topo.GetNodesPerFace() * f + a] + d] = 0.0;
  hoembed::ComputeFaceNormalCoefficients(topo, nodal.data(), 0, nf, faceCoeffs.data());
  std::vector<unsigned char> folded(nc);
  std::int64_t inverted =
    hoembed::MarkInvertedCells(conn.data(), npc, pts.data(), 0, nc, folded.data());
  std::vector<unsigned char> flags(folded);
  for (std::int64_t c = 0; c < nc; c += 9)
    flags[c] = 1;

  const int n = 1203;
  std::vector<hoembed::TransferEntry> plan(n);
  std::vector<float> n0(3 * n);
  for (int i = 0; i < n;)
  {
    const int run = 1 + static_cast<int>(uni(rng) * 9);
    // a cell with a boundary face for most runs
    std::int32_t cell = static_cast<std::int32_t>(uni(rng) * nc) % static_cast<std::int32_t>(nc);
    for (int tries = 0; tries < 20 && uni(rng) < 0.8; ++tries)
    {
      bool boundary = false;
      for (int f = 0; f < 4; ++f)
        boundary = boundary || topo.CellBoundaryFace[4 * cell + f] >= 0;
      if (boundary)
        break;
      cell = static_cast<std::int32_t>(uni(rng) * nc) % static_cast<std::int32_t>(nc);
    }
    const int sameFace = uni(rng) < 0.5 ? static_cast<int>(uni(rng) * 4) : -1;
    for (int j = 0; j < run && i < n; ++j, ++i)
    {
      auto& e = plan[i];
      e.Cell = cell;
      double l[4], sum = 0;
      for (double& x : l)
        sum += (x = uni(rng));
      if (uni(rng) < 0.03)
        sum = -sum; // outside the cell: negative barycentric coordinates, S <= 0
      e.PC[0] = l[1] / sum;
      e.PC[1] = l[2] / sum;
      e.PC[2] = l[3] / sum;
      const int f = sameFace >= 0 ? sameFace : static_cast<int>(uni(rng) * 4) % 4;
      const auto b = topo.CellBoundaryFace[4 * cell + f];
      const double u = uni(rng);
      e.Face = b >= 0 && u < 0.9 ? static_cast<std::int32_t>(4 * b + f) : -1;
      e.Distance = u < 0.8 ? 0.05 * g(rng) : 0.0;
      double m[3] = { g(rng), g(rng), g(rng) };
      if (uni(rng) < 0.03)
        m[0] = m[1] = m[2] = 0.0;
      for (int d = 0; d < 3; ++d)
        n0[3 * i + d] = static_cast<float>(m[d]);
    }
  }
  std::vector<float> cov(3 * n);
  hoembed::ComputeNormalCovectors(plan.data(), npc, restCoeffs.data(), n0.data(), 0, n, cov.data());

  // What the plan reaches: groups of four (from entry 0) in one cell, with one face
  int oneCell = 0, oneFace = 0, groups = 0;
  for (int i = 0; i + 4 <= n; i += 4, ++groups)
  {
    bool cellSame = true, faceSame = plan[i].Face >= 0;
    for (int j = 1; j < 4; ++j)
    {
      cellSame = cellSame && plan[i + j].Cell == plan[i].Cell;
      faceSame = faceSame && plan[i + j].Face == plan[i].Face;
    }
    oneCell += cellSame ? 1 : 0;
    oneFace += faceSame ? 1 : 0;
  }
  HOEMBED_CHECK(oneCell > groups / 10 && oneCell < groups - groups / 10 && oneFace > 0,
    "kernel tet%d: the random plan misses a path (%d of %d groups in one cell, %d on one face)",
    tet, oneCell, groups, oneFace);

  const std::pair<int, int> ranges[] = { { 0, n }, { 1, n }, { 3, n - 2 }, { 5, 6 }, { 7, 9 },
    { 2, 5 }, { 0, 4 }, { 8, 72 }, { 13, 13 + 67 } };
  int differ = 0, runs = 0;
  std::int64_t leftTotal = 0;
  auto compare = [&](const void* a, const void* b, size_t bytes) {
    differ += std::memcmp(a, b, bytes) != 0 ? 1 : 0;
  };
  for (const auto& range : ranges)
    for (int withNormals = 0; withNormals < 2; ++withNormals)
      for (int withFaces = 0; withFaces < 2; ++withFaces)
        for (int withFlags = 0; withFlags < 2; ++withFlags)
          for (int dbl = 0; dbl < 2; ++dbl)
          {
            const double* fc = withFaces ? faceCoeffs.data() : nullptr;
            const unsigned char* fl = withFlags ? flags.data() : nullptr;
            std::vector<double> d[2] = { std::vector<double>(3 * n, 7.0),
              std::vector<double>(3 * n, 7.0) };
            std::vector<float> f[2] = { std::vector<float>(3 * n, 7.0f),
              std::vector<float>(3 * n, 7.0f) };
            std::vector<float> nn[2] = { std::vector<float>(3 * n, 7.0f),
              std::vector<float>(3 * n, 7.0f) };
            std::int64_t left[2] = { 0, 0 };
            for (int simd = 0; simd < 2; ++simd)
            {
              hoembed::SetTransferKernelSimd(simd);
              if (withNormals && dbl)
                left[simd] = hoembed::EvaluateTransfer(plan.data(), npc, coeffs.data(), fc,
                  cov.data(), fl, range.first, range.second, d[simd].data(), nn[simd].data());
              else if (withNormals)
                left[simd] = hoembed::EvaluateTransfer(plan.data(), npc, coeffs.data(), fc,
                  cov.data(), fl, range.first, range.second, f[simd].data(), nn[simd].data());
              else if (dbl)
                hoembed::EvaluateTransfer(
                  plan.data(), npc, coeffs.data(), fc, range.first, range.second, d[simd].data());
              else
                hoembed::EvaluateTransfer(
                  plan.data(), npc, coeffs.data(), fc, range.first, range.second, f[simd].data());
            }
            ++runs;
            compare(d[0].data(), d[1].data(), sizeof(double) * 3 * n);
            compare(f[0].data(), f[1].data(), sizeof(float) * 3 * n);
            compare(nn[0].data(), nn[1].data(), sizeof(float) * 3 * n);
            differ += left[0] != left[1] ? 1 : 0;
            leftTotal += left[0];
          }
  hoembed::SetTransferKernelSimd(-1);
  HOEMBED_CHECK(differ == 0,
    "kernel tet%d: the AVX2 kernel differs from the plain one in %d of %d runs", tet, differ, runs);
  HOEMBED_CHECK(leftTotal > 0 && inverted > 0,
    "kernel tet%d: no folded normal reached (%lld inverted cells)", tet,
    static_cast<long long>(inverted));
  std::printf("kernel tet%d: AVX2 kernel bit for bit the plain one in %d runs (%d of %d groups "
              "in one cell, %d on one face, %lld inverted cells, %lld normals left NaN)\n",
    tet, runs, oneCell, groups, oneFace, static_cast<long long>(inverted),
    static_cast<long long>(leftTotal));
}

struct AngleStats
{
  double Median = 0, P99 = 0, Max = 0;
};

AngleStats Angles(vtkPolyData* a, vtkPolyData* b)
{
  auto* na = vtkFloatArray::SafeDownCast(a->GetPointData()->GetNormals());
  auto* nb = vtkFloatArray::SafeDownCast(b->GetPointData()->GetNormals());
  std::vector<double> ang;
  if (!na || !nb || na->GetNumberOfTuples() != nb->GetNumberOfTuples())
    return AngleStats{ 1e9, 1e9, 1e9 };
  for (vtkIdType i = 0; i < na->GetNumberOfTuples(); ++i)
  {
    double x[3], y[3];
    na->GetTuple(i, x);
    nb->GetTuple(i, y);
    ang.push_back(vtkMath::DegreesFromRadians(vtkMath::AngleBetweenVectors(x, y)));
  }
  std::sort(ang.begin(), ang.end());
  AngleStats s;
  s.Median = ang[ang.size() / 2];
  s.P99 = ang[static_cast<size_t>(0.99 * (ang.size() - 1))];
  s.Max = ang.back();
  return s;
}

bool SamePoints(vtkPolyData* a, vtkPolyData* b)
{
  vtkDataArray* x = a->GetPoints()->GetData();
  vtkDataArray* y = b->GetPoints()->GetData();
  if (x->GetDataType() != y->GetDataType() || x->GetNumberOfTuples() != y->GetNumberOfTuples())
    return false;
  const size_t bytes = static_cast<size_t>(x->GetNumberOfValues()) * x->GetDataTypeSize();
  return std::memcmp(x->GetVoidPointer(0), y->GetVoidPointer(0), bytes) == 0;
}

// A fine ellipsoid (about 2 x 0.55 x 0.55 around the box's axis: it pokes out of the
// curved box on the sides and lies inside at the ends) embedded normal-offset.
vtkSmartPointer<vtkPolyData> EmbeddedEllipsoid(vtkUnstructuredGrid* mesh, int resolution)
{
  vtkNew<vtkSphereSource> sphere;
  sphere->SetThetaResolution(2 * resolution);
  sphere->SetPhiResolution(resolution);
  sphere->SetRadius(1.0);
  vtkNew<vtkTransform> t;
  t->Translate(2.0, 0.5, 0.5);
  t->Scale(1.9, 0.56, 0.56);
  vtkNew<vtkTransformPolyDataFilter> tf;
  tf->SetInputConnection(sphere->GetOutputPort());
  tf->SetTransform(t);
  vtkNew<vtkTriangleFilter> tri;
  tri->SetInputConnection(tf->GetOutputPort());
  tri->Update();
  auto fine = vtkSmartPointer<vtkPolyData>::New();
  fine->ShallowCopy(tri->GetOutput());
  fine->GetPointData()->Initialize(); // the sphere's own normals would pass through
  vtkNew<vtkEmbeddingCoordinatesFilter> embed;
  embed->SetInputData(0, fine);
  embed->SetInputData(1, mesh);
  embed->Update();
  auto out = vtkSmartPointer<vtkPolyData>::New();
  out->ShallowCopy(embed->GetOutput());
  return out;
}

void TestFilter(int order)
{
  const int tet = order == 2 ? 10 : 4;
  auto rest = MakeBoxTetMesh(8, 2, 2, 4.0, 1.0, 1.0, order, Curve);
  auto surface = EmbeddedEllipsoid(rest, 128);
  HOEMBED_CHECK(surface->GetNumberOfPoints() > 10000, "tet%d: the embedding failed", tet);
  if (surface->GetNumberOfPoints() <= 10000)
    return;
  vtkNew<vtkDeformationTransferFilter> fast, slow;
  for (vtkDeformationTransferFilter* f : { fast.Get(), slow.Get() })
  {
    f->ComputePointNormalsOn();
    f->SetInputData(0, surface);
  }
  fast->SetPointNormalsModeToTransform();
  HOEMBED_CHECK(
    slow->GetPointNormalsMode() == vtkDeformationTransferFilter::RECOMPUTE_POINT_NORMALS,
    "the default point normals mode is not recompute");
  Warnings warnings;
  vtkNew<vtkCallbackCommand> cb;
  cb->SetCallback(&Warnings::Callback);
  cb->SetClientData(&warnings);
  fast->AddObserver(vtkCommand::WarningEvent, cb);
  auto run = [&](vtkDeformationTransferFilter* f, vtkUnstructuredGrid* mesh) {
    f->SetInputData(1, mesh);
    f->Update();
    auto out = vtkSmartPointer<vtkPolyData>::New();
    out->DeepCopy(f->GetOutput());
    return out;
  };
  // rest, rigid motions, the bend, the bend + twist; each frame both modes
  std::mt19937 rng(17);
  struct Frame
  {
    const char* Name;
    vtkSmartPointer<vtkUnstructuredGrid> Mesh;
    double R[3][3];
  };
  std::vector<Frame> frames;
  frames.push_back(
    { "rest", WithDisplacement(rest, rest), { { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 } } });
  for (int k = 0; k < 2; ++k)
  {
    std::normal_distribution<double> g(0.0, 1.0);
    double q[4] = { g(rng), g(rng), g(rng), g(rng) }, R[3][3];
    const double len = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    for (double& c : q)
      c /= len;
    vtkMath::QuaternionToMatrix3x3(q, R);
    const double t[3] = { 3.0 * g(rng), 3.0 * g(rng), 3.0 * g(rng) };
    Frame fr{ "rigid",
      WithDisplacement(Deformed(rest,
                         [&](const double* x, double* y) {
                           vtkMath::Multiply3x3(R, x, y);
                           for (int d = 0; d < 3; ++d)
                             y[d] += t[d];
                         }),
        rest),
      {} };
    std::copy(&R[0][0], &R[0][0] + 9, &fr.R[0][0]);
    frames.push_back(fr);
  }
  frames.push_back({ "bend", WithDisplacement(Deformed(rest, Bend), rest), {} });
  frames.push_back({ "bend+twist", WithDisplacement(Deformed(rest, BendTwist), rest), {} });
  vtkSmartPointer<vtkPolyData> restNormals; // the recomputed normals at rest
  for (const Frame& fr : frames)
  {
    // both kernels (AVX2 where the CPU has it, and the plain one): the same bits, and
    // offset vertices (normal fields) among them
    hoembed::SetTransferKernelSimd(0);
    auto plainFast = run(fast, fr.Mesh);
    hoembed::SetTransferKernelSimd(-1);
    auto a = run(fast, fr.Mesh);
    auto b = run(slow, fr.Mesh);
    {
      auto* n0 = vtkFloatArray::SafeDownCast(plainFast->GetPointData()->GetNormals());
      auto* n1 = vtkFloatArray::SafeDownCast(a->GetPointData()->GetNormals());
      HOEMBED_CHECK(SamePoints(plainFast, a) && n0 && n1 &&
          std::memcmp(
            n0->GetPointer(0), n1->GetPointer(0), sizeof(float) * 3 * n0->GetNumberOfTuples()) == 0,
        "tet%d %s: the AVX2 and the plain kernel differ", tet, fr.Name);
    }
    HOEMBED_CHECK(
      SamePoints(a, b), "tet%d %s: positions differ between the point normal modes", tet, fr.Name);
    const AngleStats s = Angles(a, b);
    std::printf("tet%d, %lld vertices, %s: angle transformed vs recomputed normals: median "
                "%.3g, 99th percentile %.3g, max %.3g degrees\n",
      tet, static_cast<long long>(a->GetNumberOfPoints()), fr.Name, s.Median, s.P99, s.Max);
    const std::string name = fr.Name;
    if (name == "rest")
    {
      restNormals = b;
    }
    if (name == "rest" || name == "rigid")
    {
      // against R n0, n0 the recomputed rest normals: float round-offs only (the
      // recomputed normals of a translated surface lose more: Newell's sums of
      // coordinates, printed above)
      auto expect = vtkSmartPointer<vtkPolyData>::New();
      expect->ShallowCopy(restNormals);
      vtkNew<vtkFloatArray> rn;
      rn->DeepCopy(restNormals->GetPointData()->GetNormals());
      for (vtkIdType i = 0; i < rn->GetNumberOfTuples(); ++i)
      {
        double x[3], y[3];
        rn->GetTuple(i, x);
        vtkMath::Multiply3x3(fr.R, x, y);
        rn->SetTuple(i, y);
      }
      vtkNew<vtkPointData> pd;
      pd->SetNormals(rn);
      expect->GetPointData()->ShallowCopy(pd);
      const AngleStats r = Angles(a, expect);
      HOEMBED_CHECK(
        r.Max < 1e-3, "tet%d %s: transformed normals off R n0 by %g degrees", tet, fr.Name, r.Max);
    }
    else if (order == 2)
    {
      // the bound of the shading normals on tet10: see Benchmarks/RESULTS.md (live loop)
      HOEMBED_CHECK(s.Median < 0.1 && s.P99 < 1.5 && s.Max < 3.0,
        "tet%d %s: transformed normals off the recomputed ones by median %g, 99th percentile "
        "%g, max %g degrees",
        tet, fr.Name, s.Median, s.P99, s.Max);
    }
    else
    {
      // tet4: F is constant per cell, so the normals turn by a cell's rotation step across
      // its faces (faceted shading at the FE mesh's size)
      HOEMBED_CHECK(s.Median < 0.5 && s.P99 < 12.0 && s.Max < 25.0,
        "tet%d %s: transformed normals off the recomputed ones by median %g, 99th percentile "
        "%g, max %g degrees",
        tet, fr.Name, s.Median, s.P99, s.Max);
    }
  }
  HOEMBED_CHECK(warnings.All.empty(), "tet%d: unexpected warning %s", tet,
    warnings.All.empty() ? "" : warnings.All[0].c_str());
  HOEMBED_CHECK(
    fast->GetNumberOfFoldedPointNormals() == 0, "tet%d: folded normals on a fold-free map", tet);
  // a mirrored mesh (det F < 0 everywhere: the map turns the surface inside out): every
  // normal comes from the polygons, the recompute mode's bits
  {
    auto mirrored = WithDisplacement(Deformed(rest,
                                       [](const double* x, double* y) {
                                         y[0] = x[0];
                                         y[1] = x[1];
                                         y[2] = -x[2];
                                       }),
      rest);
    auto a = run(fast, mirrored);
    auto b = run(slow, mirrored);
    auto* na = vtkFloatArray::SafeDownCast(a->GetPointData()->GetNormals());
    auto* nb = vtkFloatArray::SafeDownCast(b->GetPointData()->GetNormals());
    HOEMBED_CHECK(fast->GetNumberOfFoldedPointNormals() == a->GetNumberOfPoints(),
      "tet%d mirrored: %lld of %lld normals recomputed", tet,
      static_cast<long long>(fast->GetNumberOfFoldedPointNormals()),
      static_cast<long long>(a->GetNumberOfPoints()));
    HOEMBED_CHECK(na && nb &&
        std::memcmp(
          na->GetPointer(0), nb->GetPointer(0), sizeof(float) * 3 * na->GetNumberOfTuples()) == 0,
      "tet%d mirrored: the folded normals are not the recomputed ones", tet);
  }
  // one inverted cell (a corner pushed through the opposite face): the vertices in it get
  // the recomputed normals, bit for bit
  {
    vtkDataArray* cellIds = surface->GetPointData()->GetArray("EmbeddingCellId");
    const vtkIdType cell = static_cast<vtkIdType>(cellIds->GetComponent(0, 0));
    auto bent = Deformed(rest, Bend);
    vtkNew<vtkIdList> ids;
    bent->GetCellPoints(cell, ids);
    double x0[3], x1[3], x2[3], x3[3];
    bent->GetPoint(ids->GetId(0), x0);
    bent->GetPoint(ids->GetId(1), x1);
    bent->GetPoint(ids->GetId(2), x2);
    bent->GetPoint(ids->GetId(3), x3);
    const double c[3] = { (x1[0] + x2[0] + x3[0]) / 3, (x1[1] + x2[1] + x3[1]) / 3,
      (x1[2] + x2[2] + x3[2]) / 3 };
    double y[3];
    for (int d = 0; d < 3; ++d)
      y[d] = c[d] + 1.5 * (c[d] - x0[d]);
    vtkNew<vtkPoints> moved;
    moved->DeepCopy(bent->GetPoints());
    moved->SetPoint(ids->GetId(0), y);
    bent->SetPoints(moved);
    auto mesh = WithDisplacement(bent, rest);
    auto a = run(fast, mesh);
    auto b = run(slow, mesh);
    auto* na = vtkFloatArray::SafeDownCast(a->GetPointData()->GetNormals());
    auto* nb = vtkFloatArray::SafeDownCast(b->GetPointData()->GetNormals());
    vtkIdType inCell = 0, differ = 0;
    for (vtkIdType i = 0; na && nb && i < na->GetNumberOfTuples(); ++i)
    {
      if (static_cast<vtkIdType>(cellIds->GetComponent(i, 0)) != cell)
        continue;
      ++inCell;
      differ += std::memcmp(na->GetPointer(3 * i), nb->GetPointer(3 * i), 3 * sizeof(float)) != 0;
    }
    HOEMBED_CHECK(fast->GetNumberOfInvertedElements() > 0 && inCell > 0 && differ == 0 &&
        fast->GetNumberOfFoldedPointNormals() >= inCell,
      "tet%d one inverted cell: %lld inverted, %lld of its %lld vertices differ from the "
      "recomputed normals, %lld recomputed",
      tet, static_cast<long long>(fast->GetNumberOfInvertedElements()),
      static_cast<long long>(differ), static_cast<long long>(inCell),
      static_cast<long long>(fast->GetNumberOfFoldedPointNormals()));
  }
  // single precision output points: the same normals, the same points as recompute
  fast->SetOutputPointsPrecision(vtkAlgorithm::SINGLE_PRECISION);
  slow->SetOutputPointsPrecision(vtkAlgorithm::SINGLE_PRECISION);
  {
    auto a = run(fast, frames.back().Mesh);
    auto b = run(slow, frames.back().Mesh);
    HOEMBED_CHECK(a->GetPoints()->GetDataType() == VTK_FLOAT && SamePoints(a, b),
      "tet%d: single precision positions differ between the point normal modes", tet);
    HOEMBED_CHECK(Angles(a, b).Max < 25.0, "tet%d: single precision normals off", tet);
  }
  // without Displacement: a warning and the recomputed normals, bit for bit
  {
    auto bare = vtkSmartPointer<vtkUnstructuredGrid>::New();
    bare->ShallowCopy(Deformed(rest, BendTwist));
    warnings.All.clear();
    auto a = run(fast, bare);
    auto b = run(slow, bare);
    bool warned = false;
    for (const auto& w : warnings.All)
      warned = warned || w.find("Displacement") != std::string::npos;
    HOEMBED_CHECK(warned, "tet%d: no warning without Displacement", tet);
    auto* na = vtkFloatArray::SafeDownCast(a->GetPointData()->GetNormals());
    auto* nb = vtkFloatArray::SafeDownCast(b->GetPointData()->GetNormals());
    HOEMBED_CHECK(na && nb &&
        std::memcmp(
          na->GetPointer(0), nb->GetPointer(0), sizeof(float) * 3 * na->GetNumberOfTuples()) == 0,
      "tet%d: without Displacement the normals are not the recomputed ones", tet);
  }
  // the rest surface's points changed (a new surface object): the rest normals follow
  {
    auto moved = vtkSmartPointer<vtkPolyData>::New();
    moved->ShallowCopy(surface);
    vtkNew<vtkPoints> p;
    p->DeepCopy(surface->GetPoints());
    for (vtkIdType i = 0; i < p->GetNumberOfPoints(); ++i)
    {
      double x[3];
      p->GetPoint(i, x);
      x[1] = 1.0 - x[1]; // mirrored: every normal's y flips (and the orientation)
      p->SetPoint(i, x);
    }
    moved->SetPoints(p);
    auto ref = run(slow, frames.front().Mesh); // the original surface's rest normals
    fast->SetInputData(0, moved);
    auto a = run(fast, frames.front().Mesh); // at rest: the mirrored surface's rest normals
    auto* na = vtkFloatArray::SafeDownCast(a->GetPointData()->GetNormals());
    auto* nr = vtkFloatArray::SafeDownCast(ref->GetPointData()->GetNormals());
    double worst = 0.0;
    for (vtkIdType i = 0; na && nr && i < na->GetNumberOfTuples(); ++i)
    {
      // mirrored in y, and the triangles' orientation reversed: n -> (-nx, ny, -nz)
      worst = std::max({ worst, std::fabs(na->GetComponent(i, 0) + nr->GetComponent(i, 0)),
        std::fabs(na->GetComponent(i, 1) - nr->GetComponent(i, 1)),
        std::fabs(na->GetComponent(i, 2) + nr->GetComponent(i, 2)) });
    }
    HOEMBED_CHECK(na && nr && worst < 1e-5,
      "tet%d: the rest normals did not follow the surface's new points (%g)", tet, worst);
    fast->SetInputData(0, surface);
    auto back = run(fast, frames.front().Mesh);
    HOEMBED_CHECK(
      Angles(back, ref).Max < 1e-3, "tet%d: rest normals not rebuilt for the surface", tet);
  }
}
} // namespace

int main(int, char*[])
{
  for (int order : { 2, 1 })
  {
    TestKernel(order);
    TestKernelSimd(order);
    TestFilter(order);
  }
  return Report("TestTransferShadingNormals");
}
