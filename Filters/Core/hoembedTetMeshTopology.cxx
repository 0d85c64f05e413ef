#include "hoembedTetMeshTopology.h"
#include "hoembedShapeFunctions.h"

#include <algorithm>
#include <sstream>

namespace hoembed
{
namespace
{
using Id = TetMeshTopology::Id;

// Items keyed by a sorted tuple of node ids; bucketed by the smallest id (counting sort),
// so that matching is linear in the number of items for bounded node valence.
template <int K>
struct Keyed
{
  Id Key[K];
  Id Item;
};

template <int K>
void BucketByFirst(std::vector<Keyed<K>>& items, Id numberOfPoints, std::vector<Id>& offsets,
  std::vector<Keyed<K>>& sorted)
{
  offsets.assign(numberOfPoints + 1, 0);
  for (const auto& it : items)
    ++offsets[it.Key[0] + 1];
  for (Id i = 0; i < numberOfPoints; ++i)
    offsets[i + 1] += offsets[i];
  std::vector<Id> fill(offsets.begin(), offsets.end() - 1);
  sorted.resize(items.size());
  for (const auto& it : items)
    sorted[fill[it.Key[0]]++] = it;
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

  {
    // a point repeats in cell c when it was already stamped with c
    std::vector<Id> stamp(numberOfPoints, -1);
    for (Id c = 0; c < numberOfCells; ++c)
    {
      const Id* cell = conn + c * nodesPerCell;
      for (int i = 0; i < nodesPerCell; ++i)
      {
        if (cell[i] < 0 || cell[i] >= numberOfPoints)
        {
          std::ostringstream os;
          os << "cell " << c << " refers to point " << cell[i] << ", outside [0, "
             << numberOfPoints << ")";
          return os.str();
        }
        if (stamp[cell[i]] == c)
        {
          std::ostringstream os;
          os << "cell " << c << " repeats point " << cell[i];
          return os.str();
        }
        stamp[cell[i]] = c;
      }
    }
  }

  // Face neighbours.
  std::vector<Keyed<3>> faces(static_cast<size_t>(4 * numberOfCells));
  for (Id c = 0; c < numberOfCells; ++c)
  {
    const Id* cell = conn + c * nodesPerCell;
    for (int f = 0; f < 4; ++f)
    {
      Keyed<3>& k = faces[4 * c + f];
      Id a = cell[TetFaceNodes[f][0]], b = cell[TetFaceNodes[f][1]], d = cell[TetFaceNodes[f][2]];
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
      k.Item = 4 * c + f;
    }
  }
  std::vector<Id> offsets;
  std::vector<Keyed<3>> sorted;
  BucketByFirst(faces, numberOfPoints, offsets, sorted);
  faces.clear();
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
    const Id count = static_cast<Id>(
      std::count(this->FaceNeighbor.begin(), this->FaceNeighbor.end(), Id(-1)));
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
  std::vector<Keyed<2>> edges(static_cast<size_t>(3 * nbf));
  for (Id b = 0; b < nbf; ++b)
  {
    const Id* fn = &this->BoundaryFaceNodes[b * npf];
    for (int e = 0; e < 3; ++e)
    {
      Keyed<2>& k = edges[3 * b + e];
      k.Key[0] = std::min(fn[e], fn[(e + 1) % 3]);
      k.Key[1] = std::max(fn[e], fn[(e + 1) % 3]);
      k.Item = 3 * b + e;
    }
  }
  std::vector<Keyed<2>> sortedEdges;
  BucketByFirst(edges, numberOfPoints, offsets, sortedEdges);
  edges.clear();
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
  this->NodeFaceOffsets.assign(numberOfPoints + 1, 0);
  for (Id b = 0; b < nbf; ++b)
    for (int a = 0; a < npf; ++a)
      ++this->NodeFaceOffsets[this->BoundaryFaceNodes[b * npf + a] + 1];
  for (Id i = 0; i < numberOfPoints; ++i)
    this->NodeFaceOffsets[i + 1] += this->NodeFaceOffsets[i];
  this->NodeFaces.resize(this->NodeFaceOffsets[numberOfPoints]);
  std::vector<Id> fill(this->NodeFaceOffsets.begin(), this->NodeFaceOffsets.end() - 1);
  for (Id b = 0; b < nbf; ++b)
    for (int a = 0; a < npf; ++a)
      this->NodeFaces[fill[this->BoundaryFaceNodes[b * npf + a]]++] = b;
  return std::string();
}
} // namespace hoembed
