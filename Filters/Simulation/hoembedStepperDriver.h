/**
 * @file hoembedStepperDriver.h
 * @brief The FE stepper's work between reading its input and writing a frame, VTK-free:
 * the rest-mesh checks, the solver's set-up, the clamps (mask, plane, box), the loads,
 * the initial state, stepping to a step index and the static solve.
 *
 * vtkCorotationalFEMStepper reads its vtkUnstructuredGrid and arrays, calls these steps
 * and writes the output frame (WriteFrame); the package's binding
 * (Wrapping/Pip/hoembedPipModule.cxx) calls the same steps on numpy arrays, so both give
 * the same frames bit for bit. Errors are returned as one sentence ending in '.' (the
 * empty string on success); the caller prefixes its own name.
 */
#ifndef hoembedStepperDriver_h
#define hoembedStepperDriver_h

#include "hoembedCorotationalSolver.h"
#include "hoembedFiltersSimulationModule.h"
#include "hoembedPropertyRange.h"

#include <functional>
#include <string>
#include <vector>

namespace hoembed
{
class TetMeshInput;

/// The stepper's properties that the set-up reads (vtkCorotationalFEMStepper's names and
/// defaults).
struct StepperParameters
{
  double YoungModulus = 1.0e5;
  double PoissonRatio = 0.49;
  double Density = 1000.0;
  bool LumpedMass = false;
  double TimeStep = 0.01;
  double RayleighMass = 0.1;
  double RayleighStiffness = 0.01;
  double SolverTolerance = 1e-4;
  int MaxSolverIterations = 200;
  bool UseClampPlane = false;
  double ClampPlaneOrigin[3] = { 0.0, 0.0, 0.0 };
  double ClampPlaneNormal[3] = { 1.0, 0.0, 0.0 };
  bool UseClampBox = false;
  double ClampBox[6] = { 0.0, -1.0, 0.0, -1.0, 0.0, -1.0 };
  /// the material, as hoembedHyperelasticMaterial.h's Material (0 corotated, 1 stvk,
  /// 2 neo-hookean, 3 mooney-rivlin; StepperDriver::MaterialNames)
  int Material = 0;
  /// Mooney-Rivlin's C10, C01 (both 0: C10 = C01 = mu / 4 from E and nu)
  double MooneyRivlinC10 = 0.0;
  double MooneyRivlinC01 = 0.0;
  /// Newton's stop rule for the hyperelastic materials (CorotationalSolver::
  /// SetNewtonControls): iteration change <= tolerance * displacement of the step or
  /// static solve; at most MaxNewtonIterations per step (1: one linearised solve per
  /// step) or per static solve (which fails when it is not enough)
  double NewtonTolerance = 1e-8;
  int MaxNewtonIterations = 50;
};

/// The stepper's other settings and their defaults (vtkCorotationalFEMStepper's names):
/// the loads, the steps a run makes, live mode. With StepperParameters, the defaults are
/// written here once: the filter's constructor copies them, the package's simulate() and
/// StepperDriver binding take them through the compiled module, and a test checks the
/// ParaView XML's default_values against the filter.
struct StepperOptions
{
  /// gravity acceleration of a run (StepperInputs::Gravity is none unless given)
  double Gravity[3] = { 0.0, 0.0, -9.81 };
  /// steps of a run (the filter's advertised TIME_STEPS, simulate()'s steps)
  int NumberOfTimeSteps = 100;
  bool StaticSolve = false;
  double PrescribedSpeedLimit = 0.0;
  bool LiveMode = false;
  bool ComputeDiagnostics = true;
  bool BackgroundFactorization = false;
  int FactorizationLag = 0;
};

/// The valid range of each numeric property of the stepper (StepperParameters and
/// StepperOptions; Gravity: each component), written once: StepperDriver::Build and
/// CheckParameters refuse a value outside it with its sentence; vtkCorotationalFEMStepper,
/// the package (RANGES, check_range) and the ParaView XML's range domains (kept inside by
/// a test) read it from here.
constexpr PropertyRange StepperRanges[] = {
  { "YoungModulus", 0, NoLimit, true, false, false },
  { "PoissonRatio", -1, 0.5, true, true, false },
  { "Density", 0, NoLimit, true, false, false },
  { "TimeStep", 0, NoLimit, true, false, false },
  { "RayleighMass", 0, NoLimit, false, false, false },
  { "RayleighStiffness", 0, NoLimit, false, false, false },
  { "SolverTolerance", 1e-16, 1, false, false, false },
  { "MaxSolverIterations", 1, NoLimit, false, false, true },
  { "Gravity", -NoLimit, NoLimit, false, false, false },
  { "NumberOfTimeSteps", 0, NoLimit, false, false, true },
  { "PrescribedSpeedLimit", 0, NoLimit, false, false, false },
  { "FactorizationLag", 0, NoLimit, false, false, true },
  { "MooneyRivlinC10", 0, NoLimit, false, false, false },
  { "MooneyRivlinC01", 0, NoLimit, false, false, false },
  { "NewtonTolerance", 0, NoLimit, true, false, false },
  { "MaxNewtonIterations", 1, NoLimit, false, false, true },
};

/// The sentence refusing `value` for the property `name` (StepperRanges; "" when `value`
/// is in its range, or `name` has none).
HOEMBEDFILTERSSIMULATION_EXPORT std::string CheckStepperProperty(
  const std::string& name, double value);

/// The per-point inputs of a set-up (each nullptr: none), 1 or 3 values per point.
struct StepperInputs
{
  const double* FixedValues = nullptr;         ///< nonzero = clamped
  const double* Forces = nullptr;              ///< nodal forces (3 per point)
  const double* InitialDisplacement = nullptr; ///< 3 per point
  const double* InitialVelocity = nullptr;     ///< 3 per point
  double Gravity[3] = { 0.0, 0.0, 0.0 };
  double PrescribedSpeedLimit = 0.0;
};

class HOEMBEDFILTERSSIMULATION_EXPORT StepperDriver
{
public:
  /// The whole set-up on a mesh read with TetMeshInput::KeepPoints, in the one order both
  /// bindings use: Initialize, SetClamps, the forces, ApplyLoads (with the prescribed
  /// motion set before by SetPrescribedMotion, and the nodal forces), SetInitialState,
  /// Start. Returns the first error.
  std::string Build(
    const TetMeshInput& mesh, const StepperParameters& p, const StepperInputs& inputs);

  /// The first property of `p` outside its StepperRanges range, as its sentence ("" when
  /// all are valid). Build starts with it.
  static std::string CheckParameters(const StepperParameters& p);
  /// The same for the run's settings (Gravity, NumberOfTimeSteps, PrescribedSpeedLimit,
  /// FactorizationLag).
  static std::string CheckOptions(const StepperOptions& o);

  /// Rest validity of every cell of `mesh` (read with TetMeshInput::KeepPoints), then the
  /// solver's mesh, material and mass.
  std::string Initialize(const TetMeshInput& mesh, const StepperParameters& p);

  /// Clamped nodes: `fixedValues` (one value per point, nonzero = clamped; nullptr: none),
  /// or within 1e-9 of the bounding-box diagonal of the clamp plane's negative side or of
  /// the clamp box. `rest`: 3 per point.
  std::string SetClamps(
    const std::vector<double>& rest, const double* fixedValues, const StepperParameters& p);

  /// Prescribed motion of `numberOfPoints` points into Mask and Targets (applied by the
  /// next ApplyLoads): `mask` nonzero = prescribed (nullptr: none, clearing them),
  /// `targets` the displacements from rest (3 per point, read only where the mask is
  /// set; the others are kept 0 so that the state does not depend on unread values). A
  /// non-finite target of a prescribed point is refused and leaves Mask and Targets as
  /// they were.
  std::string SetPrescribedMotion(
    long long numberOfPoints, const double* mask, const double* targets);

  /// Gravity plus ArrayForces plus NodalForces (each empty = none) and the prescribed
  /// motion (Mask, Targets; empty = none) into the solver.
  std::string ApplyLoads(
    const double gravity[3], double prescribedSpeedLimit, long long numberOfPoints);

  /// Initial positions rest + u0 and velocities v0 (3 per point each; nullptr = zero).
  void SetInitialState(const std::vector<double>& rest, const double* u0, const double* v0);

  /// Time step, damping and solver controls; the solver at the initial state, step 0 (a
  /// pending reset is done by that).
  void Start(const StepperParameters& p);

  /// Bring the solver to step k (from the initial state again when k is behind), or with
  /// `staticSolve` to the static equilibrium (once, until StaticDone is cleared).
  /// `progress` (may be empty) gets the fraction of the steps done.
  std::string Advance(
    long long k, bool staticSolve, double timeStep, const std::function<void(double)>& progress);

  /// The material names, in Material order ("corotated", "stvk", "neo-hookean",
  /// "mooney-rivlin"), and a name's index (-1: unknown).
  static const std::vector<std::string>& MaterialNames();
  static int MaterialIndex(const std::string& name);
  /// `name`'s index into `index`, or the sentence refusing it (index then -1).
  static std::string ParseMaterial(const std::string& name, int& index);
  /// Material one of MaterialNames ("" when it is; CheckParameters starts with it, and the
  /// Mooney-Rivlin constants and Newton controls have their StepperRanges).
  static std::string CheckMaterial(const StepperParameters& p);

  /// Where the clamps' point array (FixedArrayName) was found, as the binding sees it.
  enum class FixedArrayKind
  {
    Absent,     ///< no array of that name anywhere
    Numeric,    ///< a numeric point-data array (its component 0 is read)
    NotNumeric, ///< a point-data array that is not numeric (e.g. strings)
    CellOrField ///< cell or field data of that name
  };
  /// The rule for the clamps' array `name` (empty: none asked for): an array of that name
  /// that is not numeric point data, or a named array that is absent (but the default
  /// "Fixed"), or one with another number of tuples than `numberOfPoints`, is refused
  /// with its sentence; "" when the array is to be read (Numeric) or there is none.
  static std::string CheckFixedArray(
    const char* name, FixedArrayKind kind, long long tuples, long long numberOfPoints);

  /// What a live rebuild is decided on: the set-up's parameters, the static solve and the
  /// names of the point arrays read (nullptr: none), as one string; any change of it
  /// rebuilds (the loads, set between steps, are not in it).
  static std::string BuildSignature(
    const StepperParameters& p, bool staticSolve, const std::vector<const char*>& arrayNames);

  /// The live clock (vtkCorotationalFEMStepper's LiveMode and the package's LiveSession):
  /// steps asked for since the last live advance, a reset asked for, and the target of the
  /// next live advance (never backwards).
  void RequestSteps(long long n)
  {
    this->PendingSteps += n;
  }
  /// Steps to reach step k from now (none when k is behind); `built`: the solver exists.
  void RequestStep(long long k, bool built);
  void RequestReset()
  {
    this->ResetRequested = true;
    this->PendingSteps = 0;
  }
  /// The current step as the clock shows it (0 while a reset is pending).
  long long ClockStep() const
  {
    return this->ResetRequested ? 0 : this->CurrentStep;
  }
  /// Before a live advance: the pending reset (back to the initial state), the loads as
  /// they are now, and the step to advance to: `requested` (when `timed`) or the current
  /// step plus the pending ones, whichever is later. The pending steps are consumed.
  std::string PrepareLiveStep(const double gravity[3], double prescribedSpeedLimit,
    long long numberOfPoints, bool timed, long long requested, long long& target);

  /// A frame's arrays from the solver's state (each nullptr: not written): positions x,
  /// displacements x - X, velocities (3 per point), nodal rotations (9 per point),
  /// von Mises stress (1 per cell).
  void WriteFrame(double* points, double* displacements, double* velocities, double* rotations,
    double* vonMises) const;

  CorotationalSolver Solver;
  std::vector<double> InitialX, InitialV;
  /// loads: forces of a point array (empty: none) and those set between steps (empty:
  /// none); the prescribed motion's mask and target displacements (empty: none)
  std::vector<double> ArrayForces, NodalForces, Targets;
  std::vector<unsigned char> Mask;
  int CurrentStep = 0;
  bool StaticDone = false;
  long long PendingSteps = 0;
  bool ResetRequested = false;
};
} // namespace hoembed

#endif
