/**
 * @file hoembedTetGenBridge.h
 * @brief Quality tetrahedral meshing of a closed triangle surface with TetGen (plain C++).
 *
 * TetGen (AGPL-3.0, or a commercial licence from WIAS) is compiled into this module.
 */
#ifndef hoembedTetGenBridge_h
#define hoembedTetGenBridge_h

#include "hoembedFiltersMeshingModule.h"

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace hoembed
{
struct HOEMBEDFILTERSMESHING_EXPORT TetGenParameters
{
  double RadiusEdgeRatio = 1.5;   ///< -q first value
  double MinDihedralAngle = 10.0; ///< -q second value (degrees)
  double MaxVolume = 0.0;         ///< -a value; 0 = no volume bound
  bool PreserveBoundary = false;  ///< -Y: no Steiner points on the boundary
  /// Work bound: the tetrahedra TetGen may create in all (flips create and destroy
  /// them, so a boundary recovery that flips without end reaches it). 0 (default):
  /// max(2e6, 400 x the expected count), the expected count being the enclosed volume
  /// over MaxVolume (or the number of triangles when MaxVolume is 0).
  double MaxCreatedTetrahedra = 0.0;
};

struct HOEMBEDFILTERSMESHING_EXPORT TetGenResult
{
  std::vector<double> Points;          ///< 3 per point
  std::vector<std::int64_t> Tets;      ///< 4 per tet, positively oriented (VTK order)
  std::string Error;                   ///< empty on success
  std::string Switches;                ///< the TetGen command-line switches used
  std::uint64_t CreatedTetrahedra = 0; ///< TetGen's work: tetrahedra created (0 if unknown)
  bool Stopped = false;                ///< the work bound or an abort stopped TetGen
  bool Aborted = false;                ///< it was the abort
};

/**
 * While alive, RunTetGen calls in this thread poll `abort` (every 4096 tetrahedra TetGen
 * creates) and stop with an error when it returns true: how vtkTet10Mesher lets
 * AbortExecute stop a long TetGen run. The envelope (hoembed::WrapSurface) and the
 * driver's other long steps poll the same callback (hoembed::MeshingAbortRequested).
 * Scopes nest (the innermost wins).
 */
class HOEMBEDFILTERSMESHING_EXPORT ScopedTetGenAbort
{
public:
  explicit ScopedTetGenAbort(std::function<bool()> abort);
  ~ScopedTetGenAbort();
  ScopedTetGenAbort(const ScopedTetGenAbort&) = delete;
  ScopedTetGenAbort& operator=(const ScopedTetGenAbort&) = delete;

private:
  std::function<bool()> Abort;
  const std::function<bool()>* Previous;
};

/// The innermost ScopedTetGenAbort's callback of this thread, polled now; false when none.
HOEMBEDFILTERSMESHING_EXPORT bool MeshingAbortRequested();

/// True when TetGen was compiled with HOEmbed's checkpoint patch (the work bound and
/// abort work); false with an unpatched system TetGen.
HOEMBEDFILTERSMESHING_EXPORT bool TetGenWorkIsBounded();

/**
 * Mesh the inside of the closed surface (`pts`: 3 doubles per point; `tris`: 3 ids per
 * triangle). Never throws: TetGen's failures (self-intersecting input, tiny features,
 * internal errors, the work bound, an abort) come back in TetGenResult::Error.
 */
HOEMBEDFILTERSMESHING_EXPORT TetGenResult RunTetGen(const std::vector<double>& pts,
  const std::vector<std::int64_t>& tris, const TetGenParameters& params);
} // namespace hoembed

#endif
