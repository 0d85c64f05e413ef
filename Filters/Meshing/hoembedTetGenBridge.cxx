#include "hoembedTetGenBridge.h"

#include "tetgen.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <new>
#include <sstream>
#include <utility>

namespace hoembed
{
namespace
{
// The abort callback of the innermost ScopedTetGenAbort of this thread.
thread_local const std::function<bool()>* CurrentAbort = nullptr;

// What TetGen's checkpoint (HOEmbed's patch) counts and decides.
struct Watchdog
{
  std::uint64_t Created = 0;
  std::uint64_t Budget = 0;
  const std::function<bool()>* Abort = nullptr;
  int Stop = 0; // 1: work bound, 2: aborted
};

#ifdef HOEMBED_TETGEN_CHECKPOINT_PATCH
int Checkpoint(void* data)
{
  auto* w = static_cast<Watchdog*>(data);
  if (++w->Created > w->Budget)
  {
    w->Stop = 1;
    return 1;
  }
  if ((w->Created & 4095u) == 0 && w->Abort && *w->Abort && (*w->Abort)())
  {
    w->Stop = 2;
    return 1;
  }
  return 0;
}

// Installs the checkpoint for one TetGen run; restores the previous one on any exit.
class CheckpointGuard
{
public:
  explicit CheckpointGuard(Watchdog* w)
    : OldFn(hoembed_tetgen_checkpoint), OldData(hoembed_tetgen_checkpoint_data)
  {
    hoembed_tetgen_checkpoint = &Checkpoint;
    hoembed_tetgen_checkpoint_data = w;
  }
  ~CheckpointGuard()
  {
    hoembed_tetgen_checkpoint = this->OldFn;
    hoembed_tetgen_checkpoint_data = this->OldData;
  }

private:
  int (*OldFn)(void*);
  void* OldData;
};
#endif

double SurfaceVolume(const std::vector<double>& pts, const std::vector<std::int64_t>& tris)
{
  double v = 0.0;
  for (size_t t = 0; t < tris.size() / 3; ++t)
  {
    const double* a = &pts[3 * tris[3 * t]];
    const double* b = &pts[3 * tris[3 * t + 1]];
    const double* c = &pts[3 * tris[3 * t + 2]];
    v += (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
           a[2] * (b[0] * c[1] - b[1] * c[0])) /
      6.0;
  }
  return v;
}

// A point inside each cavity of a closed surface: TetGen meshes the convex hull and
// removes only what its exterior reaches, so the inside of a closed inner shell (a
// component whose signed volume has the sign opposite to the whole surface's: its
// triangles face into it) would be filled unless it is named as a hole. The point lies a
// hundredth of the height of the shell's largest triangle off its centroid, on the side
// its normal (times the whole surface's orientation) points to.
std::vector<double> CavityPoints(
  const std::vector<double>& pts, const std::vector<std::int64_t>& tris)
{
  const size_t np = pts.size() / 3, nt = tris.size() / 3;
  std::vector<size_t> parent(np);
  for (size_t i = 0; i < np; ++i)
    parent[i] = i;
  auto find = [&](size_t i) {
    while (parent[i] != i)
      i = parent[i] = parent[parent[i]];
    return i;
  };
  for (size_t t = 0; t < nt; ++t)
    for (int k = 1; k < 3; ++k)
    {
      const size_t a = find(static_cast<size_t>(tris[3 * t])),
                   b = find(static_cast<size_t>(tris[3 * t + k]));
      if (a != b)
        parent[std::max(a, b)] = std::min(a, b);
    }
  struct Shell
  {
    double Volume = 0.0, Area = -1.0;
    size_t Largest = 0;
  };
  std::vector<Shell> shells(np);
  double total = 0.0;
  for (size_t t = 0; t < nt; ++t)
  {
    const double* a = &pts[3 * tris[3 * t]];
    const double* b = &pts[3 * tris[3 * t + 1]];
    const double* c = &pts[3 * tris[3 * t + 2]];
    const double v = (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
                       a[2] * (b[0] * c[1] - b[1] * c[0])) /
      6.0;
    double u[3], w[3], n[3];
    for (int d = 0; d < 3; ++d)
    {
      u[d] = b[d] - a[d];
      w[d] = c[d] - a[d];
    }
    n[0] = u[1] * w[2] - u[2] * w[1];
    n[1] = u[2] * w[0] - u[0] * w[2];
    n[2] = u[0] * w[1] - u[1] * w[0];
    const double area = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    Shell& sh = shells[find(static_cast<size_t>(tris[3 * t]))];
    sh.Volume += v;
    total += v;
    if (area > sh.Area)
    {
      sh.Area = area;
      sh.Largest = t;
    }
  }
  std::vector<double> holes;
  for (size_t r = 0; r < np; ++r)
  {
    const Shell& sh = shells[r];
    if (sh.Area <= 0.0 || !(sh.Volume * total < 0.0))
      continue;
    const std::int64_t* f = &tris[3 * sh.Largest];
    double longest = 0.0, n[3], u[3], w[3], centroid[3];
    for (int k = 0; k < 3; ++k)
    {
      double e2 = 0.0;
      for (int d = 0; d < 3; ++d)
      {
        const double e = pts[3 * f[(k + 1) % 3] + d] - pts[3 * f[k] + d];
        e2 += e * e;
      }
      longest = std::max(longest, std::sqrt(e2));
    }
    for (int d = 0; d < 3; ++d)
    {
      u[d] = pts[3 * f[1] + d] - pts[3 * f[0] + d];
      w[d] = pts[3 * f[2] + d] - pts[3 * f[0] + d];
      centroid[d] = (pts[3 * f[0] + d] + pts[3 * f[1] + d] + pts[3 * f[2] + d]) / 3.0;
    }
    n[0] = u[1] * w[2] - u[2] * w[1];
    n[1] = u[2] * w[0] - u[0] * w[2];
    n[2] = u[0] * w[1] - u[1] * w[0];
    // |n| = 2 x area: a hundredth of the height on the longest edge (|n| / longest) along
    // n / |n|
    const double step = (total > 0.0 ? 0.01 : -0.01) / longest;
    for (int d = 0; d < 3; ++d)
      holes.push_back(centroid[d] + step * n[d]);
  }
  return holes;
}

std::string TetGenErrorText(int code)
{
  switch (code)
  {
    case 1:
      return "TetGen ran out of memory";
    case 2:
      return "TetGen hit an internal error";
    case 3:
      return "the (coarsened) surface intersects itself";
    case 4:
      return "the surface has a feature smaller than TetGen's tolerance";
    case 5:
      return "the surface has two facets that are very close to each other";
    case 10:
      return "TetGen rejected the input surface";
    default:
      break;
  }
  std::ostringstream os;
  os << "TetGen failed with code " << code;
  return os.str();
}
// Copy TetGen's output, VTK-oriented.
void CollectOutput(tetgenio& out, TetGenResult& result)
{
  result.Points.assign(out.pointlist, out.pointlist + 3 * out.numberofpoints);
  result.Tets.resize(4 * static_cast<size_t>(out.numberoftetrahedra));
  for (int t = 0; t < out.numberoftetrahedra; ++t)
  {
    std::int64_t* tet = &result.Tets[4 * t];
    for (int k = 0; k < 4; ++k)
    {
      tet[k] = out.tetrahedronlist[out.numberofcorners * t + k];
    }
    // VTK orientation: (x1 - x0) . ((x2 - x0) x (x3 - x0)) > 0
    const double* p0 = &result.Points[3 * tet[0]];
    double e[3][3];
    for (int r = 0; r < 3; ++r)
      for (int d = 0; d < 3; ++d)
        e[r][d] = result.Points[3 * tet[r + 1] + d] - p0[d];
    const double det = e[0][0] * (e[1][1] * e[2][2] - e[1][2] * e[2][1]) -
      e[0][1] * (e[1][0] * e[2][2] - e[1][2] * e[2][0]) +
      e[0][2] * (e[1][0] * e[2][1] - e[1][1] * e[2][0]);
    if (det < 0.0)
    {
      std::swap(tet[1], tet[2]);
    }
  }
  if (out.numberoftetrahedra == 0)
  {
    result.Error = "TetGen produced no tetrahedra";
  }
}

// Run `body` (which calls TetGen), turning TetGen's exceptions into result.Error.
template <typename Body>
void Guarded(TetGenResult& result, Body body)
{
  try
  {
    body();
  }
  catch (int code)
  {
    result.Error = TetGenErrorText(code);
  }
  catch (const std::bad_alloc&)
  {
    result.Error = TetGenErrorText(1);
  }
  catch (...)
  {
    result.Error = "TetGen failed with an unknown exception";
  }
  if (!result.Error.empty())
  {
    result.Points.clear();
    result.Tets.clear();
  }
}

std::string QualitySwitches(const TetGenParameters& params)
{
  std::ostringstream sw;
  sw << "q" << params.RadiusEdgeRatio << "/" << params.MinDihedralAngle;
  return sw.str();
}
} // namespace

ScopedTetGenAbort::ScopedTetGenAbort(std::function<bool()> abort)
  : Abort(std::move(abort)), Previous(CurrentAbort)
{
  CurrentAbort = &this->Abort;
}

ScopedTetGenAbort::~ScopedTetGenAbort()
{
  CurrentAbort = this->Previous;
}

bool MeshingAbortRequested()
{
  return CurrentAbort && *CurrentAbort && (*CurrentAbort)();
}

bool TetGenWorkIsBounded()
{
#ifdef HOEMBED_TETGEN_CHECKPOINT_PATCH
  return true;
#else
  return false;
#endif
}

TetGenResult RunTetGen(const std::vector<double>& pts, const std::vector<std::int64_t>& tris,
  const TetGenParameters& params)
{
  TetGenResult result;
  std::ostringstream sw;
  // F: TetGen must not write the facets it skips (self-intersections) to files in the
  // working directory; we detect skipped facets ourselves (volume check below).
  sw << "pzQF" << QualitySwitches(params);
  if (params.MaxVolume > 0.0)
  {
    sw.precision(17);
    sw << "a" << params.MaxVolume;
  }
  if (params.PreserveBoundary)
  {
    sw << "Y";
  }
  result.Switches = sw.str();
  for (const std::int64_t id : tris)
  {
    if (id < 0 || id >= static_cast<std::int64_t>(pts.size() / 3))
    {
      result.Error = "a triangle names a point that does not exist";
      return result;
    }
  }
  const double surfaceVolume = SurfaceVolume(pts, tris);
  const double expected = params.MaxVolume > 0.0 ? std::fabs(surfaceVolume) / params.MaxVolume
                                                 : static_cast<double>(tris.size() / 3);
  Watchdog watchdog;
  watchdog.Abort = CurrentAbort;
  const double budget = params.MaxCreatedTetrahedra > 0.0
    ? params.MaxCreatedTetrahedra
    : std::max(2e6, 400.0 * std::max(expected, static_cast<double>(tris.size() / 3)));
  watchdog.Budget = budget < 1.8e19 ? static_cast<std::uint64_t>(budget) : UINT64_MAX;
  Guarded(result, [&]() {
#ifdef HOEMBED_TETGEN_CHECKPOINT_PATCH
    CheckpointGuard guard(&watchdog);
#endif
    tetgenio in, out;
    in.firstnumber = 0;
    in.numberofpoints = static_cast<int>(pts.size() / 3);
    in.pointlist = new REAL[pts.size()];
    std::copy(pts.begin(), pts.end(), in.pointlist);
    const int nt = static_cast<int>(tris.size() / 3);
    in.numberoffacets = nt;
    in.facetlist = new tetgenio::facet[nt];
    for (int t = 0; t < nt; ++t)
    {
      tetgenio::facet& f = in.facetlist[t];
      f.numberofpolygons = 1;
      f.polygonlist = new tetgenio::polygon[1];
      f.numberofholes = 0;
      f.holelist = nullptr;
      f.polygonlist[0].numberofvertices = 3;
      f.polygonlist[0].vertexlist = new int[3];
      for (int k = 0; k < 3; ++k)
      {
        f.polygonlist[0].vertexlist[k] = static_cast<int>(tris[3 * t + k]);
      }
    }
    const std::vector<double> holes = CavityPoints(pts, tris);
    if (!holes.empty())
    {
      in.numberofholes = static_cast<int>(holes.size() / 3);
      in.holelist = new REAL[holes.size()];
      std::copy(holes.begin(), holes.end(), in.holelist);
    }
    std::string switches = result.Switches;
    tetrahedralize(&switches[0], &in, &out);
    CollectOutput(out, result);
  });
  result.CreatedTetrahedra = watchdog.Created;
  if (watchdog.Stop != 0)
  {
    std::ostringstream os;
    if (watchdog.Stop == 1)
    {
      os << "TetGen exceeded its work bound (" << watchdog.Budget
         << " tetrahedra created for a mesh of about " << static_cast<long long>(expected)
         << "; it was probably stuck recovering the boundary of a thin or badly shaped "
            "surface)";
    }
    else
    {
      os << "meshing was aborted (AbortExecute) during TetGen";
    }
    result.Error = os.str();
    result.Stopped = true;
    result.Aborted = watchdog.Stop == 2;
    result.Points.clear();
    result.Tets.clear();
  }
  if (result.Error.empty())
  {
    // TetGen skips facets that intersect others and meshes on: the mesh then no longer
    // fills the surface. The volumes tell. (With quality refinement TetGen's volume differs
    // from the surface's by ~1e-5 relative on real inputs, hence the loose bound; the
    // caller's own self-intersection check runs first.)
    double meshVolume = 0.0;
    for (size_t t = 0; t < result.Tets.size() / 4; ++t)
    {
      const double* p0 = &result.Points[3 * result.Tets[4 * t]];
      double e[3][3];
      for (int r = 0; r < 3; ++r)
        for (int d = 0; d < 3; ++d)
          e[r][d] = result.Points[3 * result.Tets[4 * t + r + 1] + d] - p0[d];
      meshVolume += (e[0][0] * (e[1][1] * e[2][2] - e[1][2] * e[2][1]) -
                      e[0][1] * (e[1][0] * e[2][2] - e[1][2] * e[2][0]) +
                      e[0][2] * (e[1][0] * e[2][1] - e[1][1] * e[2][0])) /
        6.0;
    }
    if (std::fabs(meshVolume - std::fabs(surfaceVolume)) > 1e-3 * std::fabs(surfaceVolume))
    {
      std::ostringstream os;
      os << "TetGen skipped self-intersecting facets of the (coarsened) surface (mesh volume "
         << meshVolume << ", surface volume " << surfaceVolume << ")";
      result.Error = os.str();
      result.Points.clear();
      result.Tets.clear();
    }
  }
  return result;
}
} // namespace hoembed
