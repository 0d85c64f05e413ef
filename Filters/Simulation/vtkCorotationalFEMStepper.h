/**
 * @class   vtkCorotationalFEMStepper
 * @brief   co-rotated linear elasticity of a tet10 / tet4 mesh, stepped in time
 *
 * Input: the rest FE mesh, a vtkUnstructuredGrid of VTK_QUADRATIC_TETRA cells (or
 * VTK_TETRA cells, the linear baseline; not mixed). Optional input point data:
 * - `Fixed` (any numeric type, nonzero = clamped node; the name is FixedArrayName);
 * - ExternalForceArrayName: 3-component nodal forces (N), added to gravity;
 * - InitialDisplacementArrayName / InitialVelocityArrayName: 3-component initial state
 *   (default: the body starts at rest with zero velocity).
 * Nodes can also be clamped without arrays: every node on the negative side of (or on)
 * the plane ClampPlaneOrigin/ClampPlaneNormal when UseClampPlane is on, and every node
 * inside ClampBox when UseClampBox is on (a tolerance of 1e-9 of the mesh size applies).
 *
 * Output: the deformed mesh (same points order and cells as the input) with point data
 * `Displacement` (x - X), `Velocity`, `NodalRotation` (9 doubles, row-major: the polar
 * projection of the average of the element rotations around the node) and cell data
 * `VonMisesStress` (co-rotated small-strain stress at the centroid); field data
 * `KineticEnergy`, `StrainEnergy` and `SolverIterations` (of the last step); the stress
 * and the energies only with ComputeDiagnostics on (default). Input point
 * and cell data are passed.
 *
 * Mechanics (see hoembedCorotationalSolver.h): isotropic linear elasticity, element
 * rotations by polar decomposition of the centroid deformation gradient (scaled Newton
 * iteration; SVD with sign fix for inverted elements, so it stays stable through them),
 * rotated stiffness R K R^T, consistent mass (or HRZ-lumped with LumpedMass on) and
 * consistent body force, Rayleigh damping
 * C = RayleighMass * M + RayleighStiffness * K, backward Euler with one linearised solve
 * per step (conjugate gradients; products with the step matrix assembled in 3x3 node
 * blocks every step on meshes of 1000 cells or more, element by element below; initial
 * guess projected on the last solutions; preconditioned by a rotated sparse Cholesky
 * factor that is reused across steps and refreshed when that pays; the factor is Eigen's
 * SimplicialLLT, or SuiteSparse CHOLMOD for systems of 6000 DOF or more when the build
 * found it, applied through 3x3 node blocks, on two threads for large systems; see
 * hoembedCorotationalSolver.h). The kernels are
 * compiled with -march=native unless HOEMBED_SIMULATION_NATIVE is off.
 *
 * Time: RequestInformation advertises TIME_STEPS t_k = k * TimeStep, k = 0..
 * NumberOfTimeSteps, and TIME_RANGE. RequestData integrates from the cached state to the
 * requested UPDATE_TIME_STEP (rounded to a step): sequential frames cost one step each, a
 * request for an earlier time restarts from the initial state. With StaticSolve on, the
 * output is the static equilibrium under the loads (the same for every time); it needs
 * clamped nodes.
 *
 * Defaults: YoungModulus 1e5 (Pa), PoissonRatio 0.49, Density 1000 (kg/m^3), Gravity
 * (0, 0, -9.81), RayleighMass 0.1 (1/s), RayleighStiffness 0.01 (s), TimeStep 0.01 (s),
 * NumberOfTimeSteps 100, StaticSolve off, LumpedMass off, SolverTolerance 1e-4 (CG stops
 * at |r| <= tol * max(|b|, dt |f_ext|); how far that is from a tight solve:
 * Benchmarks/bench_stepper.py and Benchmarks/RESULTS.md), MaxSolverIterations 200,
 * FixedArrayName "Fixed" (a missing "Fixed" array means no clamps; a missing array of
 * another name is an error, and so is an array of that name that is not numeric point
 * data: cell or field data, strings),
 * no force / initial arrays, no clamp plane or box, Material "corotated" (hyperelastic
 * laws: Material below; MooneyRivlinC10/C01 0 = from E and nu, NewtonTolerance 1e-8,
 * MaxNewtonIterations 50).
 *
 * Errors (vtkErrorMacro, empty output): PoissonRatio >= 0.5 or <= -1, YoungModulus <= 0,
 * Density <= 0, TimeStep <= 0, negative damping, an unknown Material, negative
 * Mooney-Rivlin constants, NewtonTolerance <= 0 or MaxNewtonIterations < 1, a static
 * hyperelastic solve that does not converge, unsupported or mixed cell types, an
 * inverted or zero-volume rest element (named by cell id), missing or wrongly sized
 * arrays, a singular static problem, a non-finite state during integration (named by the
 * step).
 *
 * Threading: element loops use vtkSMPTools.
 *
 * Live (incremental) use: with LiveMode on, the stepper keeps its state while loads
 * change, for a simulation driven from outside while it runs (e.g. a mouse drag):
 * - loads: Gravity, SetNodalForces() (added to the ExternalForceArrayName forces) and
 *   SetPrescribedMotion() (a mask and target displacements from rest of chosen nodes:
 *   hard Dirichlet conditions, each step lands those nodes on their targets exactly; see
 *   hoembedCorotationalSolver.h for the step and its stability). Changing them applies
 *   to the next step and continues from the current state; changing the targets alone
 *   keeps the factorised preconditioner, changing the mask refactorises once (on a
 *   background thread with BackgroundFactorization on);
 * - Step(n) advances n steps, AdvanceTo(t) to time t (never backwards), ResetState()
 *   returns to the initial state; a pipeline request for a later UPDATE_TIME_STEP also
 *   advances, an earlier (or no) time outputs the current state; NumberOfTimeSteps does
 *   not cap the live clock. GetSimulationTime() is the time of the current state;
 * - a change of the input mesh or of any other property rebuilds and restarts.
 * With LiveMode off (default) the output at time t depends on the inputs only: any
 * change, SetPrescribedMotion and SetNodalForces included, restarts from the initial
 * state at the next request (the loads then act from the first step on).
 *
 * @warning The tangent ignores the derivative of the rotations (the usual co-rotational
 * approximation) and each step makes one linearised solve: very large time steps stay
 * stable and dissipate, but a step that rotates parts of the body through tens of degrees
 * at once overshoots the strain energy transiently (seen: 8x for ~50 degrees in one step).
 * Clamped nodes stay where the initial state puts them (their velocity is zeroed).
 * Prescribed nodes move by (target - position) in one step: for a smooth motion move the
 * targets by a fraction of an element size per step (a jump is a velocity kick).
 * @warning CHOLMOD's supernodal module is GPL-2.0-or-later: a build that links it (the
 * CMake option HOEMBED_USE_CHOLMOD, on when found) is bound by that licence.
 *
 * @sa vtkDeformationTransferFilter vtkTimeSeriesWriter
 */
#ifndef vtkCorotationalFEMStepper_h
#define vtkCorotationalFEMStepper_h

#include "hoembedFiltersSimulationModule.h"
#include "vtkUnstructuredGridAlgorithm.h"

#include <string> // for std::string
#include <vector> // for std::vector

class vtkDataArray;
namespace hoembed
{
struct StepperParameters;
}

class HOEMBEDFILTERSSIMULATION_EXPORT vtkCorotationalFEMStepper
  : public vtkUnstructuredGridAlgorithm
{
public:
  static vtkCorotationalFEMStepper* New();
  vtkTypeMacro(vtkCorotationalFEMStepper, vtkUnstructuredGridAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// Material: Young's modulus (> 0), Poisson's ratio (in (-1, 0.5)), density (> 0).
  vtkSetMacro(YoungModulus, double);
  vtkGetMacro(YoungModulus, double);
  vtkSetMacro(PoissonRatio, double);
  vtkGetMacro(PoissonRatio, double);
  vtkSetMacro(Density, double);
  vtkGetMacro(Density, double);
  ///@}

  ///@{
  /// Gravity acceleration (body force density * g). Default (0, 0, -9.81).
  vtkSetVector3Macro(Gravity, double);
  vtkGetVector3Macro(Gravity, double);
  ///@}

  ///@{
  /// Optional point-data array names (nullptr or "" = not used).
  vtkSetStringMacro(ExternalForceArrayName);
  vtkGetStringMacro(ExternalForceArrayName);
  vtkSetStringMacro(InitialDisplacementArrayName);
  vtkGetStringMacro(InitialDisplacementArrayName);
  vtkSetStringMacro(InitialVelocityArrayName);
  vtkGetStringMacro(InitialVelocityArrayName);
  vtkSetStringMacro(FixedArrayName);
  vtkGetStringMacro(FixedArrayName);
  ///@}

  ///@{
  /// Rayleigh damping C = RayleighMass * M + RayleighStiffness * K (both >= 0).
  vtkSetMacro(RayleighMass, double);
  vtkGetMacro(RayleighMass, double);
  vtkSetMacro(RayleighStiffness, double);
  vtkGetMacro(RayleighStiffness, double);
  ///@}

  ///@{
  /// Time step (> 0) and number of advertised steps.
  vtkSetMacro(TimeStep, double);
  vtkGetMacro(TimeStep, double);
  vtkSetMacro(NumberOfTimeSteps, int);
  vtkGetMacro(NumberOfTimeSteps, int);
  ///@}

  ///@{
  /// Output the static equilibrium instead of integrating in time.
  vtkSetMacro(StaticSolve, bool);
  vtkGetMacro(StaticSolve, bool);
  vtkBooleanMacro(StaticSolve, bool);
  ///@}

  ///@{
  /// HRZ-lumped (diagonal) mass instead of the consistent mass.
  vtkSetMacro(LumpedMass, bool);
  vtkGetMacro(LumpedMass, bool);
  vtkBooleanMacro(LumpedMass, bool);
  ///@}

  ///@{
  /// Clamp every node with (x - origin) . normal <= 0.
  vtkSetMacro(UseClampPlane, bool);
  vtkGetMacro(UseClampPlane, bool);
  vtkBooleanMacro(UseClampPlane, bool);
  vtkSetVector3Macro(ClampPlaneOrigin, double);
  vtkGetVector3Macro(ClampPlaneOrigin, double);
  vtkSetVector3Macro(ClampPlaneNormal, double);
  vtkGetVector3Macro(ClampPlaneNormal, double);
  ///@}

  ///@{
  /// Clamp every node inside the box (xmin, xmax, ymin, ymax, zmin, zmax).
  vtkSetMacro(UseClampBox, bool);
  vtkGetMacro(UseClampBox, bool);
  vtkBooleanMacro(UseClampBox, bool);
  vtkSetVector6Macro(ClampBox, double);
  vtkGetVector6Macro(ClampBox, double);
  ///@}

  ///@{
  /// Compute the diagnostics of the output: the `VonMisesStress` cell array and the
  /// `KineticEnergy` and `StrainEnergy` field arrays (default on). Off, they are left out
  /// of the output (the positions, the other arrays and the state are the same): a live
  /// loop that only draws the surface saves their cost every frame. Not part of the
  /// state: in LiveMode a change does not restart.
  vtkSetMacro(ComputeDiagnostics, bool);
  vtkGetMacro(ComputeDiagnostics, bool);
  vtkBooleanMacro(ComputeDiagnostics, bool);
  ///@}

  ///@{
  /// LiveMode only: factorise the preconditioner on a background thread when a grab or a
  /// release changes the prescribed set (and when the factor has drifted), while the CG
  /// keeps stepping with a factor it has: a grab frame then costs a few more CG
  /// iterations instead of a factorisation (~0.5 s at 14k DOF). Each step is still
  /// solved to SolverTolerance; only the preconditioner differs. Default off; offline
  /// requests always factorise synchronously (their outputs depend on the inputs only).
  /// FactorizationLag (default 0): 0 takes a new factor at the first step after it is
  /// done (which step depends on the machine's load); n > 0 takes it exactly n steps
  /// after it was asked for, waiting for it if needed (deterministic: tests, benchmarks).
  /// Neither restarts the state.
  vtkSetMacro(BackgroundFactorization, bool);
  vtkGetMacro(BackgroundFactorization, bool);
  vtkBooleanMacro(BackgroundFactorization, bool);
  vtkSetMacro(FactorizationLag, int);
  vtkGetMacro(FactorizationLag, int);
  ///@}

  ///@{
  /// Live mode (see the class description): loads change without restarting the state.
  /// Default off (offline: every change restarts from the initial state).
  vtkSetMacro(LiveMode, bool);
  vtkGetMacro(LiveMode, bool);
  vtkBooleanMacro(LiveMode, bool);
  ///@}

  /**
   * Prescribed motion of chosen nodes: `mask` (1 component, nonzero = prescribed) and
   * `targetDisplacements` (3 components: target x - X), one tuple per input point (checked
   * at the next update). nullptr mask clears it. The arrays are copied. Returns false
   * (with an error) for arrays of the wrong shape or non-finite targets.
   */
  bool SetPrescribedMotion(vtkDataArray* mask, vtkDataArray* targetDisplacements);
  ///@{
  /// Speed limit of the prescribed nodes (distance per second; 0 = none, default): a node
  /// farther from its target than PrescribedSpeedLimit * TimeStep moves that far towards
  /// it per step, so that a target that jumps (a fast mouse) is followed stably. A load:
  /// in LiveMode a change does not restart. Interactive use: about half an element size
  /// per step (see hoembedCorotationalSolver.h).
  vtkSetMacro(PrescribedSpeedLimit, double);
  vtkGetMacro(PrescribedSpeedLimit, double);
  ///@}
  /// Nodal forces (3 components per input point; nullptr clears), added to the
  /// ExternalForceArrayName forces. Copied. False (with an error) for a bad array.
  bool SetNodalForces(vtkDataArray* forces);

  ///@{
  /// LiveMode: advance n steps (>= 0), or to time t, and update the output; false (with
  /// an error) when the stepper fails or LiveMode is off.
  bool Step(int n = 1);
  bool AdvanceTo(double t);
  ///@}
  /// LiveMode: back to the initial state (time 0) at the next update.
  void ResetState();
  /// Time of the current state (steps taken since the initial state times TimeStep).
  double GetSimulationTime();

  ///@{
  /// Conjugate-gradient controls: relative residual and iteration cap per step.
  vtkSetMacro(SolverTolerance, double);
  vtkGetMacro(SolverTolerance, double);
  vtkSetMacro(MaxSolverIterations, int);
  vtkGetMacro(MaxSolverIterations, int);
  ///@}

  ///@{
  /// The material (hoembedHyperelasticMaterial.h for the energies and conversions):
  /// 0 "corotated" (co-rotated linear elasticity, the default), 1 "stvk" (St. Venant-
  /// Kirchhoff), 2 "neo-hookean" (the stable Neo-Hookean of Smith, de Goes and Kim 2018,
  /// defined through inversion), 3 "mooney-rivlin". The hyperelastic ones take their
  /// constants from YoungModulus and PoissonRatio (small-strain limit = linear
  /// elasticity with them) and step by Newton's method on the backward-Euler potential
  /// (hoembedCorotationalSolver.h; a time step's Newton systems are solved by CG to
  /// SolverTolerance, relative). SetMaterial(name) takes the name; an unknown name
  /// (or number) is refused at the next update with the driver's message.
  vtkSetMacro(Material, int);
  vtkGetMacro(Material, int);
  void SetMaterial(const char* name);
  const char* GetMaterialAsString();
  /// Mooney-Rivlin's C10 and C01 (Pa); both 0 (the default): C10 = C01 = mu / 4 from
  /// YoungModulus and PoissonRatio.
  vtkSetMacro(MooneyRivlinC10, double);
  vtkGetMacro(MooneyRivlinC10, double);
  vtkSetMacro(MooneyRivlinC01, double);
  vtkGetMacro(MooneyRivlinC01, double);
  /// Newton's controls (hyperelastic materials): an iteration's largest DOF change <=
  /// NewtonTolerance times the largest displacement of the step (default 1e-8); at most
  /// MaxNewtonIterations per step (default 50; 1: one linearised solve per frame, the
  /// interactive choice) or per static solve (which fails when they do not suffice).
  vtkSetMacro(NewtonTolerance, double);
  vtkGetMacro(NewtonTolerance, double);
  vtkSetMacro(MaxNewtonIterations, int);
  vtkGetMacro(MaxNewtonIterations, int);
  ///@}

  ///@{
  /// Measurements of the last RequestData: steps taken, seconds spent in rotation
  /// extraction, assembly and the linear solve, and CG iterations in total (hyperelastic
  /// materials: Newton iterations, their time all in LastSolveTime).
  vtkGetMacro(LastNumberOfSteps, int);
  vtkGetMacro(LastRotationTime, double);
  vtkGetMacro(LastAssemblyTime, double);
  vtkGetMacro(LastSolveTime, double);
  vtkGetMacro(LastSolverIterations, int);
  /// Of the last request: numeric factorisations of the preconditioner and their seconds
  /// (included in LastSolveTime).
  vtkGetMacro(LastNumberOfFactorizations, int);
  vtkGetMacro(LastFactorizationTime, double);
  /// Of the last request, with BackgroundFactorization: factors from the background
  /// thread taken into use (their time is not in LastSolveTime).
  vtkGetMacro(LastNumberOfBackgroundFactorizations, int);
  ///@}

protected:
  vtkCorotationalFEMStepper();
  ~vtkCorotationalFEMStepper() override;

  int RequestInformation(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestUpdateExtent(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  // the settings: their defaults are hoembed::StepperParameters' and
  // hoembed::StepperOptions' (the constructor copies them)
  double YoungModulus;
  double PoissonRatio;
  double Density;
  double Gravity[3];
  char* ExternalForceArrayName = nullptr;
  char* InitialDisplacementArrayName = nullptr;
  char* InitialVelocityArrayName = nullptr;
  char* FixedArrayName = nullptr;
  double RayleighMass;
  double RayleighStiffness;
  double TimeStep;
  int NumberOfTimeSteps;
  bool StaticSolve;
  bool LumpedMass;
  bool UseClampPlane;
  double ClampPlaneOrigin[3];
  double ClampPlaneNormal[3];
  bool UseClampBox;
  double ClampBox[6];
  double SolverTolerance;
  int MaxSolverIterations;
  int Material;
  double MooneyRivlinC10;
  double MooneyRivlinC01;
  double NewtonTolerance;
  int MaxNewtonIterations;
  bool LiveMode;
  bool ComputeDiagnostics;
  double PrescribedSpeedLimit;
  bool BackgroundFactorization;
  int FactorizationLag;

  int LastNumberOfSteps = 0;
  double LastRotationTime = 0.0;
  double LastAssemblyTime = 0.0;
  double LastSolveTime = 0.0;
  int LastSolverIterations = 0;
  int LastNumberOfFactorizations = 0;
  double LastFactorizationTime = 0.0;
  int LastNumberOfBackgroundFactorizations = 0;

private:
  vtkCorotationalFEMStepper(const vtkCorotationalFEMStepper&) = delete;
  void operator=(const vtkCorotationalFEMStepper&) = delete;

  bool CheckProperties();
  // The steps of RequestData: read the mesh and set up the solver (clamps, loads, initial
  // state), advance it to step k, write the output at time tk.
  bool BuildSolver(vtkUnstructuredGrid* input);
  // The input's point arrays the set-up reads: the clamps' (FixedArrayName; `values`
  // left empty when none), the forces and the initial state (each empty when not named).
  bool ReadClamps(vtkUnstructuredGrid* input, std::vector<double>& values);
  bool ReadPointInputs(vtkUnstructuredGrid* input, std::vector<double>& forces,
    std::vector<double>& u0, std::vector<double>& v0);
  bool Advance(long long k, vtkUnstructuredGrid* output);
  void WriteOutput(vtkUnstructuredGrid* input, vtkUnstructuredGrid* output, double tk);
  // Live loads to the solver (gravity, forces, prescribed motion); false for arrays whose
  // size does not match the mesh.
  bool ApplyLoads(vtkIdType numberOfPoints);
  // the properties the driver's set-up reads
  void GetParameters(hoembed::StepperParameters& p) const;
  // The properties whose change rebuilds in LiveMode (all but the loads and LiveMode).
  std::string BuildSignature() const;
  struct Internals;
  Internals* Internal;
};

#endif
