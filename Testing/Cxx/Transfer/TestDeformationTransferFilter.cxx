// vtkDeformationTransferFilter: kernels against VTK's own cells, identity, rigid exactness
// (normal-offset and barycentric, tet10 and tet4), a bend+twist against an independent
// reference, nodal-rotation normals, caching, time forwarding, output normals, bad input.
#include "hoembedTestUtilities.h"
#include "hoembedTransferKernel.h"
#include "hoembedTransferTestUtilities.h"
#include "vtkDeformationTransferFilter.h"
#include "vtkTet10Mesher.h"

#include "vtkCallbackCommand.h"
#include "vtkCommand.h"
#include "vtkFloatArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkMath.h"
#include "vtkOBJReader.h"
#include "vtkObjectFactory.h"
#include "vtkTriangle.h"
#include "vtkPolyDataNormals.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkUnstructuredGridAlgorithm.h"

#include <cmath>
#include <random>
#include <string>
#include <vector>

using namespace hoembed_test;

namespace
{
// Collects error and warning messages of an object.
struct Messages
{
  std::vector<std::string> Errors, Warnings;
  static void Callback(vtkObject*, unsigned long event, void* client, void* data)
  {
    auto* self = static_cast<Messages*>(client);
    (event == vtkCommand::ErrorEvent ? self->Errors : self->Warnings)
      .push_back(data ? static_cast<const char*>(data) : "");
  }
  void Watch(vtkObject* o)
  {
    vtkNew<vtkCallbackCommand> cb;
    cb->SetCallback(&Messages::Callback);
    cb->SetClientData(this);
    o->AddObserver(vtkCommand::ErrorEvent, cb);
    o->AddObserver(vtkCommand::WarningEvent, cb);
  }
  bool ErrorContains(const std::string& s) const
  {
    for (const auto& e : Errors)
      if (e.find(s) != std::string::npos)
        return true;
    return false;
  }
  void Clear()
  {
    Errors.clear();
    Warnings.clear();
  }
};

// A gently curved box: the boundary's tri6 faces are really curved.
void Curve(double x[3])
{
  const double y = x[1], z = x[2];
  x[0] += 0.05 * std::sin(2.0 * y + z);
  x[1] += 0.08 * std::sin(1.3 * x[0]);
  x[2] += 0.06 * std::cos(1.7 * x[0] + y);
}

double MaxDiff(vtkPoints* a, const std::vector<double>& b)
{
  double m = 0.0;
  for (vtkIdType i = 0; i < a->GetNumberOfPoints(); ++i)
  {
    double x[3];
    a->GetPoint(i, x);
    m = std::max(m, std::sqrt(vtkMath::Distance2BetweenPoints(x, &b[3 * i])));
  }
  return m;
}

std::vector<double> Coordinates(vtkPoints* p)
{
  std::vector<double> out(3 * p->GetNumberOfPoints());
  for (vtkIdType i = 0; i < p->GetNumberOfPoints(); ++i)
    p->GetPoint(i, &out[3 * i]);
  return out;
}

// A random rotation (unit quaternion) and translation.
void RandomRigid(std::mt19937& rng, double R[3][3], double t[3])
{
  std::normal_distribution<double> g(0.0, 1.0);
  double q[4] = { g(rng), g(rng), g(rng), g(rng) };
  const double len = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  for (double& c : q)
    c /= len;
  vtkMath::QuaternionToMatrix3x3(q, R);
  for (int d = 0; d < 3; ++d)
    t[d] = 5.0 * g(rng);
}

vtkSmartPointer<vtkPolyData> Run(
  vtkDeformationTransferFilter* f, vtkPolyData* surface, vtkUnstructuredGrid* mesh)
{
  f->SetInputData(0, surface);
  f->SetInputData(1, mesh);
  f->Update();
  return f->GetOutput();
}

// Transfer `surface` onto a random rigid motion of `mesh`; returns the largest distance,
// relative to `diag`, of the result from the same motion applied to `reference`.
double RigidError(vtkDeformationTransferFilter* f, vtkPolyData* surface, vtkUnstructuredGrid* mesh,
  vtkPoints* reference, std::mt19937& rng, double diag)
{
  double R[3][3], t[3];
  RandomRigid(rng, R, t);
  auto moved = Deformed(mesh, [&](const double* x, double* y) {
    vtkMath::Multiply3x3(R, x, y);
    for (int d = 0; d < 3; ++d)
      y[d] += t[d];
  });
  auto out = Run(f, surface, moved);
  std::vector<double> expect(3 * reference->GetNumberOfPoints());
  for (vtkIdType i = 0; i < reference->GetNumberOfPoints(); ++i)
  {
    double x[3];
    reference->GetPoint(i, x);
    vtkMath::Multiply3x3(R, x, &expect[3 * i]);
    for (int d = 0; d < 3; ++d)
      expect[3 * i + d] += t[d];
  }
  return MaxDiff(out->GetPoints(), expect) / diag;
}

// A source of meshes over time: the rest mesh rotated by angle t about z (TIME_STEPS 0,1,2).
class TimeRotatedMesh : public vtkUnstructuredGridAlgorithm
{
public:
  static TimeRotatedMesh* New();
  vtkTypeMacro(TimeRotatedMesh, vtkUnstructuredGridAlgorithm);
  vtkSmartPointer<vtkUnstructuredGrid> Rest;

protected:
  TimeRotatedMesh()
  {
    this->SetNumberOfInputPorts(0);
  }
  int RequestInformation(
    vtkInformation*, vtkInformationVector**, vtkInformationVector* out) override
  {
    double steps[3] = { 0.0, 1.0, 2.0 };
    double range[2] = { 0.0, 2.0 };
    out->GetInformationObject(0)->Set(vtkStreamingDemandDrivenPipeline::TIME_STEPS(), steps, 3);
    out->GetInformationObject(0)->Set(vtkStreamingDemandDrivenPipeline::TIME_RANGE(), range, 2);
    return 1;
  }
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector* out) override
  {
    vtkInformation* info = out->GetInformationObject(0);
    double t = info->Has(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP())
      ? info->Get(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP())
      : 0.0;
    auto mesh = Deformed(this->Rest, [t](const double* x, double* y) {
      y[0] = std::cos(t) * x[0] - std::sin(t) * x[1];
      y[1] = std::sin(t) * x[0] + std::cos(t) * x[1];
      y[2] = x[2];
    });
    vtkUnstructuredGrid* o = vtkUnstructuredGrid::GetData(out, 0);
    o->ShallowCopy(mesh);
    o->GetInformation()->Set(vtkDataObject::DATA_TIME_STEP(), t);
    return 1;
  }
};
vtkStandardNewMacro(TimeRotatedMesh);

void TestKernels()
{
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  // Monomial cell coefficients == VTK's shape functions, tet10 and tet4.
  for (int npc : { 10, 4 })
  {
    std::vector<double> x(3 * npc);
    for (double& v : x)
      v = uni(rng);
    std::vector<std::int64_t> conn(npc);
    for (int a = 0; a < npc; ++a)
      conn[a] = a;
    std::vector<double> coeffs(hoembed::CellCoefficientSize(npc));
    hoembed::ComputeCellMapCoefficients(conn.data(), npc, x.data(), 0, 1, coeffs.data());
    double worst = 0.0;
    for (int k = 0; k < 50; ++k)
    {
      hoembed::TransferEntry e{ { 0.5 * uni(rng) + 0.3, 0.5 * uni(rng) + 0.2, 0.7 * uni(rng) }, 0.0,
        0, -1 };
      double w[10], ref[3] = { 0, 0, 0 }, got[3];
      if (npc == 10)
        vtkQuadraticTetra::InterpolationFunctions(e.PC, w);
      else
        vtkTetra::InterpolationFunctions(e.PC, w);
      for (int a = 0; a < npc; ++a)
        for (int d = 0; d < 3; ++d)
          ref[d] += w[a] * x[3 * a + d];
      hoembed::EvaluateTransfer(&e, npc, coeffs.data(), nullptr, 0, 1, got);
      worst = std::max(worst, std::sqrt(vtkMath::Distance2BetweenPoints(ref, got)));
    }
    HOEMBED_CHECK(
      worst < 1e-13, "cell map coefficients (%d nodes) differ from VTK by %g", npc, worst);
  }
  // Face (u, v) <-> tet parametric coordinates round trip, all four faces.
  double worst = 0.0;
  for (int f = 0; f < 4; ++f)
    for (int k = 0; k < 20; ++k)
    {
      double uv[2] = { 0.5 * (uni(rng) + 1.0), 0.0 }, back[2], pc[3];
      uv[1] = 0.5 * (1.0 - uv[0]) * (uni(rng) + 1.0);
      hoembed::TetFaceToTetParametric(f, uv, pc);
      hoembed::TetParametricToFace(f, pc, back);
      worst = std::max(worst, std::fabs(back[0] - uv[0]) + std::fabs(back[1] - uv[1]));
    }
  HOEMBED_CHECK(
    worst < 1e-14, "TetParametricToFace does not invert TetFaceToTetParametric (%g)", worst);
}

void TestIdentityAndRigid(int order, bool barycentric)
{
  auto mesh = MakeBoxTetMesh(4, 2, 2, 4.0, 1.0, 1.0, order, Curve);
  std::vector<EmbeddedVertex> truth;
  auto surface = MakeEmbeddedSurface(
    mesh, [](const double* p) { return 0.15 * std::sin(2.0 * p[0]) + 0.05; }, 40, truth,
    barycentric);
  const double diag = Diagonal(surface);
  const char* what = barycentric ? "barycentric" : "normal-offset";
  vtkNew<vtkDeformationTransferFilter> f;
  auto out = Run(f, surface, mesh);
  HOEMBED_CHECK(out->GetNumberOfPoints() == surface->GetNumberOfPoints(), "identity: wrong size");
  const double idErr = MaxDiff(out->GetPoints(), Coordinates(surface->GetPoints())) / diag;
  HOEMBED_CHECK(idErr < 1e-10, "identity (tet%d, %s): error %g of the diagonal",
    order == 2 ? 10 : 4, what, idErr);
  HOEMBED_CHECK(out->GetPolys()->GetNumberOfCells() == surface->GetPolys()->GetNumberOfCells(),
    "topology not passed");
  HOEMBED_CHECK(
    !out->GetPointData()->GetArray("EmbeddingCellId"), "embedding arrays passed to the output");

  std::mt19937 rng(11 + order);
  double worstRigid = 0.0;
  for (int trial = 0; trial < 3; ++trial)
  {
    const double err = RigidError(f, surface, mesh, surface->GetPoints(), rng, diag);
    worstRigid = std::max(worstRigid, err);
    HOEMBED_CHECK(
      err < 1e-9, "rigid (tet%d, %s): error %g of the diagonal", order == 2 ? 10 : 4, what, err);
  }
  std::printf("generated curved box, tet%d, %s: identity error %.3g, rigid error %.3g of the "
              "diagonal\n",
    order == 2 ? 10 : 4, what, idErr, worstRigid);
  HOEMBED_CHECK(f->GetTopologyBuildCount() == 1, "topology rebuilt for new coordinates (%d builds)",
    f->GetTopologyBuildCount());
  HOEMBED_CHECK(f->GetPlanBuildCount() == 1, "plan rebuilt for new coordinates (%d builds)",
    f->GetPlanBuildCount());
}

// A smooth non-rigid deformation: bend about the y axis and twist about x.
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

void TestAgainstReference(int order)
{
  auto mesh = MakeBoxTetMesh(4, 2, 2, 4.0, 1.0, 1.0, order, Curve);
  std::vector<EmbeddedVertex> truth;
  auto surface = MakeEmbeddedSurface(
    mesh, [](const double* p) { return 0.2 * std::cos(3.0 * p[0]) - 0.05; }, 30, truth);
  const double diag = Diagonal(surface);
  auto bent = Deformed(mesh, BendTwist);
  vtkNew<vtkDeformationTransferFilter> f;
  auto out = Run(f, surface, bent);
  const double err = MaxDiff(out->GetPoints(), ReferenceTransfer(bent, truth)) / diag;
  HOEMBED_CHECK(err < 1e-12, "bend+twist (tet%d): differs from the independent reference by %g",
    order == 2 ? 10 : 4, err);
  std::printf("bend+twist, tet%d: %.3g of the diagonal from the independent reference\n",
    order == 2 ? 10 : 4, err);

  // Without EmbeddingFace (older files): the face is deduced, same result.
  auto old = vtkSmartPointer<vtkPolyData>::New();
  old->ShallowCopy(surface);
  old->GetPointData()->RemoveArray("EmbeddingFace");
  vtkNew<vtkDeformationTransferFilter> g;
  auto out2 = Run(g, old, bent);
  const double err2 = MaxDiff(out2->GetPoints(), Coordinates(out->GetPoints())) / diag;
  HOEMBED_CHECK(out2->GetNumberOfPoints() == out->GetNumberOfPoints() && err2 < 1e-13,
    "deduced faces give a different result (%g)", err2);

  // ROTATE_NORMALS: rest normals rotated by per-node rotations (a varying rotation field).
  auto rotated = vtkSmartPointer<vtkUnstructuredGrid>::New();
  rotated->ShallowCopy(bent);
  vtkNew<vtkDoubleArray> rot;
  rot->SetName("NodalRotation");
  rot->SetNumberOfComponents(9);
  rot->SetNumberOfTuples(mesh->GetNumberOfPoints());
  vtkNew<vtkDoubleArray> disp;
  disp->SetName("Displacement");
  disp->SetNumberOfComponents(3);
  disp->SetNumberOfTuples(mesh->GetNumberOfPoints());
  auto rest = PointsOf(mesh);
  std::vector<double> restNormals(rest.size()), expectNormals(rest.size());
  {
    int npc;
    auto conn = MeshConnectivity(mesh, npc);
    hoembed::TetMeshTopology topo;
    topo.Build(conn.data(), mesh->GetNumberOfCells(), npc, mesh->GetNumberOfPoints());
    hoembed::ComputeBoundaryNodeNormals(topo, rest.data(), restNormals.data());
  }
  for (vtkIdType i = 0; i < mesh->GetNumberOfPoints(); ++i)
  {
    const double* x = &rest[3 * i];
    const double a = 0.3 * x[0], b = 0.2 * x[1];
    double Ra[3][3] = { { std::cos(a), -std::sin(a), 0 }, { std::sin(a), std::cos(a), 0 },
      { 0, 0, 1 } };
    double Rb[3][3] = { { 1, 0, 0 }, { 0, std::cos(b), -std::sin(b) },
      { 0, std::sin(b), std::cos(b) } };
    double Rm[3][3];
    vtkMath::Multiply3x3(Ra, Rb, Rm);
    rot->SetTuple(i, &Rm[0][0]);
    double y[3];
    bent->GetPoint(i, y);
    double u[3] = { y[0] - x[0], y[1] - x[1], y[2] - x[2] };
    disp->SetTuple(i, u);
    vtkMath::Multiply3x3(Rm, &restNormals[3 * i], &expectNormals[3 * i]);
  }
  rotated->GetPointData()->AddArray(rot);
  rotated->GetPointData()->AddArray(disp);
  vtkNew<vtkDeformationTransferFilter> h;
  h->SetNormalModeToRotate();
  auto out3 = Run(h, surface, rotated);
  const double err3 =
    MaxDiff(out3->GetPoints(), ReferenceTransfer(bent, truth, expectNormals)) / diag;
  HOEMBED_CHECK(err3 < 1e-12, "rotated normals (tet%d): differ from the reference by %g",
    order == 2 ? 10 : 4, err3);
  const double diff3 = MaxDiff(out3->GetPoints(), Coordinates(out->GetPoints())) / diag;
  HOEMBED_CHECK(
    diff3 > 1e-4, "rotated normals give the recomputed result (%g): test cannot fail", diff3);

  // ROTATE_NORMALS without the arrays: warning, recomputed normals.
  Messages msg;
  vtkNew<vtkDeformationTransferFilter> k;
  msg.Watch(k);
  k->SetNormalModeToRotate();
  auto out4 = Run(k, surface, bent);
  HOEMBED_CHECK(!msg.Warnings.empty() && msg.Warnings[0].find("NodalRotation") != std::string::npos,
    "no warning for ROTATE_NORMALS without NodalRotation");
  HOEMBED_CHECK(MaxDiff(out4->GetPoints(), Coordinates(out->GetPoints())) / diag < 1e-14,
    "fallback does not recompute the normals");
}

// DEFORM_NORMALS: for an affine map y = A x + b the isoparametric deformation gradient is A
// at every node, so the deformed nodal normals must be normalise(A n_rest); the reference
// applies them with VTK's interpolation and the Core normal field. A shear A makes them
// differ from the recomputed (surface) normals, a rotation A must give a rigid motion.
void TestDeformNormals(int order)
{
  const int tet = order == 2 ? 10 : 4;
  auto mesh = MakeBoxTetMesh(4, 2, 2, 4.0, 1.0, 1.0, order, Curve);
  std::vector<EmbeddedVertex> truth;
  auto surface = MakeEmbeddedSurface(
    mesh, [](const double* p) { return 0.2 * std::cos(3.0 * p[0]) + 0.1; }, 30, truth);
  const double diag = Diagonal(surface);
  auto rest = PointsOf(mesh);
  std::vector<double> restNormals(rest.size());
  {
    int npc;
    auto conn = MeshConnectivity(mesh, npc);
    hoembed::TetMeshTopology topo;
    topo.Build(conn.data(), mesh->GetNumberOfCells(), npc, mesh->GetNumberOfPoints());
    hoembed::ComputeBoundaryNodeNormals(topo, rest.data(), restNormals.data());
  }
  const double c = std::cos(0.7), s = std::sin(0.7);
  const double shear[3][3] = { { 1.0, 0.1, 0.35 }, { -0.05, 1.1, 0.2 }, { 0.3, 0.0, 0.9 } };
  const double rotation[3][3] = { { c, -s, 0.0 }, { s * 0.6, c * 0.6, 0.8 },
    { -s * 0.8, -c * 0.8, 0.6 } };
  for (int which = 0; which < 2; ++which)
  {
    const auto& A = which == 0 ? shear : rotation;
    auto moved = Deformed(mesh, [&](const double* x, double* y) {
      for (int d = 0; d < 3; ++d)
        y[d] = A[d][0] * x[0] + A[d][1] * x[1] + A[d][2] * x[2] + 0.5 * (d + 1);
    });
    vtkNew<vtkDoubleArray> disp;
    disp->SetName("Displacement");
    disp->SetNumberOfComponents(3);
    disp->SetNumberOfTuples(mesh->GetNumberOfPoints());
    std::vector<double> expect(rest.size(), 0.0);
    for (vtkIdType i = 0; i < mesh->GetNumberOfPoints(); ++i)
    {
      double y[3];
      moved->GetPoint(i, y);
      const double u[3] = { y[0] - rest[3 * i], y[1] - rest[3 * i + 1], y[2] - rest[3 * i + 2] };
      disp->SetTuple(i, u);
      double m[3];
      vtkMath::Multiply3x3(A, &restNormals[3 * i], m);
      const double len = vtkMath::Norm(m);
      for (int d = 0; d < 3 && len > 0.0; ++d)
        expect[3 * i + d] = m[d] / len;
    }
    moved->GetPointData()->AddArray(disp);
    vtkNew<vtkDeformationTransferFilter> f;
    f->SetNormalModeToDeform();
    Messages msg;
    msg.Watch(f);
    auto out = Run(f, surface, moved);
    HOEMBED_CHECK(msg.Warnings.empty(), "DEFORM_NORMALS (tet%d) warned: %s", tet,
      msg.Warnings.empty() ? "" : msg.Warnings[0].c_str());
    const double err = MaxDiff(out->GetPoints(), ReferenceTransfer(moved, truth, expect)) / diag;
    HOEMBED_CHECK(err < 1e-12, "deformed normals (tet%d, %s): differ from normalise(A n) by %g",
      tet, which == 0 ? "shear" : "rotation", err);
    vtkNew<vtkDeformationTransferFilter> g; // recomputed surface normals
    auto surfaceNormals = Run(g, surface, moved);
    const double diff = MaxDiff(out->GetPoints(), Coordinates(surfaceNormals->GetPoints())) / diag;
    if (which == 0)
    {
      HOEMBED_CHECK(diff > 1e-3,
        "deformed normals (tet%d) equal the recomputed ones under a shear "
        "(%g): test cannot fail",
        tet, diff);
    }
    else
    {
      HOEMBED_CHECK(diff < 1e-12,
        "deformed normals (tet%d) differ from the recomputed ones under "
        "a rotation (%g)",
        tet, diff);
    }
    std::printf("DEFORM_NORMALS, tet%d, %s: %.3g from the reference, %.3g from the recomputed "
                "normals\n",
      tet, which == 0 ? "shear" : "rotation", err, diff);
  }
  // Without Displacement: a warning naming it, and the recomputed normals.
  auto plain = Deformed(mesh, [](const double* x, double* y) {
    y[0] = x[0] + 0.2 * x[2];
    y[1] = x[1];
    y[2] = x[2];
  });
  vtkNew<vtkDeformationTransferFilter> k;
  Messages msg;
  msg.Watch(k);
  k->SetNormalModeToDeform();
  auto out = Run(k, surface, plain);
  HOEMBED_CHECK(!msg.Warnings.empty() && msg.Warnings[0].find("Displacement") != std::string::npos,
    "no warning for DEFORM_NORMALS without Displacement");
  vtkNew<vtkDeformationTransferFilter> g;
  HOEMBED_CHECK(
    MaxDiff(out->GetPoints(), Coordinates(Run(g, surface, plain)->GetPoints())) / diag < 1e-14,
    "DEFORM_NORMALS fallback does not recompute the normals");
}

void TestTimeAndCaching()
{
  auto mesh = MakeBoxTetMesh(3, 2, 2, 3.0, 1.0, 1.0, 2, Curve);
  std::vector<EmbeddedVertex> truth;
  auto surface = MakeEmbeddedSurface(
    mesh, [](const double*) { return 0.1; }, 10, truth);
  vtkNew<TimeRotatedMesh> source;
  source->Rest = mesh;
  vtkNew<vtkDeformationTransferFilter> f;
  f->SetInputData(0, surface);
  f->SetMeshConnection(source->GetOutputPort());
  f->UpdateInformation();
  vtkInformation* outInfo = f->GetOutputInformation(0);
  HOEMBED_CHECK(outInfo->Length(vtkStreamingDemandDrivenPipeline::TIME_STEPS()) == 3,
    "TIME_STEPS not forwarded (%d)",
    outInfo->Length(vtkStreamingDemandDrivenPipeline::TIME_STEPS()));
  const double diag = Diagonal(surface);
  for (double t : { 1.0, 2.0, 0.0 })
  {
    f->UpdateTimeStep(t);
    vtkPolyData* out = f->GetOutput();
    const double dt = out->GetInformation()->Has(vtkDataObject::DATA_TIME_STEP())
      ? out->GetInformation()->Get(vtkDataObject::DATA_TIME_STEP())
      : -1.0;
    HOEMBED_CHECK(dt == t, "DATA_TIME_STEP %g, expected %g", dt, t);
    std::vector<double> expect(3 * surface->GetNumberOfPoints());
    for (vtkIdType i = 0; i < surface->GetNumberOfPoints(); ++i)
    {
      double x[3];
      surface->GetPoint(i, x);
      expect[3 * i] = std::cos(t) * x[0] - std::sin(t) * x[1];
      expect[3 * i + 1] = std::sin(t) * x[0] + std::cos(t) * x[1];
      expect[3 * i + 2] = x[2];
    }
    const double err = MaxDiff(out->GetPoints(), expect) / diag;
    HOEMBED_CHECK(
      err < 1e-9, "time %g: the surface is not the mesh's rotation at that time (%g)", t, err);
  }
  // The source makes a new grid (and a new cell array object via ShallowCopy of a fresh
  // CopyStructure) each time: the fingerprint is unchanged, so no topology rebuild.
  HOEMBED_CHECK(
    f->GetTopologyBuildCount() == 1, "topology rebuilt over time (%d)", f->GetTopologyBuildCount());
  HOEMBED_CHECK(f->GetPlanBuildCount() == 1, "plan rebuilt over time (%d)", f->GetPlanBuildCount());
  // A deep copy of the cells (a new cell array) with the same topology: no rebuild either.
  auto copy = vtkSmartPointer<vtkUnstructuredGrid>::New();
  copy->DeepCopy(mesh);
  vtkNew<vtkDeformationTransferFilter> g;
  Run(g, surface, mesh);
  Run(g, surface, copy);
  HOEMBED_CHECK(g->GetTopologyBuildCount() == 1, "deep-copied mesh rebuilt the topology (%d)",
    g->GetTopologyBuildCount());
}

void TestPointNormals()
{
  // A closed triangulated sphere-like surface is not needed: compare with VTK's own normals
  // on the transferred patch surface, where triangles of a patch have similar areas.
  auto mesh = MakeBoxTetMesh(3, 2, 2, 3.0, 1.0, 1.0, 2, Curve);
  std::vector<EmbeddedVertex> truth;
  auto surface = MakeEmbeddedSurface(
    mesh, [](const double*) { return 0.1; }, 0, truth);
  vtkNew<vtkDeformationTransferFilter> f;
  f->ComputePointNormalsOn();
  auto out = Run(f, surface, Deformed(mesh, BendTwist));
  auto* n = vtkFloatArray::SafeDownCast(out->GetPointData()->GetNormals());
  HOEMBED_CHECK(n && n->GetNumberOfTuples() == out->GetNumberOfPoints(), "no point normals");
  if (!n)
    return;
  vtkNew<vtkPolyDataNormals> ref;
  ref->SetInputData(out);
  ref->SplittingOff();
  ref->ConsistencyOff();
  ref->AutoOrientNormalsOff();
  ref->ComputePointNormalsOn();
  ref->Update();
  vtkDataArray* rn = ref->GetOutput()->GetPointData()->GetNormals();
  double worst = 0.0;
  for (vtkIdType i = 0; i < out->GetNumberOfPoints(); ++i)
  {
    double a[3], b[3];
    n->GetTuple(i, a);
    rn->GetTuple(i, b);
    worst = std::max(worst, vtkMath::DegreesFromRadians(vtkMath::AngleBetweenVectors(a, b)));
  }
  HOEMBED_CHECK(worst < 10.0, "point normals differ from vtkPolyDataNormals by %g degrees", worst);
  // Single precision output when asked: the same points to float precision.
  const std::vector<double> doubles = Coordinates(out->GetPoints());
  f->SetOutputPointsPrecision(vtkAlgorithm::SINGLE_PRECISION);
  f->Update();
  HOEMBED_CHECK(f->GetOutput()->GetPoints()->GetDataType() == VTK_FLOAT, "not single precision");
  const double ferr = MaxDiff(f->GetOutput()->GetPoints(), doubles) / Diagonal(out);
  HOEMBED_CHECK(ferr < 1e-6 && ferr > 0.0, "single precision output differs by %g", ferr);
}

void TestBadInput()
{
  auto mesh = MakeBoxTetMesh(3, 2, 2, 3.0, 1.0, 1.0, 2, Curve);
  std::vector<EmbeddedVertex> truth;
  auto surface = MakeEmbeddedSurface(
    mesh, [](const double*) { return 0.1; }, 10, truth);
  auto check = [&](vtkPolyData* s, vtkUnstructuredGrid* m, const char* expect, const char* what) {
    vtkNew<vtkDeformationTransferFilter> f;
    Messages msg;
    msg.Watch(f);
    vtkSmartPointer<vtkPolyData> out = Run(f, s, m);
    HOEMBED_CHECK(msg.ErrorContains(expect), "%s: no error mentioning '%s' (%zu errors)", what,
      expect, msg.Errors.size());
    HOEMBED_CHECK(out->GetNumberOfPoints() == 0, "%s: output not empty", what);
  };
  for (const char* name : { "EmbeddingCellId", "EmbeddingParametricCoords", "EmbeddingDistance" })
  {
    auto s = vtkSmartPointer<vtkPolyData>::New();
    s->DeepCopy(surface);
    s->GetPointData()->RemoveArray(name);
    check(s, mesh, name, "missing array");
  }
  {
    auto s = vtkSmartPointer<vtkPolyData>::New();
    s->DeepCopy(surface);
    s->GetFieldData()->RemoveArray("EmbeddingMeshFingerprint");
    check(s, mesh, "EmbeddingMeshFingerprint", "missing fingerprint");
    s->DeepCopy(surface);
    s->GetFieldData()->RemoveArray("EmbeddingMethod");
    check(s, mesh, "EmbeddingMethod", "missing method");
  }
  {
    auto other = MakeBoxTetMesh(3, 2, 3, 3.0, 1.0, 1.0, 2, Curve);
    check(surface, other, "not the mesh the surface was embedded in", "mismatched mesh");
    auto tet4 = MakeBoxTetMesh(3, 2, 2, 3.0, 1.0, 1.0, 1, Curve);
    check(surface, tet4, "not the mesh the surface was embedded in", "tet4 instead of tet10");
  }
  {
    auto nan = Deformed(mesh, [](const double* x, double* y) {
      for (int d = 0; d < 3; ++d)
        y[d] = x[d];
    });
    nan->GetPoints()->SetPoint(5, std::nan(""), 0.0, 0.0);
    check(surface, nan, "non-finite", "NaN in the deformed mesh");
  }
  {
    auto s = vtkSmartPointer<vtkPolyData>::New();
    s->DeepCopy(surface);
    vtkDataArray::SafeDownCast(s->GetPointData()->GetArray("EmbeddingCellId"))
      ->SetComponent(3, 0, 99999);
    check(s, mesh, "cell id outside", "cell id out of range");
  }
  {
    // Inverted elements: a warning, the transfer is still computed and finite.
    auto flat = Deformed(mesh, [](const double* x, double* y) {
      y[0] = x[0];
      y[1] = x[1];
      y[2] = x[0] > 1.5 ? -x[2] : x[2]; // mirror half the beam: inverts those elements
    });
    vtkNew<vtkDeformationTransferFilter> f;
    Messages msg;
    msg.Watch(f);
    auto out = Run(f, surface, flat);
    HOEMBED_CHECK(msg.Errors.empty(), "inverted elements gave an error");
    HOEMBED_CHECK(!msg.Warnings.empty() && msg.Warnings[0].find("inverted") != std::string::npos,
      "no warning for inverted elements");
    HOEMBED_CHECK(f->GetNumberOfInvertedElements() > 0, "inverted elements not counted");
    bool finite = out->GetNumberOfPoints() == surface->GetNumberOfPoints();
    for (vtkIdType i = 0; finite && i < out->GetNumberOfPoints(); ++i)
    {
      double x[3];
      out->GetPoint(i, x);
      finite = std::isfinite(x[0]) && std::isfinite(x[1]) && std::isfinite(x[2]);
    }
    HOEMBED_CHECK(finite, "inverted elements: output missing or not finite");
    // And the rest mesh has none.
    Run(f, surface, mesh);
    HOEMBED_CHECK(f->GetNumberOfInvertedElements() == 0, "rest mesh reported inverted");
  }
}
// Real surfaces (../shared/data/meshes) embedded in a curved tet10 / tet4 box mesh inside
// their bounding box: vertices outside the box get p = the closest point on the (straight)
// box boundary, found by brute force over the boundary faces, and d = |v - p|; vertices
// inside get their cell and d = 0. The FE mesh is then curved; whatever the embedding's
// accuracy, a rigid motion of the mesh must move the transferred surface rigidly.
void TestRealMeshes(const std::string& dir)
{
  for (const char* name : { "bunny_lowres.obj", "fandisk.obj", "scorpion_low_resolution.obj" })
  {
    vtkNew<vtkOBJReader> reader;
    reader->SetFileName((dir + "/" + name).c_str());
    reader->Update();
    vtkPolyData* fine = reader->GetOutput();
    HOEMBED_CHECK(fine->GetNumberOfPoints() > 0, "%s: could not read", name);
    if (fine->GetNumberOfPoints() == 0)
      continue;
    double b[6];
    fine->GetBounds(b);
    double lo[3], ext[3];
    for (int d = 0; d < 3; ++d)
    {
      ext[d] = 0.6 * (b[2 * d + 1] - b[2 * d]);
      lo[d] = b[2 * d] + 0.2 * (b[2 * d + 1] - b[2 * d]);
    }
    for (int order : { 2, 1 })
    {
      auto straight = MakeBoxTetMesh(4, 3, 3, ext[0], ext[1], ext[2], order, [&](double x[3]) {
        for (int d = 0; d < 3; ++d)
          x[d] += lo[d];
      });
      int npc;
      auto conn = MeshConnectivity(straight, npc);
      hoembed::TetMeshTopology topo;
      topo.Build(conn.data(), straight->GetNumberOfCells(), npc, straight->GetNumberOfPoints());
      const vtkIdType n = fine->GetNumberOfPoints();
      std::vector<EmbeddedVertex> truth(n);
      vtkNew<vtkTriangle> tri;
      for (vtkIdType i = 0; i < n; ++i)
      {
        double v[3];
        fine->GetPoint(i, v);
        EmbeddedVertex& e = truth[i];
        double best = VTK_DOUBLE_MAX;
        for (vtkIdType f = 0; f < topo.GetNumberOfBoundaryFaces(); ++f)
        {
          const auto* fn = &topo.BoundaryFaceNodes[f * topo.GetNodesPerFace()];
          double a[3], bb[3], c[3], closest[3], w[3], pcs[3], dist2;
          straight->GetPoint(fn[0], a);
          straight->GetPoint(fn[1], bb);
          straight->GetPoint(fn[2], c);
          tri->GetPoints()->SetPoint(0, a);
          tri->GetPoints()->SetPoint(1, bb);
          tri->GetPoints()->SetPoint(2, c);
          int sub;
          tri->EvaluatePosition(v, closest, sub, pcs, dist2, w);
          if (dist2 < best)
          {
            best = dist2;
            e.Boundary = f;
            e.Cell = topo.BoundaryFaceCell[f];
            e.LocalFace = topo.BoundaryFaceLocal[f];
            e.UV[0] = w[1];
            e.UV[1] = w[2];
          }
        }
        hoembed::TetFaceToTetParametric(e.LocalFace, e.UV, e.PC);
        e.Distance = std::sqrt(best);
        const bool inside = v[0] > lo[0] && v[0] < lo[0] + ext[0] && v[1] > lo[1] &&
          v[1] < lo[1] + ext[1] && v[2] > lo[2] && v[2] < lo[2] + ext[2];
        if (inside)
        {
          double pc[3], w[10];
          int sub;
          e.Cell = straight->FindCell(v, nullptr, -1, 1e-9, sub, pc, w);
          e.PC[0] = pc[0];
          e.PC[1] = pc[1];
          e.PC[2] = pc[2];
          e.Distance = 0.0;
          e.LocalFace = -1;
        }
      }
      // The surface with these arrays, without EmbeddingFace (deduced by the filter).
      auto surface = vtkSmartPointer<vtkPolyData>::New();
      surface->ShallowCopy(fine);
      vtkNew<vtkIdTypeArray> cellId;
      cellId->SetName("EmbeddingCellId");
      vtkNew<vtkDoubleArray> pcoords;
      pcoords->SetName("EmbeddingParametricCoords");
      pcoords->SetNumberOfComponents(3);
      vtkNew<vtkDoubleArray> dist;
      dist->SetName("EmbeddingDistance");
      for (vtkIdType i = 0; i < n; ++i)
      {
        cellId->InsertNextValue(truth[i].Cell);
        pcoords->InsertNextTuple(truth[i].PC);
        dist->InsertNextValue(truth[i].Distance);
      }
      surface->GetPointData()->AddArray(cellId);
      surface->GetPointData()->AddArray(pcoords);
      surface->GetPointData()->AddArray(dist);
      vtkNew<vtkStringArray> method;
      method->SetName("EmbeddingMethod");
      method->InsertNextValue("normal-offset");
      vtkNew<vtkStringArray> fp;
      fp->SetName("EmbeddingMeshFingerprint");
      fp->InsertNextValue(Fingerprint(straight));
      surface->GetFieldData()->AddArray(method);
      surface->GetFieldData()->AddArray(fp);

      auto curved = Deformed(straight, [&](const double* x, double* y) {
        double u[3] = { (x[0] - lo[0]) / ext[0] * 4.0, (x[1] - lo[1]) / ext[1],
          (x[2] - lo[2]) / ext[2] };
        Curve(u);
        y[0] = lo[0] + u[0] * ext[0] / 4.0;
        y[1] = lo[1] + u[1] * ext[1];
        y[2] = lo[2] + u[2] * ext[2];
      });
      const double diag = Diagonal(fine);
      for (const char* m : { "normal-offset", "barycentric" })
      {
        method->SetValue(0, m);
        method->Modified();
        surface->Modified();
        vtkNew<vtkDeformationTransferFilter> f;
        f->SetOutputPointsPrecision(vtkAlgorithm::DOUBLE_PRECISION); // OBJ points are float
        auto rest = vtkSmartPointer<vtkPolyData>::New();
        rest->DeepCopy(Run(f, surface, curved));
        HOEMBED_CHECK(rest->GetNumberOfPoints() == n, "%s: transfer failed", name);
        if (rest->GetNumberOfPoints() != n)
          continue;
        std::mt19937 rng(99);
        const double err = RigidError(f, surface, curved, rest->GetPoints(), rng, diag);
        std::printf("real mesh %s, tet%d, %s: %lld vertices, rigid error %.3g of the diagonal\n",
          name, order == 2 ? 10 : 4, m, static_cast<long long>(n), err);
        HOEMBED_CHECK(err < 1e-9, "%s tet%d %s: rigid error %g of the diagonal", name,
          order == 2 ? 10 : 4, m, err);
      }
    }
  }
}
// Real curved meshes (vtkTet10Mesher on the real surfaces) carrying surfaces embedded by
// construction: identity, rigid exactness and a bend against the independent reference.
void TestRealCurvedMeshes(const std::string& dir)
{
  for (const char* name : { "bunny_lowres.obj", "fandisk.obj" })
  {
    vtkNew<vtkOBJReader> reader;
    reader->SetFileName((dir + "/" + name).c_str());
    for (int order : { 2, 1 })
    {
      vtkNew<vtkTet10Mesher> mesher;
      mesher->SetInputConnection(reader->GetOutputPort());
      mesher->SetTargetNumberOfElements(400);
      mesher->SetElementOrder(order);
      mesher->Update();
      vtkUnstructuredGrid* mesh = mesher->GetOutput();
      HOEMBED_CHECK(mesh->GetNumberOfCells() > 0, "%s: mesher failed", name);
      if (mesh->GetNumberOfCells() == 0)
        continue;
      const double size = mesh->GetLength();
      std::vector<EmbeddedVertex> truth;
      auto surface = MakeEmbeddedSurface(
        mesh,
        [size](const double* p) { return size * (0.02 + 0.01 * std::sin(40.0 * p[0] / size)); }, 50,
        truth);
      const double diag = Diagonal(surface);
      vtkNew<vtkDeformationTransferFilter> f;
      auto rest = Run(f, surface, mesh);
      const double idErr = MaxDiff(rest->GetPoints(), Coordinates(surface->GetPoints())) / diag;
      HOEMBED_CHECK(idErr < 1e-10, "%s tet%d: identity error %g", name, order == 2 ? 10 : 4, idErr);
      std::mt19937 rng(5);
      const double rigidErr = RigidError(f, surface, mesh, surface->GetPoints(), rng, diag);
      HOEMBED_CHECK(
        rigidErr < 1e-9, "%s tet%d: rigid error %g", name, order == 2 ? 10 : 4, rigidErr);
      // A smooth non-rigid map (a swirl about z), against the independent reference.
      double c[3];
      mesh->GetCenter(c);
      auto swirled = Deformed(mesh, [&](const double* x, double* y) {
        const double a = 2.0 * (x[2] - c[2]) / size;
        y[0] = c[0] + std::cos(a) * (x[0] - c[0]) - std::sin(a) * (x[1] - c[1]);
        y[1] = c[1] + std::sin(a) * (x[0] - c[0]) + std::cos(a) * (x[1] - c[1]);
        y[2] = x[2];
      });
      auto sw = Run(f, surface, swirled);
      const double refErr = MaxDiff(sw->GetPoints(), ReferenceTransfer(swirled, truth)) / diag;
      HOEMBED_CHECK(refErr < 1e-12, "%s tet%d: swirl differs from the reference by %g", name,
        order == 2 ? 10 : 4, refErr);
      std::printf("real curved mesh %s (vtkTet10Mesher, tet%d, %lld cells, %lld surface points): "
                  "identity %.3g, rigid %.3g, swirl vs reference %.3g of the diagonal\n",
        name, order == 2 ? 10 : 4, static_cast<long long>(mesh->GetNumberOfCells()),
        static_cast<long long>(surface->GetNumberOfPoints()), idErr, rigidErr, refErr);
    }
  }
}
} // namespace

int main(int argc, char* argv[])
{
  TestKernels();
  for (int order : { 2, 1 })
  {
    TestIdentityAndRigid(order, false);
    TestIdentityAndRigid(order, true);
    TestAgainstReference(order);
    TestDeformNormals(order);
  }
  TestTimeAndCaching();
  TestPointNormals();
  TestBadInput();
  const std::string dir = DataDir(argc, argv);
  if (!dir.empty())
  {
    TestRealMeshes(dir);
    TestRealCurvedMeshes(dir);
  }
  else
    std::printf("real meshes not available: skipped that part\n");
  return Report("TestDeformationTransferFilter");
}
