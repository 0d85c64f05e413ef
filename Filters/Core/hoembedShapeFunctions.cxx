#include "hoembedShapeFunctions.h"

namespace hoembed
{
const double Tet10NodeParametric[10][3] = { { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 },
  { 0.5, 0, 0 }, { 0.5, 0.5, 0 }, { 0, 0.5, 0 }, { 0, 0, 0.5 }, { 0.5, 0, 0.5 }, { 0, 0.5, 0.5 } };

void Tet4Shape(const double pc[3], double N[4])
{
  N[0] = 1.0 - pc[0] - pc[1] - pc[2];
  N[1] = pc[0];
  N[2] = pc[1];
  N[3] = pc[2];
}

void Tet4Derivs(const double*, double dN[12])
{
  static const double d[12] = { -1, 1, 0, 0, -1, 0, 1, 0, -1, 0, 0, 1 };
  for (int i = 0; i < 12; ++i)
  {
    dN[i] = d[i];
  }
}

void Tet10Shape(const double pc[3], double N[10])
{
  const double L1 = pc[0], L2 = pc[1], L3 = pc[2];
  const double L0 = 1.0 - L1 - L2 - L3;
  N[0] = L0 * (2.0 * L0 - 1.0);
  N[1] = L1 * (2.0 * L1 - 1.0);
  N[2] = L2 * (2.0 * L2 - 1.0);
  N[3] = L3 * (2.0 * L3 - 1.0);
  N[4] = 4.0 * L0 * L1;
  N[5] = 4.0 * L1 * L2;
  N[6] = 4.0 * L2 * L0;
  N[7] = 4.0 * L0 * L3;
  N[8] = 4.0 * L1 * L3;
  N[9] = 4.0 * L2 * L3;
}

void Tet10Derivs(const double pc[3], double dN[30])
{
  const double L1 = pc[0], L2 = pc[1], L3 = pc[2];
  const double L0 = 1.0 - L1 - L2 - L3;
  const double a0 = 1.0 - 4.0 * L0; // d/dx of L0(2L0-1) = (4L0-1) * dL0/dx, dL0/dx = -1
  // d/dr
  dN[0] = a0;
  dN[1] = 4.0 * L1 - 1.0;
  dN[2] = 0.0;
  dN[3] = 0.0;
  dN[4] = 4.0 * (L0 - L1);
  dN[5] = 4.0 * L2;
  dN[6] = -4.0 * L2;
  dN[7] = -4.0 * L3;
  dN[8] = 4.0 * L3;
  dN[9] = 0.0;
  // d/ds
  dN[10] = a0;
  dN[11] = 0.0;
  dN[12] = 4.0 * L2 - 1.0;
  dN[13] = 0.0;
  dN[14] = -4.0 * L1;
  dN[15] = 4.0 * L1;
  dN[16] = 4.0 * (L0 - L2);
  dN[17] = -4.0 * L3;
  dN[18] = 0.0;
  dN[19] = 4.0 * L3;
  // d/dt
  dN[20] = a0;
  dN[21] = 0.0;
  dN[22] = 0.0;
  dN[23] = 4.0 * L3 - 1.0;
  dN[24] = -4.0 * L1;
  dN[25] = 0.0;
  dN[26] = -4.0 * L2;
  dN[27] = 4.0 * (L0 - L3);
  dN[28] = 4.0 * L1;
  dN[29] = 4.0 * L2;
}

void Tri3Shape(const double pc[2], double N[3])
{
  N[0] = 1.0 - pc[0] - pc[1];
  N[1] = pc[0];
  N[2] = pc[1];
}

void Tri3Derivs(const double*, double dN[6])
{
  static const double d[6] = { -1, 1, 0, -1, 0, 1 };
  for (int i = 0; i < 6; ++i)
  {
    dN[i] = d[i];
  }
}

void Tri6Shape(const double pc[2], double N[6])
{
  const double L1 = pc[0], L2 = pc[1];
  const double L0 = 1.0 - L1 - L2;
  N[0] = L0 * (2.0 * L0 - 1.0);
  N[1] = L1 * (2.0 * L1 - 1.0);
  N[2] = L2 * (2.0 * L2 - 1.0);
  N[3] = 4.0 * L0 * L1;
  N[4] = 4.0 * L1 * L2;
  N[5] = 4.0 * L2 * L0;
}

void Tri6Derivs(const double pc[2], double dN[12])
{
  const double L1 = pc[0], L2 = pc[1];
  const double L0 = 1.0 - L1 - L2;
  const double a0 = 1.0 - 4.0 * L0;
  dN[0] = a0;
  dN[1] = 4.0 * L1 - 1.0;
  dN[2] = 0.0;
  dN[3] = 4.0 * (L0 - L1);
  dN[4] = 4.0 * L2;
  dN[5] = -4.0 * L2;
  dN[6] = a0;
  dN[7] = 0.0;
  dN[8] = 4.0 * L2 - 1.0;
  dN[9] = -4.0 * L1;
  dN[10] = 4.0 * L1;
  dN[11] = 4.0 * (L0 - L2);
}

void TetFaceToTetParametric(int face, const double uv[2], double pc[3])
{
  const double w[3] = { 1.0 - uv[0] - uv[1], uv[0], uv[1] };
  pc[0] = pc[1] = pc[2] = 0.0;
  for (int k = 0; k < 3; ++k)
  {
    const double* c = Tet10NodeParametric[TetFaceNodes[face][k]];
    pc[0] += w[k] * c[0];
    pc[1] += w[k] * c[1];
    pc[2] += w[k] * c[2];
  }
}
} // namespace hoembed
