/**
 * @file hoembedCorotationalSolver.h
 * @brief Co-rotated linear elasticity on tet4 / tet10 meshes with implicit Euler steps.
 *
 * Plain C++ kernel (no VTK pipeline code; Eigen stays in the .cxx).
 *
 * Mechanics: each element e keeps its rest stiffness K_e (hoembedTetElementMatrices.h)
 * and, at every step, the rotation R_e of the polar decomposition of its deformation
 * gradient at the centroid (scaled Newton iteration; SVD with a sign fix for inverted or
 * nearly flat elements, so it stays stable through inversion). The
 * elastic force is f_e = R_e K_e (R_e^T x_e - X_e) (zero for any rigid motion) and the
 * tangent is approximated by R_e K_e R_e^T. Damping is Rayleigh, C = alpha M + beta K~.
 *
 * Time stepping: backward Euler with one linearised solve per step,
 *   (M (1 + dt alpha) + K~ (dt beta + dt^2)) dv
 *       = dt (f_ext - f_int(x_n) - alpha M v_n - (beta + dt) K~ v_n),
 *   v_{n+1} = v_n + dv,  x_{n+1} = x_n + dt v_{n+1}.
 * Clamped DOFs keep dv = 0 (their position stays where the state put them).
 *
 * Linear solver: conjugate gradients on the exact step system, warm-started from the
 * previous step's dv, with matrix-free products (element by element: R_e K_e R_e^T p_e,
 * plus the mass), preconditioned by a sparse Cholesky factor rotated by the averaged
 * nodal rotations Q: P^-1 = Q A_f^-1 Q^T. A_f is first the unrotated system matrix
 * (factorised once per dt / damping / material / clamps; exact for a rigid rotation of
 * the whole body); when the CG iterations since the last factorisation exceed an
 * estimate of its cost (deterministic: 0.25 n^(2/3) iterations for n DOF, within
 * [10, 500]) and the iteration count per step has grown by half, the current matrix is
 * assembled (fixed
 * pattern, element-to-CSR gather map built once) and factorised instead (symbolic
 * analysis reused), and Q becomes the rotation relative to that state. Factor: of the
 * matrix permuted by a node-level fill-reducing ordering (a node's 3 DOFs stay together),
 * Eigen's SimplicialLLT on an AMD ordering below 6000 DOF, SuiteSparse CHOLMOD
 * (supernodal, METIS or AMD, whichever fills less) above when the build found it; the
 * factor is then copied into 3x3 node blocks (float values above 6000 DOF, double
 * arithmetic) for the triangular solves. The CG stops at |r| <= tol * max(|b|, dt |f_ext|).
 *
 * StaticSolve: solves f_int(x) = f_ext by repeated linearised solves (the first one is
 * exactly small-strain linear elasticity from the rest state), needs clamped nodes.
 *
 * Threading: element loops and the assembly gather run with vtkSMPTools; the scatter of
 * element vectors is serial.
 */
#ifndef hoembedCorotationalSolver_h
#define hoembedCorotationalSolver_h

#include "hoembedFiltersSimulationModule.h"

#include <memory>
#include <string>

namespace hoembed
{
class HOEMBEDFILTERSSIMULATION_EXPORT CorotationalSolver
{
public:
  struct Timings
  {
    double Rotation = 0.0; ///< seconds in polar decompositions (element + nodal)
    double Assembly = 0.0; ///< seconds rotating element matrices, forces, scatter
    double Solve = 0.0;    ///< seconds in the preconditioned CG (and factorisation)
    long long Steps = 0;
    long long Iterations = 0; ///< total CG iterations
    long long Factorizations = 0; ///< numeric factorisations of the preconditioner
    double Factorization = 0.0;   ///< seconds in them (part of Solve)
  };

  CorotationalSolver();
  ~CorotationalSolver();
  CorotationalSolver(const CorotationalSolver&) = delete;
  CorotationalSolver& operator=(const CorotationalSolver&) = delete;

  /**
   * Build element matrices and the sparsity pattern. nodesPerCell is 4 or 10;
   * connectivity holds nodesPerCell ids per cell; restPoints 3 doubles per point.
   * Returns false with `error` set (and `badCell` >= 0 when a cell is at fault).
   */
  bool Initialize(int nodesPerCell, long long numberOfCells, const long long* connectivity,
    long long numberOfPoints, const double* restPoints, double young, double poisson,
    double density, bool lumpedMass, std::string& error, long long& badCell);

  /// Per-point clamp flags (nonzero = clamped), or nullptr for none.
  void SetFixed(const unsigned char* fixed);
  /// Gravity (consistent body force density * g) plus optional nodal forces (3 per point).
  void SetExternalForces(const double gravity[3], const double* nodalForces);
  void SetTimeStep(double dt);
  void SetRayleighDamping(double alpha, double beta);
  void SetSolverControls(double relativeTolerance, int maxIterations);

  /// Back to rest: x = X, v = 0.
  void ResetState();
  /// Set positions and velocities (3 doubles per point each; either may be nullptr).
  void SetState(const double* positions, const double* velocities);

  /// One implicit Euler step. False if the state became non-finite (state is kept).
  bool Step();
  /// Static equilibrium. False with error set (no clamps, non-finite, no convergence).
  bool SolveStatic(int maxIterations, double tolerance, std::string& error);

  long long GetNumberOfPoints() const;
  long long GetNumberOfCells() const;
  const double* GetPositions() const;
  const double* GetVelocities() const;
  const double* GetRestPositions() const;
  /// Row-major 3x3 per point: polar projection of the average of the element
  /// rotations around the point (identity for a point in no cell).
  void ComputeNodalRotations(double* rotations) const;
  /// von Mises stress of the co-rotated small-strain stress at each cell centroid.
  void ComputeVonMises(double* stress) const;
  /// Kinetic energy 1/2 v^T M v and co-rotated strain energy 1/2 u^T K u summed over cells.
  double KineticEnergy() const;
  double StrainEnergy() const;
  /// Total mass (sum of the mass matrix over one component).
  double TotalMass() const;

  const Timings& GetTimings() const;
  void ResetTimings();
  int GetLastIterations() const;
  double GetLastRelativeResidual() const;

private:
  struct Impl;
  std::unique_ptr<Impl> P;
};
} // namespace hoembed

#endif
