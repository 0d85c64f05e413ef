#include "vtkCorotationalFEMStepper.h"

#include "hoembedCorotationalSolver.h"
#include "hoembedStepperDriver.h"
#include "hoembedArrayNames.h"
#include "hoembedTetMeshInputVTK.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkCellTypes.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkUnstructuredGrid.h"
#include "vtkWeakPointer.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkCorotationalFEMStepper);

struct vtkCorotationalFEMStepper::Internals
{
  // The set-up, loads and stepping (hoembedStepperDriver, shared with the pip wheel); the
  // references keep this file's names for the driver's state.
  hoembed::StepperDriver Driver;
  hoembed::CorotationalSolver& Solver = Driver.Solver;
  vtkTimeStamp BuildTime;
  // the mesh the solver was built from: another object (an older one: its MTime does not
  // tell) or another size rebuilds, also in LiveMode, whose rebuild test ignores the
  // filter's MTime
  vtkWeakPointer<vtkUnstructuredGrid> BuiltInput;
  bool Built = false;
  bool& StaticDone = Driver.StaticDone;
  int& CurrentStep = Driver.CurrentStep;
  std::vector<double>& InitialX = Driver.InitialX;
  std::vector<double>& InitialV = Driver.InitialV;
  // loads: forces of the ExternalForceArrayName array (empty: none), and those set by
  // SetNodalForces / SetPrescribedMotion (empty: none)
  std::vector<double>& ArrayForces = Driver.ArrayForces;
  std::vector<double>& NodalForces = Driver.NodalForces;
  std::vector<double>& Targets = Driver.Targets;
  std::vector<unsigned char>& Mask = Driver.Mask;
  std::string Signature; // BuildSignature() of the build (LiveMode)
  bool LastOK = false;
};

vtkCorotationalFEMStepper::vtkCorotationalFEMStepper() : Internal(new Internals)
{
  this->SetFixedArrayName(hoembed::ArrayNames::Fixed);
  // the defaults are the driver's
  const hoembed::StepperParameters p;
  this->YoungModulus = p.YoungModulus;
  this->PoissonRatio = p.PoissonRatio;
  this->Density = p.Density;
  this->LumpedMass = p.LumpedMass;
  this->TimeStep = p.TimeStep;
  this->RayleighMass = p.RayleighMass;
  this->RayleighStiffness = p.RayleighStiffness;
  this->SolverTolerance = p.SolverTolerance;
  this->MaxSolverIterations = p.MaxSolverIterations;
  this->Material = p.Material;
  this->MooneyRivlinC10 = p.MooneyRivlinC10;
  this->MooneyRivlinC01 = p.MooneyRivlinC01;
  this->NewtonTolerance = p.NewtonTolerance;
  this->MaxNewtonIterations = p.MaxNewtonIterations;
  this->UseClampPlane = p.UseClampPlane;
  this->UseClampBox = p.UseClampBox;
  for (int i = 0; i < 3; ++i)
  {
    this->ClampPlaneOrigin[i] = p.ClampPlaneOrigin[i];
    this->ClampPlaneNormal[i] = p.ClampPlaneNormal[i];
  }
  for (int i = 0; i < 6; ++i)
  {
    this->ClampBox[i] = p.ClampBox[i];
  }
  const hoembed::StepperOptions o;
  for (int i = 0; i < 3; ++i)
  {
    this->Gravity[i] = o.Gravity[i];
  }
  this->NumberOfTimeSteps = o.NumberOfTimeSteps;
  this->StaticSolve = o.StaticSolve;
  this->PrescribedSpeedLimit = o.PrescribedSpeedLimit;
  this->LiveMode = o.LiveMode;
  this->ComputeDiagnostics = o.ComputeDiagnostics;
  this->BackgroundFactorization = o.BackgroundFactorization;
  this->FactorizationLag = o.FactorizationLag;
}

vtkCorotationalFEMStepper::~vtkCorotationalFEMStepper()
{
  delete this->Internal;
  this->SetExternalForceArrayName(nullptr);
  this->SetInitialDisplacementArrayName(nullptr);
  this->SetInitialVelocityArrayName(nullptr);
  this->SetFixedArrayName(nullptr);
}

// The driver's ranges (hoembed::StepperRanges): the set macros do not clamp, so that a bad
// value is refused with the driver's sentence, not changed.
bool vtkCorotationalFEMStepper::CheckProperties()
{
  hoembed::StepperParameters p;
  this->GetParameters(p);
  hoembed::StepperOptions o;
  for (int i = 0; i < 3; ++i)
  {
    o.Gravity[i] = this->Gravity[i];
  }
  o.NumberOfTimeSteps = this->NumberOfTimeSteps;
  o.PrescribedSpeedLimit = this->PrescribedSpeedLimit;
  o.FactorizationLag = this->FactorizationLag;
  std::string error = hoembed::StepperDriver::CheckParameters(p);
  if (error.empty())
  {
    error = hoembed::StepperDriver::CheckOptions(o);
  }
  if (!error.empty())
  {
    vtkErrorMacro(<< error);
    return false;
  }
  return true;
}

int vtkCorotationalFEMStepper::RequestInformation(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  outInfo->Remove(vtkStreamingDemandDrivenPipeline::TIME_STEPS());
  outInfo->Remove(vtkStreamingDemandDrivenPipeline::TIME_RANGE());
  if (!hoembed::CheckStepperProperty("TimeStep", this->TimeStep).empty() ||
    !hoembed::CheckStepperProperty("NumberOfTimeSteps", this->NumberOfTimeSteps).empty())
  {
    return 1; // no time steps to advertise; the error is RequestData's (CheckProperties)
  }
  std::vector<double> times(static_cast<size_t>(this->NumberOfTimeSteps) + 1);
  for (size_t k = 0; k < times.size(); ++k)
  {
    times[k] = static_cast<double>(k) * this->TimeStep;
  }
  outInfo->Set(
    vtkStreamingDemandDrivenPipeline::TIME_STEPS(), times.data(), static_cast<int>(times.size()));
  double range[2] = { 0.0, times.back() };
  outInfo->Set(vtkStreamingDemandDrivenPipeline::TIME_RANGE(), range, 2);
  return 1;
}

namespace
{
vtkDataArray* GetVectorArray(vtkUnstructuredGrid* input, const char* name, bool& error)
{
  error = false;
  if (!name || !*name)
  {
    return nullptr;
  }
  vtkDataArray* a = input->GetPointData()->GetArray(name);
  if (!a || a->GetNumberOfComponents() != 3)
  {
    error = true;
    return nullptr;
  }
  return a;
}
} // namespace

int vtkCorotationalFEMStepper::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkUnstructuredGrid* input = vtkUnstructuredGrid::GetData(inputVector[0], 0);
  vtkUnstructuredGrid* output = vtkUnstructuredGrid::GetData(outputVector, 0);
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  output->Initialize();
  this->LastNumberOfSteps = 0;
  this->LastRotationTime = this->LastAssemblyTime = this->LastSolveTime = 0.0;
  this->LastSolverIterations = 0;
  this->LastNumberOfFactorizations = 0;
  this->LastFactorizationTime = 0.0;
  this->LastNumberOfBackgroundFactorizations = 0;
  Internals& I = *this->Internal;

  if (!input || input->GetNumberOfCells() == 0 || !input->GetPoints())
  {
    vtkErrorMacro("The input mesh is empty (no cells).");
    I.Built = false;
    return 0;
  }
  if (!this->CheckProperties())
  {
    I.Built = false;
    return 0;
  }
  I.LastOK = false;
  // Offline, any change restarts; live, only a change of the mesh or of a property that
  // is not a load.
  const bool changed =
    this->LiveMode ? this->BuildSignature() != I.Signature : this->GetMTime() > I.BuildTime;
  const bool otherMesh = input != I.BuiltInput ||
    input->GetNumberOfPoints() != I.Solver.GetNumberOfPoints() ||
    input->GetNumberOfCells() != I.Solver.GetNumberOfCells();
  if (!I.Built || input->GetMTime() > I.BuildTime || changed || otherMesh)
  {
    if (!this->BuildSolver(input))
    {
      return 0;
    }
  }

  // Requested step.
  double t = 0.0;
  const bool timed = outInfo->Has(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP());
  if (timed)
  {
    t = outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP());
  }
  long long k = std::llround(t / this->TimeStep);
  if (this->LiveMode)
  {
    const std::string error = I.Driver.PrepareLiveStep(
      this->Gravity, this->PrescribedSpeedLimit, input->GetNumberOfPoints(), timed, k, k);
    if (!error.empty())
    {
      vtkErrorMacro(<< error);
      return 0;
    }
  }
  else
  {
    k = std::max(0LL, std::min<long long>(k, this->NumberOfTimeSteps));
  }
  const double tk = static_cast<double>(k) * this->TimeStep;

  I.Solver.SetBackgroundFactorization(
    this->LiveMode && this->BackgroundFactorization, this->FactorizationLag);
  if (!this->Advance(k, output))
  {
    return 0;
  }
  const auto& T = I.Solver.GetTimings();
  this->LastNumberOfSteps = static_cast<int>(T.Steps);
  this->LastRotationTime = T.Rotation;
  this->LastAssemblyTime = T.Assembly;
  this->LastSolveTime = T.Solve;
  this->LastSolverIterations = static_cast<int>(T.Iterations);
  this->LastNumberOfFactorizations = static_cast<int>(T.Factorizations);
  this->LastFactorizationTime = T.Factorization;
  this->LastNumberOfBackgroundFactorizations = static_cast<int>(T.BackgroundFactorizations);

  this->WriteOutput(input, output, tk);
  I.LastOK = true;
  return 1;
}

//------------------------------------------------------------------------------
std::string vtkCorotationalFEMStepper::BuildSignature() const
{
  hoembed::StepperParameters p;
  this->GetParameters(p);
  return hoembed::StepperDriver::BuildSignature(p, this->StaticSolve,
    { this->ExternalForceArrayName, this->InitialDisplacementArrayName,
      this->InitialVelocityArrayName, this->FixedArrayName });
}

//------------------------------------------------------------------------------
bool vtkCorotationalFEMStepper::ApplyLoads(vtkIdType np)
{
  const std::string error =
    this->Internal->Driver.ApplyLoads(this->Gravity, this->PrescribedSpeedLimit, np);
  if (!error.empty())
  {
    vtkErrorMacro(<< error);
    return false;
  }
  return true;
}

//------------------------------------------------------------------------------
bool vtkCorotationalFEMStepper::SetPrescribedMotion(vtkDataArray* mask, vtkDataArray* targets)
{
  Internals& I = *this->Internal;
  if (!mask)
  {
    if (!I.Mask.empty())
    {
      I.Mask.clear();
      I.Targets.clear();
      this->Modified();
    }
    return true;
  }
  if (mask->GetNumberOfComponents() != 1 || !targets || targets->GetNumberOfComponents() != 3 ||
    targets->GetNumberOfTuples() != mask->GetNumberOfTuples())
  {
    vtkErrorMacro("SetPrescribedMotion: needs a 1-component mask and a 3-component target "
                  "displacement array with the same number of tuples (one per point).");
    return false;
  }
  // the arrays' values as doubles; the driver keeps the mask and the prescribed rows
  const vtkIdType n = mask->GetNumberOfTuples();
  std::vector<double> m(n), t(3 * n, 0.0);
  for (vtkIdType p = 0; p < n; ++p)
  {
    m[p] = mask->GetComponent(p, 0);
    if (m[p] != 0.0)
    {
      targets->GetTuple(p, &t[3 * p]);
    }
  }
  const std::string error = I.Driver.SetPrescribedMotion(n, m.data(), t.data());
  if (!error.empty())
  {
    vtkErrorMacro("SetPrescribedMotion: " << error);
    return false;
  }
  this->Modified();
  return true;
}

bool vtkCorotationalFEMStepper::SetNodalForces(vtkDataArray* forces)
{
  Internals& I = *this->Internal;
  if (!forces)
  {
    if (!I.NodalForces.empty())
    {
      I.NodalForces.clear();
      this->Modified();
    }
    return true;
  }
  if (forces->GetNumberOfComponents() != 3)
  {
    vtkErrorMacro("SetNodalForces: needs a 3-component array (one tuple per point).");
    return false;
  }
  std::vector<double> f(3 * static_cast<size_t>(forces->GetNumberOfTuples()));
  for (vtkIdType p = 0; p < forces->GetNumberOfTuples(); ++p)
  {
    forces->GetTuple(p, &f[3 * p]);
  }
  for (double v : f)
  {
    if (!std::isfinite(v))
    {
      vtkErrorMacro("SetNodalForces: the forces are not finite.");
      return false;
    }
  }
  I.NodalForces.swap(f);
  this->Modified();
  return true;
}

bool vtkCorotationalFEMStepper::Step(int n)
{
  if (!this->LiveMode)
  {
    vtkErrorMacro("Step() needs LiveMode on (offline, request a time from the pipeline).");
    return false;
  }
  if (n < 0)
  {
    vtkErrorMacro("Step(" << n << "): the number of steps must be >= 0.");
    return false;
  }
  this->Internal->Driver.RequestSteps(n);
  this->Modified();
  this->Update();
  return this->Internal->LastOK;
}

bool vtkCorotationalFEMStepper::AdvanceTo(double t)
{
  if (!this->LiveMode)
  {
    vtkErrorMacro("AdvanceTo() needs LiveMode on (offline, request a time from the pipeline).");
    return false;
  }
  if (!std::isfinite(t) || !(this->TimeStep > 0.0))
  {
    vtkErrorMacro("AdvanceTo(" << t << "): the time must be finite (and TimeStep > 0).");
    return false;
  }
  Internals& I = *this->Internal;
  I.Driver.RequestStep(std::llround(t / this->TimeStep), I.Built);
  this->Modified();
  this->Update();
  return I.LastOK;
}

void vtkCorotationalFEMStepper::ResetState()
{
  this->Internal->Driver.RequestReset();
  this->Modified();
}

double vtkCorotationalFEMStepper::GetSimulationTime()
{
  const Internals& I = *this->Internal;
  return I.Built ? I.Driver.ClockStep() * this->TimeStep : 0.0;
}

//------------------------------------------------------------------------------
// Read the mesh (the one reader) and the point arrays; the driver sets up the solver
// (rest validity of every cell, clamps, loads, initial state).
bool vtkCorotationalFEMStepper::BuildSolver(vtkUnstructuredGrid* input)
{
  Internals& I = *this->Internal;
  I.Built = false;
  // Types, connectivity, node ranges and finite points: the one reader.
  hoembed::TetMeshInput mesh;
  std::vector<double> scratch;
  const std::string readError =
    mesh.Read(hoembed::ViewTetMesh(input, true, scratch), hoembed::TetMeshInput::KeepPoints);
  if (!readError.empty())
  {
    vtkErrorMacro(<< readError << ".");
    return false;
  }
  std::vector<double> fixed, forces, u0, v0;
  if (!this->ReadClamps(input, fixed) || !this->ReadPointInputs(input, forces, u0, v0))
  {
    return false;
  }
  hoembed::StepperParameters p;
  this->GetParameters(p);
  hoembed::StepperInputs in;
  auto data = [](const std::vector<double>& v) { return v.empty() ? nullptr : v.data(); };
  in.FixedValues = data(fixed);
  in.Forces = data(forces);
  in.InitialDisplacement = data(u0);
  in.InitialVelocity = data(v0);
  for (int i = 0; i < 3; ++i)
  {
    in.Gravity[i] = this->Gravity[i];
  }
  in.PrescribedSpeedLimit = this->PrescribedSpeedLimit;
  const std::string error = I.Driver.Build(mesh, p, in);
  if (!error.empty())
  {
    vtkErrorMacro(<< error);
    return false;
  }
  I.Signature = this->BuildSignature();
  I.Built = true;
  I.BuildTime.Modified();
  I.BuiltInput = input;
  return true;
}

//------------------------------------------------------------------------------
// The clamps' array (FixedArrayName): where it is, the driver's rule, its values.
bool vtkCorotationalFEMStepper::ReadClamps(vtkUnstructuredGrid* input, std::vector<double>& values)
{
  const vtkIdType np = input->GetNumberOfPoints();
  const bool named = this->FixedArrayName && *this->FixedArrayName;
  vtkDataArray* fixedArray =
    named ? input->GetPointData()->GetArray(this->FixedArrayName) : nullptr;
  using Kind = hoembed::StepperDriver::FixedArrayKind;
  Kind kind = fixedArray ? Kind::Numeric : Kind::Absent;
  if (!fixedArray && named)
  {
    if (input->GetPointData()->GetAbstractArray(this->FixedArrayName))
    {
      kind = Kind::NotNumeric;
    }
    else if (input->GetCellData()->GetAbstractArray(this->FixedArrayName) ||
      input->GetFieldData()->GetAbstractArray(this->FixedArrayName))
    {
      kind = Kind::CellOrField;
    }
  }
  const std::string error = hoembed::StepperDriver::CheckFixedArray(
    this->FixedArrayName, kind, fixedArray ? fixedArray->GetNumberOfTuples() : 0, np);
  if (!error.empty())
  {
    vtkErrorMacro(<< error);
    return false;
  }
  values.clear();
  if (fixedArray)
  {
    values.resize(np);
    for (vtkIdType p = 0; p < np; ++p)
    {
      values[p] = fixedArray->GetComponent(p, 0);
    }
  }
  return true;
}

//------------------------------------------------------------------------------
// The forces and the initial state (displacement, velocity): 3-component point arrays.
bool vtkCorotationalFEMStepper::ReadPointInputs(vtkUnstructuredGrid* input,
  std::vector<double>& forces, std::vector<double>& u0, std::vector<double>& v0)
{
  const vtkIdType np = input->GetNumberOfPoints();
  const char* names[3] = { this->ExternalForceArrayName, this->InitialDisplacementArrayName,
    this->InitialVelocityArrayName };
  const char* properties[3] = { "ExternalForceArrayName", "InitialDisplacementArrayName",
    "InitialVelocityArrayName" };
  std::vector<double>* out[3] = { &forces, &u0, &v0 };
  for (int k = 0; k < 3; ++k)
  {
    bool bad3 = false;
    vtkDataArray* a = GetVectorArray(input, names[k], bad3);
    if (bad3)
    {
      vtkErrorMacro(<< properties[k] << " '" << names[k]
                    << "' is not a 3-component point-data array.");
      return false;
    }
    out[k]->clear();
    if (a)
    {
      out[k]->resize(3 * static_cast<size_t>(np));
      for (vtkIdType p = 0; p < np; ++p)
      {
        for (int i = 0; i < 3; ++i)
        {
          (*out[k])[3 * p + i] = a->GetComponent(p, i);
        }
      }
    }
  }
  return true;
}

//------------------------------------------------------------------------------
// Bring the solver to step k (or to the static equilibrium); false with an error.
bool vtkCorotationalFEMStepper::Advance(long long k, vtkUnstructuredGrid* output)
{
  const std::string error = this->Internal->Driver.Advance(
    k, this->StaticSolve, this->TimeStep, [this](double f) { this->UpdateProgress(f); });
  if (!error.empty())
  {
    vtkErrorMacro(<< error);
    this->Internal->Built = false; // restart from the initial state next time
    output->Initialize();
    return false;
  }
  return true;
}

//------------------------------------------------------------------------------
void vtkCorotationalFEMStepper::SetMaterial(const char* name)
{
  // an unknown name becomes -1, which the driver refuses again at the next update
  int index = -1;
  const std::string error = hoembed::StepperDriver::ParseMaterial(name ? name : "", index);
  if (!error.empty())
  {
    vtkErrorMacro(<< error);
  }
  this->SetMaterial(index);
}

//------------------------------------------------------------------------------
const char* vtkCorotationalFEMStepper::GetMaterialAsString()
{
  const auto& names = hoembed::StepperDriver::MaterialNames();
  return this->Material >= 0 && this->Material < static_cast<int>(names.size())
    ? names[this->Material].c_str()
    : "unknown";
}

//------------------------------------------------------------------------------
void vtkCorotationalFEMStepper::GetParameters(hoembed::StepperParameters& p) const
{
  p.YoungModulus = this->YoungModulus;
  p.PoissonRatio = this->PoissonRatio;
  p.Density = this->Density;
  p.LumpedMass = this->LumpedMass;
  p.TimeStep = this->TimeStep;
  p.RayleighMass = this->RayleighMass;
  p.RayleighStiffness = this->RayleighStiffness;
  p.SolverTolerance = this->SolverTolerance;
  p.MaxSolverIterations = this->MaxSolverIterations;
  p.Material = this->Material;
  p.MooneyRivlinC10 = this->MooneyRivlinC10;
  p.MooneyRivlinC01 = this->MooneyRivlinC01;
  p.NewtonTolerance = this->NewtonTolerance;
  p.MaxNewtonIterations = this->MaxNewtonIterations;
  p.UseClampPlane = this->UseClampPlane;
  p.UseClampBox = this->UseClampBox;
  for (int i = 0; i < 3; ++i)
  {
    p.ClampPlaneOrigin[i] = this->ClampPlaneOrigin[i];
    p.ClampPlaneNormal[i] = this->ClampPlaneNormal[i];
  }
  for (int i = 0; i < 6; ++i)
  {
    p.ClampBox[i] = this->ClampBox[i];
  }
}

//------------------------------------------------------------------------------
// The input's structure and data, the current positions and the stepper's arrays.
void vtkCorotationalFEMStepper::WriteOutput(
  vtkUnstructuredGrid* input, vtkUnstructuredGrid* output, double tk)
{
  Internals& I = *this->Internal;
  const vtkIdType nc = input->GetNumberOfCells();
  const vtkIdType np = input->GetNumberOfPoints();
  output->CopyStructure(input);
  output->GetPointData()->PassData(input->GetPointData());
  output->GetCellData()->PassData(input->GetCellData());
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(np);
  vtkNew<vtkDoubleArray> disp, vel, rot, vm;
  disp->SetName(hoembed::ArrayNames::Displacement);
  disp->SetNumberOfComponents(3);
  disp->SetNumberOfTuples(np);
  vel->SetName(hoembed::ArrayNames::Velocity);
  vel->SetNumberOfComponents(3);
  vel->SetNumberOfTuples(np);
  rot->SetName(hoembed::ArrayNames::NodalRotation);
  rot->SetNumberOfComponents(9);
  rot->SetNumberOfTuples(np);
  vm->SetName(hoembed::ArrayNames::VonMisesStress);
  vm->SetNumberOfTuples(this->ComputeDiagnostics ? nc : 0);
  I.Driver.WriteFrame(static_cast<double*>(points->GetVoidPointer(0)), disp->GetPointer(0),
    vel->GetPointer(0), rot->GetPointer(0), this->ComputeDiagnostics ? vm->GetPointer(0) : nullptr);
  output->SetPoints(points);
  output->GetPointData()->AddArray(disp);
  output->GetPointData()->AddArray(vel);
  output->GetPointData()->AddArray(rot);
  if (this->ComputeDiagnostics)
  {
    output->GetCellData()->AddArray(vm);
  }
  else
  {
    // an input array of that name (a stepper's output fed back) would describe another state
    output->GetCellData()->RemoveArray(hoembed::ArrayNames::VonMisesStress);
  }
  auto addField = [&](const char* name, double value) {
    vtkNew<vtkDoubleArray> a;
    a->SetName(name);
    a->InsertNextValue(value);
    output->GetFieldData()->AddArray(a);
  };
  if (this->ComputeDiagnostics)
  {
    addField(hoembed::ArrayNames::KineticEnergy, I.Solver.KineticEnergy());
    addField(hoembed::ArrayNames::StrainEnergy, I.Solver.StrainEnergy());
  }
  addField(hoembed::ArrayNames::SolverIterations, I.Solver.GetLastIterations());
  output->GetInformation()->Set(vtkDataObject::DATA_TIME_STEP(), tk);
  this->UpdateProgress(1.0);
}

void vtkCorotationalFEMStepper::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  auto str = [](const char* s) { return s ? s : "(none)"; };
  os << indent << "YoungModulus: " << this->YoungModulus << "\n";
  os << indent << "PoissonRatio: " << this->PoissonRatio << "\n";
  os << indent << "Density: " << this->Density << "\n";
  os << indent << "Gravity: (" << this->Gravity[0] << ", " << this->Gravity[1] << ", "
     << this->Gravity[2] << ")\n";
  os << indent << "ExternalForceArrayName: " << str(this->ExternalForceArrayName) << "\n";
  os << indent << "InitialDisplacementArrayName: " << str(this->InitialDisplacementArrayName)
     << "\n";
  os << indent << "InitialVelocityArrayName: " << str(this->InitialVelocityArrayName) << "\n";
  os << indent << "FixedArrayName: " << str(this->FixedArrayName) << "\n";
  os << indent << "RayleighMass: " << this->RayleighMass << "\n";
  os << indent << "RayleighStiffness: " << this->RayleighStiffness << "\n";
  os << indent << "TimeStep: " << this->TimeStep << "\n";
  os << indent << "NumberOfTimeSteps: " << this->NumberOfTimeSteps << "\n";
  os << indent << "StaticSolve: " << this->StaticSolve << "\n";
  os << indent << "LumpedMass: " << this->LumpedMass << "\n";
  os << indent << "UseClampPlane: " << this->UseClampPlane << "\n";
  os << indent << "ClampPlaneOrigin: (" << this->ClampPlaneOrigin[0] << ", "
     << this->ClampPlaneOrigin[1] << ", " << this->ClampPlaneOrigin[2] << ")\n";
  os << indent << "ClampPlaneNormal: (" << this->ClampPlaneNormal[0] << ", "
     << this->ClampPlaneNormal[1] << ", " << this->ClampPlaneNormal[2] << ")\n";
  os << indent << "UseClampBox: " << this->UseClampBox << "\n";
  os << indent << "ClampBox: (" << this->ClampBox[0] << ", " << this->ClampBox[1] << ", "
     << this->ClampBox[2] << ", " << this->ClampBox[3] << ", " << this->ClampBox[4] << ", "
     << this->ClampBox[5] << ")\n";
  os << indent << "SolverTolerance: " << this->SolverTolerance << "\n";
  os << indent << "MaxSolverIterations: " << this->MaxSolverIterations << "\n";
  os << indent << "Material: " << this->Material << " (" << this->GetMaterialAsString() << ")\n";
  os << indent << "MooneyRivlinC10: " << this->MooneyRivlinC10 << "\n";
  os << indent << "MooneyRivlinC01: " << this->MooneyRivlinC01 << "\n";
  os << indent << "NewtonTolerance: " << this->NewtonTolerance << "\n";
  os << indent << "MaxNewtonIterations: " << this->MaxNewtonIterations << "\n";
  os << indent << "LiveMode: " << this->LiveMode << "\n";
  os << indent << "ComputeDiagnostics: " << this->ComputeDiagnostics << "\n";
  os << indent << "PrescribedSpeedLimit: " << this->PrescribedSpeedLimit << "\n";
  os << indent << "BackgroundFactorization: " << this->BackgroundFactorization << "\n";
  os << indent << "FactorizationLag: " << this->FactorizationLag << "\n";
  os << indent << "LastNumberOfSteps: " << this->LastNumberOfSteps << "\n";
  os << indent << "LastRotationTime: " << this->LastRotationTime << "\n";
  os << indent << "LastAssemblyTime: " << this->LastAssemblyTime << "\n";
  os << indent << "LastSolveTime: " << this->LastSolveTime << "\n";
  os << indent << "LastSolverIterations: " << this->LastSolverIterations << "\n";
  os << indent << "LastNumberOfFactorizations: " << this->LastNumberOfFactorizations << "\n";
  os << indent << "LastFactorizationTime: " << this->LastFactorizationTime << "\n";
  os << indent
     << "LastNumberOfBackgroundFactorizations: " << this->LastNumberOfBackgroundFactorizations
     << "\n";
} //------------------------------------------------------------------------------
int vtkCorotationalFEMStepper::RequestUpdateExtent(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector*)
{
  // Distributed pipelines: every process simulates the whole mesh (the FE system is
  // small; the transfer needs every node), whatever piece is asked of the output.
  using SDDP = vtkStreamingDemandDrivenPipeline;
  if (vtkInformation* inInfo = inputVector[0]->GetInformationObject(0))
  {
    inInfo->Set(SDDP::UPDATE_PIECE_NUMBER(), 0);
    inInfo->Set(SDDP::UPDATE_NUMBER_OF_PIECES(), 1);
    inInfo->Set(SDDP::UPDATE_NUMBER_OF_GHOST_LEVELS(), 0);
  }
  return 1;
}
