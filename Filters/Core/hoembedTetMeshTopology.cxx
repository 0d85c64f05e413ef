#include "hoembedTetMeshTopology.h"
#include "hoembedCsr.h"
#include "hoembedShapeFunctions.h"

#include <algorithm>
#include <sstream>

namespace hoembed
{
namespace
{
using Id = TetMeshTopology::Id;

// Items keyed by a sorted tuple of node ids (`make(i, item)` fills item i), bucketed by
// the smallest id (BuildCsr, items in their order within a bucket): matching is then
// linear in the number of items for bounded node valence.
template <typename T, typename Make>
void BucketByFirst(
  Id numberOfItems, Id numberOfPoints, Make make, std::vector<Id>& offsets, std::vector<T>& sorted)
{
  BuildCsr(
    numberOfPoints,
    [&](auto&& emit) {
      T it;
      for (Id i = 0; i < numberOfItems; ++i)
      {
        make(i, it);
        emit(it.Key[0], it);
      }
    },
    offsets, sorted);
}

// Sort a bucket by a total order (no ties: the item ids differ): insertion sort for the
// usual handful of items, std::sort for a large bucket (a node shared by many cells).
template <typename T, typename Less>
void SortBucket(T* first, T* last, Less less)
{
  if (last - first > 48)
  {
    std::sort(first, last, less);
    return;
  }
  for (T* i = first + 1; i < last; ++i)
  {
    const T v = *i;
    T* j = i;
    for (; j > first && less(v, j[-1]); --j)
      *j = j[-1];
    *j = v;
  }
}

// Whether local faces fa and fb (items 4 * cell + face) of two tet10 cells with the same
// corners also have the same mid-edge node on each edge. The corners of a face are
// distinct, so an edge is named by the corner opposite it.
bool SameFaceMids(const Id* conn, Id fa, Id fb)
{
  const Id* ca = conn + (fa / 4) * 10;
  const Id* cb = conn + (fb / 4) * 10;
  const int* na = TetFaceNodes[fa % 4];
  const int* nb = TetFaceNodes[fb % 4];
  // edge e of a face runs from corner e to corner e + 1 (mod 3): corner e + 2 is opposite
  const Id ob[3] = { cb[nb[2]], cb[nb[0]], cb[nb[1]] };
  for (int e = 0; e < 3; ++e)
  {
    const Id opposite = ca[na[(e + 2) % 3]];
    const int e2 = opposite == ob[0] ? 0 : (opposite == ob[1] ? 1 : 2);
    if (opposite != ob[e2] || ca[na[3 + e]] != cb[nb[3 + e2]])
      return false;
  }
  return true;
}
} // namespace

std::string TetMeshTopology::Build(
  const Id* conn, Id numberOfCells, int nodesPerCell, Id numberOfPoints)
{
  std::string err = this->BuildImpl(conn, numberOfCells, nodesPerCell, numberOfPoints);
  if (!err.empty())
  {
    // Leave an empty topology behind, not a half-built one.
    *this = TetMeshTopology();
  }
  return err;
}

// One function (~190 lines) in five marked sections (checks, face neighbours, boundary
// faces, boundary edges, faces around nodes): each fills the tables the next reads, and
// they share the face hash and scratch of the first passes; Build wraps it so that a
// failure leaves an empty topology, never a half-built one.
std::string TetMeshTopology::BuildImpl(
  const Id* conn, Id numberOfCells, int nodesPerCell, Id numberOfPoints)
{
  if (nodesPerCell != 4 && nodesPerCell != 10)
  {
    return "cells must have 4 (tet4) or 10 (tet10) nodes";
  }
  if (numberOfCells < 0 || numberOfPoints < 0)
  {
    return "negative number of cells or points";
  }
  if (numberOfCells > 0 && !conn)
  {
    return "no connectivity given";
  }
  this->NodesPerCell = nodesPerCell;
  this->NumberOfCells = numberOfCells;
  this->NumberOfPoints = numberOfPoints;
  const int npf = this->GetNodesPerFace();

  // node ids in range, no node twice in a cell (a per-node stamp: the last cell seen)
  std::vector<Id>& lastCell = this->NodeStamp;
  lastCell.assign(numberOfPoints, -1);
  for (Id c = 0; c < numberOfCells; ++c)
  {
    const Id* cell = conn + c * nodesPerCell;
    for (int i = 0; i < nodesPerCell; ++i)
    {
      if (cell[i] < 0 || cell[i] >= numberOfPoints)
      {
        std::ostringstream os;
        os << "cell " << c << " refers to point " << cell[i] << ", outside [0, " << numberOfPoints
           << ")";
        return os.str();
      }
      if (lastCell[cell[i]] == c)
      {
        std::ostringstream os;
        os << "cell " << c << " repeats point " << cell[i];
        return os.str();
      }
      lastCell[cell[i]] = c;
    }
  }

  // Face neighbours.
  std::vector<Id>& offsets = this->BucketOffsets;
  std::vector<Keyed<3>>& sorted = this->SortedFaces;
  BucketByFirst(
    4 * numberOfCells, numberOfPoints,
    [conn, nodesPerCell](Id item, Keyed<3>& k) {
      const Id* cell = conn + (item / 4) * nodesPerCell;
      const int* fn = TetFaceNodes[item % 4];
      Id a = cell[fn[0]], b = cell[fn[1]], d = cell[fn[2]];
      if (b < a)
        std::swap(a, b);
      if (d < b)
      {
        std::swap(b, d);
        if (b < a)
          std::swap(a, b);
      }
      k.Key[0] = a;
      k.Key[1] = b;
      k.Key[2] = d;
      k.Item = item;
    },
    offsets, sorted);
  this->FaceNeighbor.assign(4 * numberOfCells, -1);
  for (Id p = 0; p < numberOfPoints; ++p)
  {
    // Sort the bucket (faces whose smallest node is p) by the other two nodes, then walk
    // the runs of equal faces: O(k log k) for k faces in the bucket, not O(k^2) (a node
    // shared by many cells makes a large bucket).
    Keyed<3>* first = sorted.data() + offsets[p];
    Keyed<3>* last = sorted.data() + offsets[p + 1];
    SortBucket(first, last, [](const Keyed<3>& a, const Keyed<3>& b) {
      return a.Key[1] != b.Key[1] ? a.Key[1] < b.Key[1]
                                  : (a.Key[2] != b.Key[2] ? a.Key[2] < b.Key[2] : a.Item < b.Item);
    });
    for (Keyed<3>* run = first; run != last;)
    {
      Keyed<3>* end = run + 1;
      while (end != last && end->Key[1] == run->Key[1] && end->Key[2] == run->Key[2])
        ++end;
      if (end - run > 2)
      {
        std::ostringstream os;
        os << "face (" << run->Key[0] << ", " << run->Key[1] << ", " << run->Key[2]
           << ") is shared by more than two cells";
        return os.str();
      }
      if (end - run == 2)
      {
        if (nodesPerCell == 10 && !SameFaceMids(conn, run[0].Item, run[1].Item))
        {
          // Conforming tet10 neighbours share the face's mid-edge nodes too.
          std::ostringstream os;
          os << "cells " << run[0].Item / 4 << " and " << run[1].Item / 4 << " share the face ("
             << run->Key[0] << ", " << run->Key[1] << ", " << run->Key[2]
             << ") but not its mid-edge nodes (non-conforming tet10 mesh)";
          return os.str();
        }
        this->FaceNeighbor[run[0].Item] = run[1].Item / 4;
        this->FaceNeighbor[run[1].Item] = run[0].Item / 4;
      }
      run = end;
    }
  }

  // Boundary faces.
  this->BoundaryFaceCell.clear();
  this->BoundaryFaceLocal.clear();
  this->BoundaryFaceNodes.clear();
  this->CellBoundaryFace.assign(4 * numberOfCells, -1);
  {
    const Id count =
      static_cast<Id>(std::count(this->FaceNeighbor.begin(), this->FaceNeighbor.end(), Id(-1)));
    this->BoundaryFaceCell.reserve(count);
    this->BoundaryFaceLocal.reserve(count);
    this->BoundaryFaceNodes.reserve(count * npf);
    this->BoundaryEdgeNodes.reserve(9 * count); // at most 3 edges per face, 3 ids each
  }
  for (Id c = 0; c < numberOfCells; ++c)
  {
    for (int f = 0; f < 4; ++f)
    {
      if (this->FaceNeighbor[4 * c + f] >= 0)
        continue;
      this->CellBoundaryFace[4 * c + f] = static_cast<Id>(this->BoundaryFaceCell.size());
      this->BoundaryFaceCell.push_back(c);
      this->BoundaryFaceLocal.push_back(f);
      for (int a = 0; a < npf; ++a)
        this->BoundaryFaceNodes.push_back(conn[c * nodesPerCell + TetFaceNodes[f][a]]);
    }
  }
  const Id nbf = this->GetNumberOfBoundaryFaces();

  // Boundary edges and the neighbours across them.
  std::vector<Keyed<2>>& sortedEdges = this->SortedEdges;
  BucketByFirst(
    3 * nbf, numberOfPoints,
    [this, npf](Id item, Keyed<2>& k) {
      const Id* fn = &this->BoundaryFaceNodes[(item / 3) * npf];
      const int e = static_cast<int>(item % 3);
      k.Key[0] = std::min(fn[e], fn[(e + 1) % 3]);
      k.Key[1] = std::max(fn[e], fn[(e + 1) % 3]);
      k.Item = item;
    },
    offsets, sortedEdges);
  this->BoundaryFaceNeighbor.assign(3 * nbf, -1);
  this->BoundaryEdgeNodes.clear();
  this->NumberOfNonManifoldBoundaryEdges = 0;
  for (Id p = 0; p < numberOfPoints; ++p)
  {
    Keyed<2>* first = sortedEdges.data() + offsets[p];
    Keyed<2>* last = sortedEdges.data() + offsets[p + 1];
    SortBucket(first, last, [](const Keyed<2>& a, const Keyed<2>& b) {
      return a.Key[1] != b.Key[1] ? a.Key[1] < b.Key[1] : a.Item < b.Item;
    });
    for (Keyed<2>* run = first; run != last;)
    {
      Keyed<2>* end = run + 1;
      while (end != last && end->Key[1] == run->Key[1])
        ++end;
      const Id count = static_cast<Id>(end - run); // boundary faces on this edge
      if (count == 2)
      {
        this->BoundaryFaceNeighbor[run[0].Item] = run[1].Item / 3;
        this->BoundaryFaceNeighbor[run[1].Item] = run[0].Item / 3;
      }
      else if (count > 2)
      {
        ++this->NumberOfNonManifoldBoundaryEdges;
      }
      const Id b = run->Item / 3;
      const int e = static_cast<int>(run->Item % 3);
      this->BoundaryEdgeNodes.push_back(run->Key[0]);
      this->BoundaryEdgeNodes.push_back(run->Key[1]);
      this->BoundaryEdgeNodes.push_back(npf == 6 ? this->BoundaryFaceNodes[b * npf + 3 + e] : -1);
      run = end;
    }
  }

  // Boundary faces around each node.
  BuildCsr(
    numberOfPoints,
    [&](auto&& emit) {
      for (Id b = 0; b < nbf; ++b)
        for (int a = 0; a < npf; ++a)
          emit(this->BoundaryFaceNodes[b * npf + a], b);
    },
    this->NodeFaceOffsets, this->NodeFaces);
  return std::string();
}
} // namespace hoembed
