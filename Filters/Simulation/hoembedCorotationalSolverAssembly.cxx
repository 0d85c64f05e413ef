// hoembed::CorotationalSolver: the step matrix assembled in 3x3 node blocks (rotated
// stiffness S = sum_e R_e K_e R_e^T, rebuilt every step), its products with vectors, and
// the scalar CSR copy of cM M + cK S for the factorisation. See hoembedCorotationalSolver.h.
#include "hoembedCorotationalSolver.h"
#include "hoembedCorotationalSolverImpl.h"

#include <algorithm>
#include <vector>

namespace hoembed
{
// Block pattern = the node adjacency (the pattern of MN); per element the block index of
// each node pair; the cells split in two halves for two threads; per value of the scalar matrix A
// its block value.
void CorotationalSolver::Impl::BuildBlocks()
{
  const int* outer = MN.outerIndexPtr();
  const int* inner = MN.innerIndexPtr();
  const long long nb = MN.nonZeros();
  S.assign(9 * nb, 0.0);
  BlockOf.assign(NC * N * N, 0);
  auto block = [&](int row, int col) {
    const int* b = inner + outer[row];
    const int* e = inner + outer[row + 1];
    return static_cast<int>(std::lower_bound(b, e, col) - inner);
  };
  for (long long e = 0; e < NC; ++e)
  {
    for (int a = 0; a < N; ++a)
    {
      for (int b = 0; b < N; ++b)
      {
        BlockOf[(e * N + a) * N + b] = block(Conn[e * N + a], Conn[e * N + b]);
      }
    }
  }
  // two halves of the cells for two threads, cut by a plane across the longest extent
  // of the mesh (at the median cell centroid): a cell goes to its half's group when none
  // of its nodes is also a node of the other half, else to the shared cells (a layer
  // along the cut, added afterwards on one thread)
  std::vector<double> key(NC, 0.0);
  {
    double lo[3] = { 1e300, 1e300, 1e300 }, hi[3] = { -1e300, -1e300, -1e300 };
    for (long long p = 0; p < NP; ++p)
    {
      for (int i = 0; i < 3; ++i)
      {
        lo[i] = std::min(lo[i], X[3 * p + i]);
        hi[i] = std::max(hi[i], X[3 * p + i]);
      }
    }
    int axis = 0;
    for (int i = 1; i < 3; ++i)
    {
      axis = (hi[i] - lo[i] > hi[axis] - lo[axis]) ? i : axis;
    }
    for (long long e = 0; e < NC; ++e)
    {
      for (int a = 0; a < N; ++a)
      {
        key[e] += X[3 * Conn[e * N + a] + axis];
      }
    }
  }
  std::vector<double> sorted(key);
  std::nth_element(sorted.begin(), sorted.begin() + NC / 2, sorted.end());
  const double cut = NC > 0 ? sorted[NC / 2] : 0.0;
  std::vector<unsigned char> side(NC, 0), half(NP, 0);
  for (long long e = 0; e < NC; ++e)
  {
    side[e] = key[e] < cut ? 0 : 1;
    for (int a = 0; a < N; ++a)
    {
      half[Conn[e * N + a]] |= side[e] + 1;
    }
  }
  for (auto& g : HalfCells)
  {
    g.clear();
  }
  SharedCells.clear();
  for (long long e = 0; e < NC; ++e)
  {
    bool shared = false;
    for (int a = 0; a < N; ++a)
    {
      shared = shared || half[Conn[e * N + a]] == 3;
    }
    (shared ? SharedCells : HalfCells[side[e]]).push_back(static_cast<int>(e));
  }
  FInt.assign(3 * NP, 0.0);
  EW.assign(Assembled() ? 0 : NC * D, 0.0);
  const int* aOuter = A.outerIndexPtr();
  const int* aInner = A.innerIndexPtr();
  AFromS.assign(A.nonZeros(), 0);
  for (long long r = 0; r < 3 * NP; ++r)
  {
    for (int k = aOuter[r]; k < aOuter[r + 1]; ++k)
    {
      const int c = aInner[k];
      const int I = static_cast<int>(r / 3), J = c / 3;
      if (outer[I] == outer[I + 1])
      {
        AFromS[k] = -1; // isolated point: no block
        continue;
      }
      AFromS[k] = 9 * block(I, J) + 3 * static_cast<int>(r % 3) + c % 3;
    }
  }
}

// S = sum_e R_e K_e R_e^T and FInt = -sum_e R_e K_e (R_e^T y_e - X_e), y = x + vScale v
// (every step, after the rotations). Per element: the forces, then the upper node blocks
// R K_ab R^T (b >= a; R times the row block of K first, vectorised) added into S, with
// their transposes below. On two threads or more the two halves of the cells without
// common nodes run in parallel, then the shared cells; on one thread all cells in order
// (the sums then differ from the threaded ones in the last bits).
void CorotationalSolver::Impl::AssembleS(double vScale)
{
  std::fill(S.begin(), S.end(), 0.0);
  std::fill(FInt.begin(), FInt.end(), 0.0);
  const bool threaded =
    NC >= ParallelCells && 2 * SharedCells.size() < std::size_t(NC) && ParallelThreadCount() >= 2;
  auto cells = [&](const int* list, vtkIdType begin, vtkIdType end) {
    double u[30], w[30], T[3][30];
    for (vtkIdType c = begin; c < end; ++c)
    {
      const long long e = list ? list[c] : c;
      const double* R = &Rot[e * 9];
      const double r00 = R[0], r01 = R[1], r02 = R[2], r10 = R[3], r11 = R[4], r12 = R[5],
                   r20 = R[6], r21 = R[7], r22 = R[8];
      const double* K = &Ke[e * D * D];
      if (c + 1 < end)
      {
        // the next element's blocks lie at random places of S: fetch them early
        const int* nb = &BlockOf[(list ? list[c + 1] : c + 1) * N * N];
        for (int k = 0; k < N * N; ++k)
        {
          const double* q = &S[9 * static_cast<long long>(nb[k])];
          __builtin_prefetch(q, 1);
          __builtin_prefetch(q + 8, 1);
        }
      }
      // forces -R K (R^T y - X)
      for (int a = 0; a < N; ++a)
      {
        const long long pa = Conn[e * N + a];
        const double y0 = x[3 * pa] + vScale * v[3 * pa];
        const double y1 = x[3 * pa + 1] + vScale * v[3 * pa + 1];
        const double y2 = x[3 * pa + 2] + vScale * v[3 * pa + 2];
        u[3 * a] = r00 * y0 + r10 * y1 + r20 * y2 - X[3 * pa];
        u[3 * a + 1] = r01 * y0 + r11 * y1 + r21 * y2 - X[3 * pa + 1];
        u[3 * a + 2] = r02 * y0 + r12 * y1 + r22 * y2 - X[3 * pa + 2];
      }
      SymmetricTimes(D, K, u, w);
      for (int a = 0; a < N; ++a)
      {
        double* fa = &FInt[3 * Conn[e * N + a]];
        const double w0 = w[3 * a], w1 = w[3 * a + 1], w2 = w[3 * a + 2];
        fa[0] -= r00 * w0 + r01 * w1 + r02 * w2;
        fa[1] -= r10 * w0 + r11 * w1 + r12 * w2;
        fa[2] -= r20 * w0 + r21 * w1 + r22 * w2;
      }
      // blocks R K_ab R^T, b >= a: T = R K(3a:3a+3, 3a:), then T(:, 3b:3b+3) R^T
      const int* blk = &BlockOf[e * N * N];
      for (int a = 0; a < N; ++a)
      {
        const double* K0 = K + 3 * a * D;
        const double* K1 = K0 + D;
        const double* K2 = K1 + D;
        for (int k = 3 * a; k < D; ++k)
        {
          T[0][k] = r00 * K0[k] + r01 * K1[k] + r02 * K2[k];
          T[1][k] = r10 * K0[k] + r11 * K1[k] + r12 * K2[k];
          T[2][k] = r20 * K0[k] + r21 * K1[k] + r22 * K2[k];
        }
        for (int b = a; b < N; ++b)
        {
          double B[9];
          for (int i = 0; i < 3; ++i)
          {
            const double s0 = T[i][3 * b], s1 = T[i][3 * b + 1], s2 = T[i][3 * b + 2];
            B[3 * i] = s0 * r00 + s1 * r01 + s2 * r02;
            B[3 * i + 1] = s0 * r10 + s1 * r11 + s2 * r12;
            B[3 * i + 2] = s0 * r20 + s1 * r21 + s2 * r22;
          }
          double* sab = &S[9 * static_cast<long long>(blk[a * N + b])];
          for (int k = 0; k < 9; ++k)
          {
            sab[k] += B[k];
          }
          if (b != a)
          {
            double* sba = &S[9 * static_cast<long long>(blk[b * N + a])];
            for (int i = 0; i < 3; ++i)
            {
              for (int j = 0; j < 3; ++j)
              {
                sba[3 * j + i] += B[3 * i + j];
              }
            }
          }
        }
      }
    }
  };
  if (!threaded)
  {
    cells(nullptr, 0, NC);
    return;
  }
  ParallelLoop<vtkIdType>(0, 2, 1, [&](vtkIdType g0, vtkIdType g1) {
    for (vtkIdType g = g0; g < g1; ++g)
    {
      cells(HalfCells[g].data(), 0, static_cast<vtkIdType>(HalfCells[g].size()));
    }
  });
  cells(SharedCells.data(), 0, static_cast<vtkIdType>(SharedCells.size()));
}

void CorotationalSolver::Impl::MassApply(const double* p, double s, double* y) const
{
  const int* outer = MN.outerIndexPtr();
  const int* inner = MN.innerIndexPtr();
  const double* val = MN.valuePtr();
  for (long long r = 0; r < NP; ++r)
  {
    double a0 = 0.0, a1 = 0.0, a2 = 0.0;
    for (int k = outer[r]; k < outer[r + 1]; ++k)
    {
      const double m = val[k];
      const double* q = p + 3 * inner[k];
      a0 += m * q[0];
      a1 += m * q[1];
      a2 += m * q[2];
    }
    y[3 * r] += s * a0;
    y[3 * r + 1] += s * a1;
    y[3 * r + 2] += s * a2;
  }
}

// y = CM M p + CK S p, block row by block row (threaded for large meshes)
void CorotationalSolver::Impl::MatVec(const Eigen::VectorXd& p, Eigen::VectorXd& y)
{
  if (!Assembled())
  {
    MatVecElements(p, y);
    return;
  }
  MassBlockProduct(S.data(), CM, CK, nullptr, p, y);
}

void CorotationalSolver::Impl::MassBlockProduct(const double* blocks, double cM, double cK,
  const char* free, const Eigen::VectorXd& p, Eigen::VectorXd& y) const
{
  const int* outer = MN.outerIndexPtr();
  const int* inner = MN.innerIndexPtr();
  const double* mval = MN.valuePtr();
  const double* q = p.data();
  double* out = y.data();
  ParallelFor(NP, ParallelNodes, [&](vtkIdType begin, vtkIdType end) {
    for (vtkIdType r = begin; r < end; ++r)
    {
      double m0 = 0.0, m1 = 0.0, m2 = 0.0, s0 = 0.0, s1 = 0.0, s2 = 0.0;
      for (int k = outer[r]; k < outer[r + 1]; ++k)
      {
        const double* pj = q + 3 * inner[k];
        const double* b = blocks + 9 * static_cast<long long>(k);
        const double m = mval[k];
        m0 += m * pj[0];
        m1 += m * pj[1];
        m2 += m * pj[2];
        s0 += b[0] * pj[0] + b[1] * pj[1] + b[2] * pj[2];
        s1 += b[3] * pj[0] + b[4] * pj[1] + b[5] * pj[2];
        s2 += b[6] * pj[0] + b[7] * pj[1] + b[8] * pj[2];
      }
      const double row[3] = { cM * m0 + cK * s0, cM * m1 + cK * s1, cM * m2 + cK * s2 };
      for (int c = 0; c < 3; ++c)
      {
        out[3 * r + c] = !free || free[3 * r + c] ? row[c] : 0.0;
      }
    }
  });
}

// A = cM M + cK S on the scalar pattern (for a factorisation of the current system)
void CorotationalSolver::Impl::AssembleA(double cM, double cK)
{
  if (!Assembled())
  {
    AssembleS(VScale); // S is not kept up to date on small meshes
  }
  double* val = A.valuePtr();
  const long long nnz = A.nonZeros();
  for (long long k = 0; k < nnz; ++k)
  {
    const int s = AFromS[k];
    val[k] = cM * MassValues[k] + (s < 0 ? 0.0 : cK * S[s]);
  }
}
template <typename Local>
void CorotationalSolver::Impl::ElementProducts(Local&& local)
{
  ParallelFor(NC, ParallelCells, [&](vtkIdType begin, vtkIdType end) {
    double l[30], w[30];
    for (vtkIdType e = begin; e < end; ++e)
    {
      const double* R = &Rot[e * 9];
      local(e, R, l);
      SymmetricTimes(D, &Ke[e * D * D], l, w);
      double* out = &EW[e * D];
      for (int a = 0; a < N; ++a)
      {
        for (int i = 0; i < 3; ++i)
        {
          out[3 * a + i] =
            R[3 * i] * w[3 * a] + R[3 * i + 1] * w[3 * a + 1] + R[3 * i + 2] * w[3 * a + 2];
        }
      }
    }
  });
}

void CorotationalSolver::Impl::ScatterElements(double scale, double* out) const
{
  for (long long e = 0; e < NC; ++e)
  {
    const double* f = &EW[e * D];
    for (int a = 0; a < N; ++a)
    {
      double* oa = out + 3 * Conn[e * N + a];
      oa[0] += scale * f[3 * a];
      oa[1] += scale * f[3 * a + 1];
      oa[2] += scale * f[3 * a + 2];
    }
  }
}

// Small meshes: FInt element by element (element results, then a serial scatter).
void CorotationalSolver::Impl::ElementForces(double vScale)
{
  ElementProducts([&](vtkIdType e, const double* R, double* ue) {
    for (int a = 0; a < N; ++a)
    {
      const long long pa = Conn[e * N + a];
      const double y0 = x[3 * pa] + vScale * v[3 * pa];
      const double y1 = x[3 * pa + 1] + vScale * v[3 * pa + 1];
      const double y2 = x[3 * pa + 2] + vScale * v[3 * pa + 2];
      for (int i = 0; i < 3; ++i) // R^T y - X
      {
        ue[3 * a + i] = R[i] * y0 + R[3 + i] * y1 + R[6 + i] * y2 - X[3 * pa + i];
      }
    }
  });
  std::fill(FInt.begin(), FInt.end(), 0.0);
  ScatterElements(-1.0, FInt.data());
}

// Small meshes: y = CM M p + CK sum_e R_e K_e R_e^T p_e, element by element.
void CorotationalSolver::Impl::MatVecElements(const Eigen::VectorXd& p, Eigen::VectorXd& y)
{
  ElementProducts([&](vtkIdType e, const double* R, double* l) {
    for (int a = 0; a < N; ++a)
    {
      const double* q = p.data() + 3 * Conn[e * N + a];
      for (int i = 0; i < 3; ++i)
      {
        l[3 * a + i] = R[i] * q[0] + R[3 + i] * q[1] + R[6 + i] * q[2]; // R^T q
      }
    }
  });
  y.setZero();
  MassApply(p.data(), CM, y.data());
  ScatterElements(CK, y.data());
}
} // namespace hoembed
