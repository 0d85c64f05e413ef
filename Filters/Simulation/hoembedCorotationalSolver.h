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
 * Linear solver: preconditioned conjugate gradients on the exact step system, stopped at
 * |r| <= tol * max(|b|, dt |f_ext|) (vtkCorotationalFEMStepper's default tol is 1e-4:
 * on a 3000-tet10 beam, 60 steps, the displacements then differ from a 1e-10 solve by
 * ~2e-6 relative; Benchmarks/bench_stepper.py reports it for every mesh it times).
 * - Products (hoembedCorotationalSolverAssembly.cxx). Meshes of 1000 cells or more: the
 *   rotated stiffness S = sum_e R_e K_e R_e^T is assembled every step into 3x3 node blocks
 *   on the node-adjacency pattern (upper element blocks R K_ab R^T, b >= a, added with
 *   their transposes; the elastic forces come from the same pass over K_e), and a
 *   product is a block-row sweep y = cM M p + cK S p (one 3x3 block per neighbour instead
 *   of a 30x30 element matrix per element: ~5x less memory traffic). Smaller meshes keep
 *   the element-by-element products (their element matrices stay in cache; assembling S
 *   every step costs more there than it saves).
 * - Initial guess (large meshes): the Galerkin projection of the step system onto the
 *   span of the last 4 solutions dv (the A-norm-best combination, which contains the
 *   previous dv and its polynomial extrapolations; 4 products, and its residual is the
 *   CG's first). About halves the iterations (3000 tet10 beam at 1e-4: 4.75 -> 2.5).
 *   Smaller meshes start from the previous dv.
 * - Preconditioner P^-1 = Q A_f^-1 Q^T: a sparse Cholesky factor A_f rotated by the
 *   averaged nodal rotations Q. A_f is first the unrotated system matrix (factorised once
 *   per dt / damping / material / clamps; exact for a rigid rotation of the whole body);
 *   when the CG iterations since the last factorisation exceed an estimate of its cost
 *   (deterministic: 0.25 n^(2/3) iterations for n DOF, within [10, 500]) and the
 *   iteration count per step has grown by half, the current matrix (cM M + cK S) is
 *   factorised instead (symbolic analysis reused) and Q becomes the rotation relative to
 *   that state. Factor: of the matrix permuted by a node-level fill-reducing ordering (a
 *   node's 3 DOFs stay together), Eigen's SimplicialLLT on an AMD ordering below 6000
 *   DOF, SuiteSparse CHOLMOD (supernodal; AMD, METIS or CHOLMOD's nested dissection,
 *   whichever fills least) above when the build found it; the factor is then copied into
 *   3x3 node blocks (hoembedCorotationalBlockFactor.cxx), rows scaled to a unit diagonal
 *   of L L^T, stored as 3 padded columns for AVX2 (double below 6000 DOF; above, half
 *   precision where the CPU has F16C, else float; arithmetic always double, so the
 *   preconditioner is the exact inverse of a fixed SPD matrix: the 3000-tet10 beam needs
 *   the same iterations with half as with float storage). The triangular solves of the
 *   large factor run on two threads: the elimination tree is cut below its top separator
 *   into two groups of independent subtrees of equal work.
 *
 * Background factorisation (SetBackgroundFactorization; vtkCorotationalFEMStepper's
 * BackgroundFactorization in LiveMode): a grab or a release changes the prescribed set,
 * and the synchronous rule above refactorises at that step, many ordinary steps' worth of
 * time (Benchmarks/RESULTS.md, live loop): the interactive model froze at every click.
 * With it, that factorisation (and the refresh of
 * a drifted factor) runs on a worker thread, on the step matrix of the step that asked
 * for it (rotated, like a refresh), while the CG keeps a factor it has as preconditioner:
 * the current one when its free DOFs contain the new ones (a grab: restricted to them it
 * is a principal submatrix of an SPD inverse, so still SPD, and off the exact inverse by
 * a term of rank at most the DOFs that left), else the last factor made without
 * prescribed nodes (kept for that: its free DOFs contain every prescribed set's; a
 * release). Each step is still solved to the tolerance; only the iterations differ (a
 * few more while the stand-in serves). The new factor is swapped in between steps only:
 * at the first step after the worker is done, or, with a lag, exactly that many steps
 * after it was asked for (waited for then: results independent of timing). A set that
 * changes again before its factor is ready makes the job stale (dropped, or kept as the
 * newer unprescribed factor); one job at a time. The worker runs at the lowest priority
 * (Linux), so that it takes the cycles the steps leave rather than half of theirs. Static
 * solves, and the first step, stay synchronous.
 *
 * StaticSolve: solves f_int(x) = f_ext by repeated linearised solves (the first one is
 * exactly small-strain linear elasticity from the rest state), needs clamped nodes.
 *
 * Prescribed motion (SetPrescribedMotion; for interactive use, changed between steps):
 * hard Dirichlet conditions, not penalty springs. A step first puts the prescribed
 * DOFs on their targets (velocity w_c = (X_c + u_c - x_c) / dt over the step), then
 * makes the usual backward Euler step of the free DOFs linearised at that configuration
 * (rotations and forces there; the damping and inertia coupling of w_c moved to the
 * right-hand side). For a linear material this is exactly backward Euler with moving
 * Dirichlet values (tested against scikit-fem); linearising after the move, not before,
 * is what keeps a large drag in one step stable (linearised before it, the elements
 * next to the dragged nodes see the move extrapolated by (dt + beta) / dt and the
 * step blew up in tests). A target reached is exact (no penalty stiffness to tune, no
 * stiff spring that would make the step matrix ill-conditioned); a jump of the target is
 * a velocity kick that the implicit step damps, and the one linearised solve per step
 * overshoots when the drag rotates elements by tens of degrees in one step (a single
 * node of a soft 4 x 1 x 1 beam pulled by 0.8 element sizes per step kept its energy
 * bounded but needed the CG's iteration cap every step; by 0.4 per step, 5-80
 * iterations). SetPrescribedSpeedLimit bounds that: an interactive driver sets it to a
 * fraction of an element size per step, and a target that jumps is then approached at
 * that speed. The prescribed DOFs leave the system exactly like clamped
 * ones: changing the targets keeps the factorised preconditioner, changing the mask
 * refactorises at the next step (or in the background, below). Loads and targets can
 * change between steps: the state (x, v) is kept. SolveStatic puts the prescribed nodes
 * on their targets and holds them.
 *
 * Hyperelastic materials (SetMaterial: StVK, stable Neo-Hookean, Mooney-Rivlin;
 * hoembedHyperelasticMaterial.h; hoembedHyperelasticSolver.cxx): a step minimises the
 * backward-Euler incremental potential
 *   Phi(x) = 1/(2 dt^2) |x - x_n - dt v_n|_M^2 + alpha/(2 dt) |x - x_n|_M^2
 *          + beta/(2 dt) (x - x_n)^T K_n (x - x_n) + Psi(x) - f_ext^T x
 * (K_n: the projected Hessian of Psi at the step's start, so the Rayleigh damping matches
 * the co-rotated step's to first order), v_{n+1} = (x_{n+1} - x_n) / dt; SolveStatic
 * minimises Psi(x) - f_ext^T x. Held DOFs (clamped, prescribed on their speed-limited
 * targets) stay put. Newton: the exact Hessian (quadratic convergence), or, where that is
 * not positive definite, the Hessian of the per-quadrature-point tangents with their
 * negative eigenvalues clamped (positive semi-definite element Hessians, so the direction
 * is a descent direction); a backtracking Armijo line search on Phi that also refuses
 * any state inverting a cell that was not inverted (det F <= 0 at a quadrature point, or
 * the straight tet of a tet10's corners turned over: the stable Neo-Hookean has no
 * barrier), and held DOFs whose move would invert a cell move only part of the way (by
 * halves; they catch up in the next steps). Linear systems: time steps, CG to the
 * solver's relative tolerance (SetSolverControls) preconditioned by the co-rotated
 * step's node-block factor (the preconditioner above) of an earlier Newton system, rotated by the
 * nodal rotations since, from the Galerkin projection onto the last 4 directions (a new factor when
 * the free DOFs or dt change, or after 40 iterations or at negative curvature); static solves, a
 * sparse Cholesky factor (CHOLMOD supernodal when the build has it, else Eigen's simplicial LLT),
 * or CG preconditioned by the last one (to 1e-6 relative; a new factor after 25 iterations, at
 * negative curvature or when the free set changed). Psi is integrated with the symmetric 4-point
 * rule of degree 2 on tet10 (exact for the small-strain stiffness of a straight tet10), the
 * centroid on tet4.
 *
 * Threading (vtkSMPTools; and one std::thread for the background factorisation, which
 * touches nothing but its own factor object until it is joined): rotations, the
 * assembly of S (two halves of the cells cut by
 * a plane, without common nodes, in parallel, then the layer of cells along the cut; on
 * one thread all cells in order, so 1- and 2-thread runs differ in the last bits of S),
 * products (block rows), the two subtree groups of the triangular solves. Small meshes
 * (< 1000 cells) run serially.
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
    long long Iterations = 0;     ///< total CG iterations
    long long Factorizations = 0; ///< numeric factorisations of the preconditioner
    double Factorization = 0.0;   ///< seconds in them (part of Solve)
    /// factors computed by the background worker and taken (SetBackgroundFactorization)
    long long BackgroundFactorizations = 0;
    double BackgroundFactorization = 0.0; ///< the worker's seconds for the jobs finished
  };

  /// Bytes one step's CG reads at the least (arrays read once, vectors not counted):
  /// per product with the step matrix (its blocks, or the element matrices on small
  /// meshes; the mass), per preconditioner application (the factor in use, both
  /// triangular solves), per assembly (the element matrices read, the blocks written),
  /// and the products of the initial-guess projection (GuessProducts per step).
  struct Traffic
  {
    long long ProductBytes = 0;
    long long PreconditionerBytes = 0;
    long long AssemblyBytes = 0;
    int GuessProducts = 0;
  };
  Traffic GetTraffic() const;

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
  /// Prescribed motion: mask per point (nonzero = prescribed; nullptr = none) and target
  /// displacements from rest (3 per point, read where the mask is set). Points clamped by
  /// SetFixed stay clamped. Takes effect at the next Step / SolveStatic; the state is kept.
  void SetPrescribedMotion(const unsigned char* mask, const double* targetDisplacements);
  /// Speed limit of the prescribed points (distance per unit time, <= 0: none): a point
  /// farther from its target than speed * dt moves that far towards it in a step.
  void SetPrescribedSpeedLimit(double speed);
  /// Background factorisation, for interactive loops (off by default; see the header's
  /// "Background factorisation"). `lag` 0: a new factor is taken at the first step after
  /// the worker is done (when depends on timing); lag > 0: exactly `lag` steps after it
  /// was asked for, waiting for it then if needed (deterministic: for tests, benchmarks).
  void SetBackgroundFactorization(bool on, int lag = 0);
  /// Number of points with prescribed motion.
  long long GetNumberOfPrescribedPoints() const;
  /// Gravity (consistent body force density * g) plus optional nodal forces (3 per point).
  void SetExternalForces(const double gravity[3], const double* nodalForces);
  void SetTimeStep(double dt);
  void SetRayleighDamping(double alpha, double beta);
  void SetSolverControls(double relativeTolerance, int maxIterations);
  /// The material (hoembedHyperelasticMaterial.h's Material as an int; after Initialize,
  /// which resets it to Corotated): a hyperelastic one makes Step and SolveStatic Newton
  /// solves (see "Hyperelastic materials" above) with the law's constants from the
  /// Initialize's E and nu (and c10, c01 for Mooney-Rivlin; both 0: from E, nu).
  void SetMaterial(int material, double c10, double c01);
  /// Newton's stop rule (hyperelastic materials): the largest DOF change of an iteration
  /// <= tolerance times the largest displacement since the start of the step (or solve);
  /// a step stops after maxIterations (1: one linearised step per time step, the
  /// interactive choice), a static solve fails then.
  void SetNewtonControls(double tolerance, int maxIterations);
  /// Newton iterations of the last step or static solve (hyperelastic materials).
  int GetLastNewtonIterations() const;

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

  /// The solver's state (hoembedCorotationalSolverImpl.h); named here so that the steps
  /// of Initialize can be plain functions over it.
  struct Impl;

private:
  std::unique_ptr<Impl> P;
};
} // namespace hoembed

#endif
