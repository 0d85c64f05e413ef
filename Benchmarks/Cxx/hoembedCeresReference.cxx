#include "hoembedCeresReference.h"

#include "vtkGenericCell.h"
#include "vtkHigherOrderHexahedron.h"
#include "vtkHigherOrderQuadrilateral.h"
#include "vtkPoints.h"

#include <ceres/ceres.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <array>
#include <cmath>
#include <map>
#include <numeric>

namespace hoembed_ceres
{
namespace
{
/// Whether InterpolateDerivs writes dN_i/dr_k at i * dim + k (VTK 9.1's Lagrange
/// quadrilaterals and hexahedra) instead of VTK's usual k * n + i: decided against central
/// differences of InterpolateFunctions at an interior point, so that any VTK version's
/// layout is read right.
bool DerivativesInterleaved(vtkCell* cell)
{
  const int n = static_cast<int>(cell->GetNumberOfPoints());
  const int dim = cell->GetCellDimension();
  const double pc[3] = { 0.21, 0.17, 0.13 };
  std::vector<double> d(dim * n), wp(n), wm(n);
  cell->InterpolateDerivs(pc, d.data());
  double errBlocked = 0.0, errInterleaved = 0.0;
  const double h = 1e-5;
  for (int k = 0; k < dim; ++k)
  {
    double a[3] = { pc[0], pc[1], pc[2] }, b[3] = { pc[0], pc[1], pc[2] };
    a[k] += h;
    b[k] -= h;
    cell->InterpolateFunctions(a, wp.data());
    cell->InterpolateFunctions(b, wm.data());
    for (int i = 0; i < n; ++i)
    {
      const double fd = (wp[i] - wm[i]) / (2 * h);
      errBlocked = std::max(errBlocked, std::fabs(d[k * n + i] - fd));
      errInterleaved = std::max(errInterleaved, std::fabs(d[i * dim + k] - fd));
    }
  }
  return errInterleaved < errBlocked;
}

CeresPiece MakePiece(vtkCell* cell)
{
  CeresPiece piece;
  piece.Cell = vtkSmartPointer<vtkCell>::Take(cell->NewInstance());
  piece.Cell->DeepCopy(cell);
  // Higher-order cells: simplices take their order from the number of points, tensor
  // cells from their source (a grid's cell data or the cell the face came from).
  piece.Cell->Initialize();
  if (auto* hex = vtkHigherOrderHexahedron::SafeDownCast(cell))
  {
    const int* o = hex->GetOrder();
    vtkHigherOrderHexahedron::SafeDownCast(piece.Cell)->SetOrder(o[0], o[1], o[2]);
  }
  if (auto* quad = vtkHigherOrderQuadrilateral::SafeDownCast(cell))
  {
    const int* o = quad->GetOrder();
    vtkHigherOrderQuadrilateral::SafeDownCast(piece.Cell)->SetOrder(o[0], o[1]);
  }
  const vtkIdType n = cell->GetNumberOfPoints();
  piece.Nodes.resize(3 * n);
  for (vtkIdType i = 0; i < n; ++i)
    cell->GetPoints()->GetPoint(i, &piece.Nodes[3 * i]);
  piece.InterleavedDerivatives = DerivativesInterleaved(piece.Cell);
  return piece;
}

void GrowBox(CeresPiece& piece, double margin)
{
  const vtkIdType n = static_cast<vtkIdType>(piece.Nodes.size() / 3);
  double lo[3] = { HUGE_VAL, HUGE_VAL, HUGE_VAL }, hi[3] = { -HUGE_VAL, -HUGE_VAL, -HUGE_VAL };
  for (vtkIdType i = 0; i < n; ++i)
    for (int d = 0; d < 3; ++d)
    {
      lo[d] = std::min(lo[d], piece.Nodes[3 * i + d]);
      hi[d] = std::max(hi[d], piece.Nodes[3 * i + d]);
    }
  const double diag = std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) +
    (hi[1] - lo[1]) * (hi[1] - lo[1]) + (hi[2] - lo[2]) * (hi[2] - lo[2]));
  piece.Size = diag;
  for (int d = 0; d < 3; ++d)
  {
    piece.Box[2 * d] = lo[d] - margin * diag;
    piece.Box[2 * d + 1] = hi[d] + margin * diag;
  }
}

double BoxDistance(const double box[6], const double q[3])
{
  double s = 0.0;
  for (int d = 0; d < 3; ++d)
  {
    const double e = std::max({ box[2 * d] - q[d], 0.0, q[d] - box[2 * d + 1] });
    s += e * e;
  }
  return std::sqrt(s);
}

/// The parameters (in [0, 1]^dim) to VTK's parametric coordinates and their derivative
/// (row: parametric coordinate, column: parameter). Simplices go through the collapsed
/// cube so that their constraints are bounds.
void ToParametric(bool simplex, int dim, const double* a, double pc[3], double dpc[3][3])
{
  for (int i = 0; i < 3; ++i)
  {
    pc[i] = 0.0;
    for (int j = 0; j < 3; ++j)
      dpc[i][j] = i == j ? 1.0 : 0.0;
  }
  for (int i = 0; i < dim; ++i)
    pc[i] = a[i];
  if (!simplex)
    return;
  if (dim == 2)
  {
    pc[1] = (1.0 - a[0]) * a[1];
    dpc[1][0] = -a[1];
    dpc[1][1] = 1.0 - a[0];
  }
  else
  {
    pc[1] = (1.0 - a[0]) * a[1];
    pc[2] = (1.0 - a[0]) * (1.0 - a[1]) * a[2];
    dpc[1][0] = -a[1];
    dpc[1][1] = 1.0 - a[0];
    dpc[2][0] = -(1.0 - a[1]) * a[2];
    dpc[2][1] = -(1.0 - a[0]) * a[2];
    dpc[2][2] = (1.0 - a[0]) * (1.0 - a[1]);
  }
}

/// x(params) - q, with the Jacobian, evaluated by VTK's cell.
class PieceResidual : public ceres::CostFunction
{
public:
  PieceResidual(const CeresPiece& piece, const double q[3])
    : Piece(piece), Dim(piece.Cell->GetCellDimension()),
      N(static_cast<int>(piece.Nodes.size() / 3)), Weights(N), Derivs(3 * N)
  {
    std::copy(q, q + 3, this->Q);
    this->set_num_residuals(3);
    this->mutable_parameter_block_sizes()->push_back(this->Dim);
  }

  void Point(const double* a, double x[3], double dx[3][3]) const
  {
    double pc[3], dpc[3][3];
    ToParametric(this->Piece.Simplex, this->Dim, a, pc, dpc);
    this->Piece.Cell->InterpolateFunctions(pc, this->Weights.data());
    if (dx)
      this->Piece.Cell->InterpolateDerivs(pc, this->Derivs.data());
    double dxdpc[3][3] = { { 0, 0, 0 }, { 0, 0, 0 }, { 0, 0, 0 } };
    for (int d = 0; d < 3; ++d)
      x[d] = 0.0;
    for (int i = 0; i < this->N; ++i)
    {
      const double* X = &this->Piece.Nodes[3 * i];
      for (int d = 0; d < 3; ++d)
      {
        x[d] += this->Weights[i] * X[d];
        if (dx)
          for (int k = 0; k < this->Dim; ++k)
            dxdpc[d][k] +=
              this
                ->Derivs[this->Piece.InterleavedDerivatives ? i * this->Dim + k : k * this->N + i] *
              X[d];
      }
    }
    if (dx)
      for (int d = 0; d < 3; ++d)
        for (int j = 0; j < this->Dim; ++j)
        {
          dx[d][j] = 0.0;
          for (int k = 0; k < this->Dim; ++k)
            dx[d][j] += dxdpc[d][k] * dpc[k][j];
        }
  }

  bool Evaluate(
    double const* const* parameters, double* residuals, double** jacobians) const override
  {
    double x[3], dx[3][3];
    const bool wantJ = jacobians && jacobians[0];
    this->Point(parameters[0], x, wantJ ? dx : nullptr);
    for (int d = 0; d < 3; ++d)
      residuals[d] = x[d] - this->Q[d];
    if (wantJ)
      for (int d = 0; d < 3; ++d)
        for (int j = 0; j < this->Dim; ++j)
          jacobians[0][d * this->Dim + j] = dx[d][j];
    return true;
  }

private:
  const CeresPiece& Piece;
  int Dim;
  int N;
  double Q[3];
  mutable std::vector<double> Weights;
  mutable std::vector<double> Derivs;
};

/// The best of the multi-start bounded LM runs on one piece: the distance and its point.
double SolvePiece(const CeresPiece& piece, const double q[3], const CeresOptions& options,
  double stopBelow, double farBeyond, double point[3], int& iterations)
{
  PieceResidual residual(piece, q);
  const int dim = piece.Cell->GetCellDimension();
  const int k = std::max(1, dim == 3 ? options.CellStartsPerDirection : options.StartsPerDirection);
  int starts = 1;
  for (int d = 0; d < dim; ++d)
    starts *= k;
  ceres::Solver::Options so;
  so.minimizer_type = ceres::TRUST_REGION;
  so.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  so.linear_solver_type = ceres::DENSE_QR;
  so.max_num_iterations = options.MaxIterations;
  so.function_tolerance = 1e-15;
  so.gradient_tolerance = 1e-16;
  so.parameter_tolerance = 1e-15;
  so.logging_type = ceres::SILENT;
  so.minimizer_progress_to_stdout = false;
  so.num_threads = 1;
  double best = HUGE_VAL;
  // The middle first; the grid of starts only when the middle's answer is not clearly far
  // (a cell or face whose nearest point lies a fifth of its size or more beyond the best
  // distance wanted cannot change the answer, and most candidates are such).
  for (int s = -1; s < starts; ++s)
  {
    // the middle: a hexahedron's or quadrilateral's centre, or the collapsed cube's
    // preimage of a simplex's centroid
    double a[3] = { 0.5, 0.5, 0.5 };
    if (piece.Simplex)
    {
      a[0] = dim == 2 ? 1.0 / 3.0 : 0.25;
      a[1] = dim == 2 ? 0.5 : 1.0 / 3.0;
    }
    for (int d = 0, r = s; s >= 0 && d < dim; ++d, r /= k)
      a[d] = (r % k + 0.5) / k;
    ceres::Problem::Options po;
    po.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    ceres::Problem problem(po);
    problem.AddResidualBlock(&residual, nullptr, a);
    for (int d = 0; d < dim; ++d)
    {
      problem.SetParameterLowerBound(a, d, 0.0);
      problem.SetParameterUpperBound(a, d, 1.0);
    }
    ceres::Solver::Summary summary;
    ceres::Solve(so, &problem, &summary);
    iterations += static_cast<int>(summary.iterations.size());
    if (std::getenv("HOEMBED_CERES_DEBUG"))
      std::fprintf(stderr, "dim %d start %d: %zu iterations, %s, cost %.3e\n", dim, s,
        summary.iterations.size(), ceres::TerminationTypeToString(summary.termination_type),
        summary.final_cost);
    double x[3];
    residual.Point(a, x, nullptr);
    const double dist = std::sqrt((x[0] - q[0]) * (x[0] - q[0]) + (x[1] - q[1]) * (x[1] - q[1]) +
      (x[2] - q[2]) * (x[2] - q[2]));
    if (dist < best)
    {
      best = dist;
      std::copy(x, x + 3, point);
    }
    if (best <= stopBelow || (s < 0 && best > farBeyond + 0.2 * piece.Size))
      break;
  }
  return best;
}
} // namespace

std::string CeresMesh::Build(vtkUnstructuredGrid* grid, const CeresOptions& options)
{
  this->Faces.clear();
  this->Cells.clear();
  if (!grid || grid->GetNumberOfCells() == 0 || !grid->GetPoints())
    return "the mesh has no cells";
  double b[6];
  grid->GetPoints()->GetBounds(b);
  this->Diagonal = std::sqrt(
    (b[1] - b[0]) * (b[1] - b[0]) + (b[3] - b[2]) * (b[3] - b[2]) + (b[5] - b[4]) * (b[5] - b[4]));
  vtkNew<vtkGenericCell> generic;
  // Faces by their sorted corner ids: those met once are on the boundary.
  std::map<std::array<vtkIdType, 4>, std::pair<int, std::pair<vtkIdType, int>>> seen;
  for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c)
  {
    grid->GetCell(c, generic);
    vtkCell* cell = generic->GetRepresentativeCell();
    if (cell->GetCellDimension() != 3)
      return "cell " + std::to_string(c) + " is not a 3D cell";
    this->Cells.push_back(MakePiece(cell));
    this->Cells.back().Source = c;
    this->Cells.back().Simplex = cell->GetNumberOfFaces() == 4;
    GrowBox(this->Cells.back(), options.BoxMargin);
    for (int f = 0; f < cell->GetNumberOfFaces(); ++f)
    {
      vtkCell* face = cell->GetFace(f);
      const int corners = face->GetNumberOfEdges();
      std::array<vtkIdType, 4> key = { -1, -1, -1, -1 };
      for (int i = 0; i < corners; ++i)
        key[i] = face->GetPointId(i);
      std::sort(key.begin(), key.begin() + corners);
      auto it = seen.find(key);
      if (it == seen.end())
        seen.emplace(key, std::make_pair(1, std::make_pair(c, f)));
      else
        ++it->second.first;
    }
  }
  for (const auto& entry : seen)
  {
    if (entry.second.first != 1)
      continue;
    const vtkIdType c = entry.second.second.first;
    const int f = entry.second.second.second;
    grid->GetCell(c, generic);
    vtkCell* face = generic->GetRepresentativeCell()->GetFace(f);
    this->Faces.push_back(MakePiece(face));
    CeresPiece& piece = this->Faces.back();
    piece.Simplex = face->GetNumberOfEdges() == 3;
    piece.Source = c;
    piece.LocalFace = f;
    GrowBox(piece, options.BoxMargin);
  }
  return std::string();
}

void CeresDistance(
  const CeresMesh& mesh, const double q[3], const CeresOptions& options, CeresResult& result)
{
  result = CeresResult();
  double point[3];
  const double insideTol = options.InsideTolerance * mesh.Diagonal;
  for (const CeresPiece& cell : mesh.Cells)
  {
    if (BoxDistance(cell.Box, q) > 0.0)
      continue;
    ++result.CellsSolved;
    if (SolvePiece(cell, q, options, insideTol, insideTol, point, result.Iterations) <= insideTol)
    {
      result.Inside = true;
      result.Distance = 0.0;
      result.Cell = cell.Source;
      std::copy(q, q + 3, result.Point);
      return;
    }
  }
  std::vector<std::pair<double, std::size_t>> order(mesh.Faces.size());
  for (std::size_t f = 0; f < mesh.Faces.size(); ++f)
    order[f] = { BoxDistance(mesh.Faces[f].Box, q), f };
  std::sort(order.begin(), order.end());
  double best = HUGE_VAL;
  for (const auto& entry : order)
  {
    if (entry.first >= best)
      break;
    const CeresPiece& face = mesh.Faces[entry.second];
    ++result.FacesSolved;
    const double d = SolvePiece(face, q, options, -1.0, best, point, result.Iterations);
    if (d < best)
    {
      best = d;
      result.Cell = face.Source;
      result.LocalFace = face.LocalFace;
      std::copy(point, point + 3, result.Point);
    }
  }
  result.Distance = best;
}
} // namespace hoembed_ceres
