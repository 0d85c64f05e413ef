#include "hoembedBoundaryNormals.h"
#include "hoembedVector3.h"
#include "hoembedShapeFunctions.h"

#include <cmath>
#include <vector>

namespace hoembed
{
namespace
{
using Id = TetMeshTopology::Id;

double Norm(const double a[3])
{
  return std::sqrt(Dot(a, a));
}

// Face-local (u, v) of the six tri6 nodes.
const double FaceNodeUV[6][2] = { { 0, 0 }, { 1, 0 }, { 0, 1 }, { 0.5, 0 }, { 0.5, 0.5 },
  { 0, 0.5 } };

} // namespace

void EvaluateBoundaryFace(const TetMeshTopology& topo, const double* points, Id face,
  const double uv[2], double x[3], double xu[3], double xv[3])
{
  const int npf = topo.GetNodesPerFace();
  const Id* fn = &topo.BoundaryFaceNodes[face * npf];
  double N[6], dN[12];
  if (npf == 6)
  {
    Tri6Shape(uv, N);
    Tri6Derivs(uv, dN);
  }
  else
  {
    Tri3Shape(uv, N);
    Tri3Derivs(uv, dN);
  }
  for (int d = 0; d < 3; ++d)
  {
    x[d] = xu[d] = xv[d] = 0.0;
  }
  for (int a = 0; a < npf; ++a)
  {
    const double* p = points + 3 * fn[a];
    for (int d = 0; d < 3; ++d)
    {
      x[d] += N[a] * p[d];
      xu[d] += dN[a] * p[d];
      xv[d] += dN[npf + a] * p[d];
    }
  }
}

void ComputeBoundaryNodeNormals(const TetMeshTopology& topo, const double* points, double* normals)
{
  const Id np = topo.NumberOfPoints;
  for (Id i = 0; i < 3 * np; ++i)
  {
    normals[i] = 0.0;
  }
  const int npf = topo.GetNodesPerFace();
  const Id nbf = topo.GetNumberOfBoundaryFaces();
  std::vector<double> weight(np, 0.0);
  // shape-function derivatives at the face's own nodes, the same for every face:
  // D[k][0 / 1][a] = dN_a / du, dN_a / dv at node k (as EvaluateBoundaryFace has them)
  struct NodeDerivatives
  {
    double D[2][6][2][6];
    NodeDerivatives()
    {
      for (int k = 0; k < 6; ++k)
      {
        double d6[12], d3[6];
        Tri6Derivs(FaceNodeUV[k], d6);
        Tri3Derivs(FaceNodeUV[k], d3);
        for (int a = 0; a < 6; ++a)
        {
          this->D[1][k][0][a] = d6[a];
          this->D[1][k][1][a] = d6[6 + a];
          this->D[0][k][0][a] = a < 3 ? d3[a] : 0.0;
          this->D[0][k][1][a] = a < 3 ? d3[3 + a] : 0.0;
        }
      }
    }
  };
  static const NodeDerivatives Table;
  const auto& D = Table.D[npf == 6 ? 1 : 0];
  for (Id b = 0; b < nbf; ++b)
  {
    const Id* fn = &topo.BoundaryFaceNodes[b * npf];
    const double* p[6];
    for (int c = 0; c < npf; ++c)
      p[c] = points + 3 * fn[c];
    for (int a = 0; a < npf; ++a)
    {
      double xu[3] = { 0, 0, 0 }, xv[3] = { 0, 0, 0 }, n[3];
      for (int c = 0; c < npf; ++c)
        for (int d = 0; d < 3; ++d)
        {
          xu[d] += D[a][0][c] * p[c][d];
          xv[d] += D[a][1][c] * p[c][d];
        }
      Cross(xu, xv, n);
      const double len = Norm(n);
      if (!(len > 0.0))
      {
        continue;
      }
      double angle = M_PI; // the patch is smooth at its mid-edge nodes
      if (a < 3)
      {
        double t1[3], t2[3];
        for (int d = 0; d < 3; ++d)
        {
          if (a == 0)
          {
            t1[d] = xu[d];
            t2[d] = xv[d];
          }
          else if (a == 1)
          {
            t1[d] = -xu[d];
            t2[d] = xv[d] - xu[d];
          }
          else
          {
            t1[d] = -xv[d];
            t2[d] = xu[d] - xv[d];
          }
        }
        double c[3];
        Cross(t1, t2, c);
        angle = std::atan2(Norm(c), Dot(t1, t2));
      }
      double* out = normals + 3 * fn[a];
      weight[fn[a]] += std::fabs(angle);
      for (int d = 0; d < 3; ++d)
      {
        out[d] += angle * n[d] / len;
      }
    }
  }
  for (Id i = 0; i < np; ++i)
  {
    double* n = normals + 3 * i;
    const double len = Norm(n);
    if (len <= 1e-8 * weight[i])
    {
      // The faces around the node cancel (the boundary folds back on itself here): the
      // direction would be round-off, different in every frame. No normal at this node.
      n[0] = n[1] = n[2] = 0.0;
      continue;
    }
    if (len > 0.0)
    {
      n[0] /= len;
      n[1] /= len;
      n[2] /= len;
    }
  }
}

double InterpolateBoundaryNormal(const TetMeshTopology& topo, const double* nodalNormals, Id face,
  const double uv[2], double n[3], double unnormalized[3])
{
  const int npf = topo.GetNodesPerFace();
  const Id* fn = &topo.BoundaryFaceNodes[face * npf];
  double N[6];
  if (npf == 6)
  {
    Tri6Shape(uv, N);
  }
  else
  {
    Tri3Shape(uv, N);
  }
  double s[3] = { 0, 0, 0 };
  for (int a = 0; a < npf; ++a)
  {
    const double* m = nodalNormals + 3 * fn[a];
    s[0] += N[a] * m[0];
    s[1] += N[a] * m[1];
    s[2] += N[a] * m[2];
  }
  if (unnormalized)
  {
    unnormalized[0] = s[0];
    unnormalized[1] = s[1];
    unnormalized[2] = s[2];
  }
  const double len = Norm(s);
  for (int d = 0; d < 3; ++d)
  {
    n[d] = len > 0.0 ? s[d] / len : 0.0;
  }
  return len;
}
} // namespace hoembed
