#include "hoembedTetGenBridge.h"

#include "tetgen.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <new>
#include <sstream>
#include <utility>

namespace hoembed
{
namespace
{
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

TetGenResult RunTetGen(const std::vector<double>& pts, const std::vector<std::int64_t>& tris,
  const TetGenParameters& params)
{
  TetGenResult result;
  std::ostringstream sw;
  sw << "pzQ" << QualitySwitches(params);
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
  Guarded(result, [&]() {
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
    std::string switches = result.Switches;
    tetrahedralize(&switches[0], &in, &out);
    CollectOutput(out, result);
  });
  return result;
}
} // namespace hoembed
