#include "hoembedStepperDriver.h"
#include "hoembedArrayNames.h"

#include "hoembedElementGeometry.h"
#include "hoembedQuadraticMap.h"
#include "hoembedTetMeshInput.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <utility>

namespace hoembed
{
//------------------------------------------------------------------------------
std::string CheckStepperProperty(const std::string& name, double value)
{
  const PropertyRange* r = FindPropertyRange(StepperRanges, name);
  return r ? CheckPropertyRange(*r, value) : std::string();
}

namespace
{
std::string FirstError(const std::pair<const char*, double>* values, int n)
{
  for (int i = 0; i < n; ++i)
  {
    const std::string error = CheckStepperProperty(values[i].first, values[i].second);
    if (!error.empty())
      return error;
  }
  return std::string();
}
} // namespace

//------------------------------------------------------------------------------
std::string StepperDriver::CheckParameters(const StepperParameters& p)
{
  const std::pair<const char*, double> values[] = { { "YoungModulus", p.YoungModulus },
    { "PoissonRatio", p.PoissonRatio }, { "Density", p.Density }, { "TimeStep", p.TimeStep },
    { "RayleighMass", p.RayleighMass }, { "RayleighStiffness", p.RayleighStiffness },
    { "SolverTolerance", p.SolverTolerance }, { "MaxSolverIterations", p.MaxSolverIterations },
    { "MooneyRivlinC10", p.MooneyRivlinC10 }, { "MooneyRivlinC01", p.MooneyRivlinC01 },
    { "NewtonTolerance", p.NewtonTolerance },
    { "MaxNewtonIterations", static_cast<double>(p.MaxNewtonIterations) } };
  const std::string material = CheckMaterial(p);
  if (!material.empty())
  {
    return material;
  }
  return FirstError(values, static_cast<int>(sizeof(values) / sizeof(values[0])));
}

//------------------------------------------------------------------------------
std::string StepperDriver::CheckOptions(const StepperOptions& o)
{
  const std::pair<const char*, double> values[] = { { "Gravity", o.Gravity[0] },
    { "Gravity", o.Gravity[1] }, { "Gravity", o.Gravity[2] },
    { "NumberOfTimeSteps", o.NumberOfTimeSteps },
    { "PrescribedSpeedLimit", o.PrescribedSpeedLimit },
    { "FactorizationLag", o.FactorizationLag } };
  return FirstError(values, static_cast<int>(sizeof(values) / sizeof(values[0])));
}

//------------------------------------------------------------------------------
std::string StepperDriver::Build(
  const TetMeshInput& mesh, const StepperParameters& p, const StepperInputs& in)
{
  std::string error = CheckParameters(p);
  for (int i = 0; i < 3 && error.empty(); ++i)
  {
    error = CheckStepperProperty("Gravity", in.Gravity[i]);
  }
  if (error.empty())
  {
    error = CheckStepperProperty("PrescribedSpeedLimit", in.PrescribedSpeedLimit);
  }
  if (error.empty())
  {
    error = this->Initialize(mesh, p);
  }
  if (error.empty())
  {
    error = this->SetClamps(mesh.Points, in.FixedValues, p);
  }
  if (error.empty())
  {
    const size_t n3 = 3 * static_cast<size_t>(mesh.NumberOfPoints);
    this->ArrayForces.assign(in.Forces ? in.Forces : nullptr, in.Forces ? in.Forces + n3 : nullptr);
    error = this->ApplyLoads(in.Gravity, in.PrescribedSpeedLimit, mesh.NumberOfPoints);
  }
  if (error.empty())
  {
    this->SetInitialState(mesh.Points, in.InitialDisplacement, in.InitialVelocity);
    this->Start(p);
  }
  return error;
}

//------------------------------------------------------------------------------
std::string StepperDriver::Initialize(const TetMeshInput& mesh, const StepperParameters& p)
{
  this->StaticDone = false;
  const long long nc = mesh.NumberOfCells;
  const long long np = mesh.NumberOfPoints;
  const int npc = mesh.NodesPerCell;
  const std::vector<double>& rest = mesh.Points;
  // The solver's id type is long long (the reader's std::int64_t may be another 64-bit
  // type of the same width).
  const std::vector<long long> conn(mesh.Connectivity.begin(), mesh.Connectivity.end());
  double xe[30];
  for (long long c = 0; c < nc; ++c)
  {
    for (int a = 0; a < npc; ++a)
    {
      for (int i = 0; i < 3; ++i)
      {
        xe[3 * a + i] = rest[3 * conn[c * npc + a] + i];
      }
    }
    if (!TetIsValid(xe, npc))
    {
      std::ostringstream o;
      o << "Rest cell " << c << " is inverted or has zero volume (det J <= 0).";
      return o.str();
    }
  }
  const std::string materialError = CheckMaterial(p);
  if (!materialError.empty())
  {
    return materialError;
  }
  std::string error;
  long long bad = -1;
  if (!this->Solver.Initialize(npc, nc, conn.data(), np, rest.data(), p.YoungModulus,
        p.PoissonRatio, p.Density, p.LumpedMass, error, bad))
  {
    std::ostringstream o;
    if (bad >= 0)
    {
      o << "Cell " << bad << ": ";
    }
    o << error << ".";
    return o.str();
  }
  this->Solver.SetMaterial(p.Material, p.MooneyRivlinC10, p.MooneyRivlinC01);
  return std::string();
}

//------------------------------------------------------------------------------
const std::vector<std::string>& StepperDriver::MaterialNames()
{
  static const std::vector<std::string> names = { "corotated", "stvk", "neo-hookean",
    "mooney-rivlin" };
  return names;
}

//------------------------------------------------------------------------------
int StepperDriver::MaterialIndex(const std::string& name)
{
  const auto& names = MaterialNames();
  for (size_t k = 0; k < names.size(); ++k)
  {
    if (names[k] == name)
    {
      return static_cast<int>(k);
    }
  }
  return -1;
}

//------------------------------------------------------------------------------
std::string StepperDriver::ParseMaterial(const std::string& name, int& index)
{
  index = MaterialIndex(name);
  if (index >= 0)
  {
    return std::string();
  }
  std::ostringstream o;
  o << "Material '" << name << "' is not one of";
  const auto& names = MaterialNames();
  for (size_t k = 0; k < names.size(); ++k)
  {
    o << (k ? ", " : " ") << names[k];
  }
  o << ".";
  return o.str();
}

//------------------------------------------------------------------------------
std::string StepperDriver::CheckMaterial(const StepperParameters& p)
{
  std::ostringstream o;
  o.precision(17);
  const auto& names = MaterialNames();
  if (p.Material < 0 || p.Material >= static_cast<int>(names.size()))
  {
    o << "Material must be one of";
    for (size_t k = 0; k < names.size(); ++k)
    {
      o << (k ? ", " : " ") << k << " (" << names[k] << ")";
    }
    o << " (got " << p.Material << ").";
    return o.str();
  }
  return std::string();
}

//------------------------------------------------------------------------------
std::string StepperDriver::SetClamps(
  const std::vector<double>& rest, const double* fixedValues, const StepperParameters& p)
{
  const long long np = static_cast<long long>(rest.size() / 3);
  std::vector<unsigned char> fixed(np, 0);
  // the points' bounding box (all points, as vtkPointSet::GetBounds)
  double bounds[6] = { 0.0, -1.0, 0.0, -1.0, 0.0, -1.0 };
  if (np > 0)
  {
    for (int i = 0; i < 3; ++i)
    {
      bounds[2 * i] = bounds[2 * i + 1] = rest[i];
    }
    for (long long q = 1; q < np; ++q)
    {
      for (int i = 0; i < 3; ++i)
      {
        const double v = rest[3 * q + i];
        bounds[2 * i] = v < bounds[2 * i] ? v : bounds[2 * i];
        bounds[2 * i + 1] = v > bounds[2 * i + 1] ? v : bounds[2 * i + 1];
      }
    }
  }
  const double diag = std::sqrt((bounds[1] - bounds[0]) * (bounds[1] - bounds[0]) +
    (bounds[3] - bounds[2]) * (bounds[3] - bounds[2]) +
    (bounds[5] - bounds[4]) * (bounds[5] - bounds[4]));
  const double tol = 1e-9 * diag;
  const double nrm[3] = { p.ClampPlaneNormal[0], p.ClampPlaneNormal[1], p.ClampPlaneNormal[2] };
  const double nlen = std::sqrt(nrm[0] * nrm[0] + nrm[1] * nrm[1] + nrm[2] * nrm[2]);
  if (p.UseClampPlane && !(nlen > 0.0))
  {
    return "ClampPlaneNormal must be a nonzero vector.";
  }
  for (long long q = 0; q < np; ++q)
  {
    const double* x = &rest[3 * q];
    bool f = fixedValues && fixedValues[q] != 0.0;
    if (p.UseClampPlane)
    {
      double d = 0.0;
      for (int i = 0; i < 3; ++i)
      {
        d += (x[i] - p.ClampPlaneOrigin[i]) * nrm[i] / nlen;
      }
      f = f || d <= tol;
    }
    if (p.UseClampBox)
    {
      const double* b = p.ClampBox;
      f = f ||
        (x[0] >= b[0] - tol && x[0] <= b[1] + tol && x[1] >= b[2] - tol && x[1] <= b[3] + tol &&
          x[2] >= b[4] - tol && x[2] <= b[5] + tol);
    }
    fixed[q] = f ? 1 : 0;
  }
  this->Solver.SetFixed(fixed.data());
  return std::string();
}

//------------------------------------------------------------------------------
std::string StepperDriver::SetPrescribedMotion(
  long long np, const double* mask, const double* targets)
{
  if (!mask)
  {
    this->Mask.clear();
    this->Targets.clear();
    return std::string();
  }
  std::vector<unsigned char> m(static_cast<size_t>(np));
  std::vector<double> t(3 * static_cast<size_t>(np), 0.0);
  for (long long q = 0; q < np; ++q)
  {
    m[q] = mask[q] != 0.0 ? 1 : 0;
    if (!m[q])
    {
      continue;
    }
    for (int i = 0; i < 3; ++i)
    {
      t[3 * q + i] = targets[3 * q + i];
    }
    if (!std::isfinite(t[3 * q]) || !std::isfinite(t[3 * q + 1]) || !std::isfinite(t[3 * q + 2]))
    {
      std::ostringstream o;
      o << "the target displacement of point " << q << " is not finite.";
      return o.str();
    }
  }
  this->Mask.swap(m);
  this->Targets.swap(t);
  return std::string();
}

//------------------------------------------------------------------------------
std::string StepperDriver::ApplyLoads(
  const double gravity[3], double prescribedSpeedLimit, long long np)
{
  const size_t n3 = 3 * static_cast<size_t>(np);
  if (!this->NodalForces.empty() && this->NodalForces.size() != n3)
  {
    std::ostringstream o;
    o << "SetNodalForces: the array has " << this->NodalForces.size() / 3 << " tuples, expected "
      << np << " (one per input point).";
    return o.str();
  }
  if (!this->Mask.empty() && this->Mask.size() != static_cast<size_t>(np))
  {
    std::ostringstream o;
    o << "SetPrescribedMotion: the arrays have " << this->Mask.size() << " tuples, expected " << np
      << " (one per input point).";
    return o.str();
  }
  if (this->NodalForces.empty())
  {
    this->Solver.SetExternalForces(
      gravity, this->ArrayForces.empty() ? nullptr : this->ArrayForces.data());
  }
  else
  {
    std::vector<double> f = this->NodalForces;
    for (size_t k = 0; k < this->ArrayForces.size(); ++k)
    {
      f[k] += this->ArrayForces[k];
    }
    this->Solver.SetExternalForces(gravity, f.data());
  }
  this->Solver.SetPrescribedMotion(this->Mask.empty() ? nullptr : this->Mask.data(),
    this->Mask.empty() ? nullptr : this->Targets.data());
  this->Solver.SetPrescribedSpeedLimit(prescribedSpeedLimit);
  return std::string();
}

//------------------------------------------------------------------------------
void StepperDriver::SetInitialState(
  const std::vector<double>& rest, const double* u0, const double* v0)
{
  this->InitialX = rest;
  this->InitialV.assign(rest.size(), 0.0);
  for (size_t k = 0; k < rest.size(); ++k)
  {
    if (u0)
    {
      this->InitialX[k] += u0[k];
    }
    if (v0)
    {
      this->InitialV[k] = v0[k];
    }
  }
}

//------------------------------------------------------------------------------
void StepperDriver::Start(const StepperParameters& p)
{
  this->Solver.SetTimeStep(p.TimeStep);
  this->Solver.SetRayleighDamping(p.RayleighMass, p.RayleighStiffness);
  this->Solver.SetSolverControls(p.SolverTolerance, p.MaxSolverIterations);
  this->Solver.SetNewtonControls(p.NewtonTolerance, p.MaxNewtonIterations);
  this->Solver.SetState(this->InitialX.data(), this->InitialV.data());
  this->CurrentStep = 0;
  this->ResetRequested = false;
}

//------------------------------------------------------------------------------
std::string StepperDriver::CheckFixedArray(
  const char* name, FixedArrayKind kind, long long tuples, long long numberOfPoints)
{
  if (!name || !*name)
  {
    return std::string();
  }
  std::ostringstream o;
  o << "FixedArrayName '" << name << "' ";
  switch (kind)
  {
    case FixedArrayKind::NotNumeric:
      // an array of that name that is not numeric point data would clamp nothing
      // silently: refused, whether named by the user or the default "Fixed"
      o << "is a point-data array that is not numeric (e.g. strings): the clamps need "
           "numbers (nonzero = clamped).";
      return o.str();
    case FixedArrayKind::CellOrField:
      o << "is cell or field data, not point data: the clamps are per node (nonzero = "
           "clamped).";
      return o.str();
    case FixedArrayKind::Absent:
      if (std::string(name) == ArrayNames::Fixed)
      {
        return std::string(); // the default: no clamps from an array
      }
      o << "is not a point-data array of the input.";
      return o.str();
    case FixedArrayKind::Numeric:
      break;
  }
  if (tuples != numberOfPoints)
  {
    o << "has " << tuples << " tuples, expected " << numberOfPoints << " (one per point).";
    return o.str();
  }
  return std::string();
}

//------------------------------------------------------------------------------
std::string StepperDriver::BuildSignature(
  const StepperParameters& p, bool staticSolve, const std::vector<const char*>& arrayNames)
{
  std::ostringstream o;
  o.precision(17);
  o << p.YoungModulus << ' ' << p.PoissonRatio << ' ' << p.Density << ' ' << p.RayleighMass << ' '
    << p.RayleighStiffness << ' ' << p.TimeStep << ' ' << staticSolve << p.LumpedMass
    << p.UseClampPlane << p.UseClampBox;
  for (int i = 0; i < 3; ++i)
  {
    o << ' ' << p.ClampPlaneOrigin[i] << ' ' << p.ClampPlaneNormal[i];
  }
  for (int i = 0; i < 6; ++i)
  {
    o << ' ' << p.ClampBox[i];
  }
  o << ' ' << p.SolverTolerance << ' ' << p.MaxSolverIterations << ' ' << p.Material << ' '
    << p.MooneyRivlinC10 << ' ' << p.MooneyRivlinC01 << ' ' << p.NewtonTolerance << ' '
    << p.MaxNewtonIterations;
  for (const char* name : arrayNames)
  {
    o << '\n' << (name ? std::string(name) : std::string("\x01"));
  }
  return o.str();
}

//------------------------------------------------------------------------------
void StepperDriver::RequestStep(long long k, bool built)
{
  const long long now = built ? this->ClockStep() : 0;
  this->PendingSteps = std::max(0LL, k - now);
}

//------------------------------------------------------------------------------
std::string StepperDriver::PrepareLiveStep(const double gravity[3], double prescribedSpeedLimit,
  long long numberOfPoints, bool timed, long long requested, long long& target)
{
  if (this->ResetRequested)
  {
    this->Solver.SetState(this->InitialX.data(), this->InitialV.data());
    this->CurrentStep = 0;
    this->ResetRequested = false;
  }
  const std::string error = this->ApplyLoads(gravity, prescribedSpeedLimit, numberOfPoints);
  if (!error.empty())
  {
    this->PendingSteps = 0;
    return error;
  }
  this->StaticDone = false; // the loads may have changed
  // never backwards: an earlier (or no) time is the current state
  target = std::max<long long>(timed ? requested : 0, this->CurrentStep + this->PendingSteps);
  this->PendingSteps = 0;
  return std::string();
}

//------------------------------------------------------------------------------
void StepperDriver::WriteFrame(double* points, double* displacements, double* velocities,
  double* rotations, double* vonMises) const
{
  const size_t n3 = 3 * static_cast<size_t>(this->Solver.GetNumberOfPoints());
  const double* x = this->Solver.GetPositions();
  const double* v = this->Solver.GetVelocities();
  const double* X = this->Solver.GetRestPositions();
  for (size_t k = 0; k < n3; ++k)
  {
    if (points)
    {
      points[k] = x[k];
    }
    if (displacements)
    {
      displacements[k] = x[k] - X[k];
    }
    if (velocities)
    {
      velocities[k] = v[k];
    }
  }
  if (rotations)
  {
    this->Solver.ComputeNodalRotations(rotations);
  }
  if (vonMises)
  {
    this->Solver.ComputeVonMises(vonMises);
  }
}

//------------------------------------------------------------------------------
std::string StepperDriver::Advance(
  long long k, bool staticSolve, double timeStep, const std::function<void(double)>& progress)
{
  this->Solver.ResetTimings();
  if (staticSolve)
  {
    if (!this->StaticDone)
    {
      this->Solver.SetState(this->InitialX.data(), nullptr);
      std::string error;
      if (!this->Solver.SolveStatic(100, 1e-10, error))
      {
        return "StaticSolve failed: " + error + ".";
      }
      this->StaticDone = true;
    }
    return std::string();
  }
  if (k < this->CurrentStep)
  {
    this->Solver.SetState(this->InitialX.data(), this->InitialV.data());
    this->CurrentStep = 0;
  }
  const long long todo = k - this->CurrentStep;
  for (long long s = 0; s < todo; ++s)
  {
    if (!this->Solver.Step())
    {
      std::ostringstream o;
      o << "Non-finite state at time step " << this->CurrentStep + 1
        << " (t = " << (this->CurrentStep + 1) * timeStep << "): reduce TimeStep or the loads.";
      return o.str();
    }
    ++this->CurrentStep;
    if (progress && todo > 1 && (s % 16 == 0 || s + 1 == todo))
    {
      progress(static_cast<double>(s + 1) / static_cast<double>(todo));
    }
  }
  return std::string();
}
} // namespace hoembed
