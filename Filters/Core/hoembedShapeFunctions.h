/**
 * @file hoembedShapeFunctions.h
 * @brief Shape functions of tet4, tet10, tri3 and tri6 elements in VTK's node order.
 *
 * Plain C++ kernels (no VTK pipeline code). Parametric coordinates are VTK's: a tet
 * point is (r, s, t) with corners 0:(0,0,0), 1:(1,0,0), 2:(0,1,0), 3:(0,0,1); a
 * triangle point is (r, s) with corners 0:(0,0), 1:(1,0), 2:(0,1).
 *
 * Node order (as vtkTetra, vtkQuadraticTetra, vtkTriangle, vtkQuadraticTriangle):
 * - tet10: corners 0-3, then mid-edge nodes on edges 01, 12, 20, 03, 13, 23.
 * - tri6: corners 0-2, then mid-edge nodes on edges 01, 12, 20.
 *
 * Derivative arrays use VTK's layout: all d/dr first, then all d/ds, then all d/dt,
 * e.g. for tet10 `dN[0..9]` = dN/dr, `dN[10..19]` = dN/ds, `dN[20..29]` = dN/dt.
 *
 * @sa vtkQuadraticTetra::InterpolationFunctions, vtkQuadraticTriangle::InterpolationDerivs
 */
#ifndef hoembedShapeFunctions_h
#define hoembedShapeFunctions_h

#include "hoembedCoreModule.h"

namespace hoembed
{
/// Corner pairs of the six tet10 edges, in mid-node order (node 4 + e sits on edge e).
constexpr int TetEdgeCorners[6][2] = { { 0, 1 }, { 1, 2 }, { 2, 0 }, { 0, 3 }, { 1, 3 }, { 2, 3 } };

/// The four faces of a tet as tri6 node lists (corners a, b, c, then mids ab, bc, ca),
/// VTK's face order. With a positively oriented tet, each face's normal
/// (xb - xa) x (xc - xa) points out of the element. The first three entries are the
/// tri3 faces of a tet4.
constexpr int TetFaceNodes[4][6] = { { 0, 1, 3, 4, 8, 7 }, { 1, 2, 3, 5, 9, 8 },
  { 2, 0, 3, 6, 7, 9 }, { 0, 2, 1, 6, 5, 4 } };

/// The corner opposite each face (face f does not contain corner TetFaceOpposite[f]).
constexpr int TetFaceOpposite[4] = { 2, 0, 1, 3 };
/// The face opposite each corner (TetFaceOpposite inverted).
constexpr int TetCornerOppositeFace[4] = { 1, 2, 0, 3 };

/// Parametric coordinates (r, s, t) of the ten tet10 nodes.
HOEMBEDCORE_EXPORT extern const double Tet10NodeParametric[10][3];

HOEMBEDCORE_EXPORT void Tet4Shape(const double pc[3], double N[4]);
HOEMBEDCORE_EXPORT void Tet4Derivs(const double pc[3], double dN[12]);
HOEMBEDCORE_EXPORT void Tet10Shape(const double pc[3], double N[10]);
HOEMBEDCORE_EXPORT void Tet10Derivs(const double pc[3], double dN[30]);
HOEMBEDCORE_EXPORT void Tri3Shape(const double pc[2], double N[3]);
HOEMBEDCORE_EXPORT void Tri3Derivs(const double pc[2], double dN[6]);
HOEMBEDCORE_EXPORT void Tri6Shape(const double pc[2], double N[6]);
HOEMBEDCORE_EXPORT void Tri6Derivs(const double pc[2], double dN[12]);

/**
 * Map a point (u, v) of face `face` (tri parametric coordinates, in the face's node
 * order of TetFaceNodes) to the tet's parametric coordinates (r, s, t).
 */
HOEMBEDCORE_EXPORT void TetFaceToTetParametric(int face, const double uv[2], double pc[3]);

/**
 * Interpolate x = sum_i N_i x_i for `n` nodes with coordinates `x` (3 doubles per node).
 */
inline void Interpolate(int n, const double* N, const double* x, double out[3])
{
  out[0] = out[1] = out[2] = 0.0;
  for (int i = 0; i < n; ++i)
  {
    out[0] += N[i] * x[3 * i];
    out[1] += N[i] * x[3 * i + 1];
    out[2] += N[i] * x[3 * i + 2];
  }
}
} // namespace hoembed

#endif
