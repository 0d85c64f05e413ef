"""A straight box beam FE mesh carrying a fine surface with thorns, embedded analytically.

Helpers for the transfer benchmarks (not a benchmark itself). The paper's Fig. 2 / Fig. 5
setting: a coarse beam, a fine surface with sharp features smaller than an element.

The embedding is built without vtkEmbeddingCoordinatesFilter, exactly: the beam mesh is a
straight box, every fine vertex is v = p + d n with p on a box face and n that face's
normal; thorns (cones) stand only on boundary faces none of whose nodes is on a box edge,
where the smooth normal field of the mesh (angle-weighted nodal normals, paper eq. 6-7)
equals the flat face normal exactly. So the closest point is the orthogonal projection
and the stored (cell, parametric coordinates, local face, d) satisfy v = p + d n(p) to
round-off. Barycentric embeddings store the parametric coordinates of v itself in the
cell of p (extrapolated outside it: exact at rest since straight cells are affine).
"""

import itertools

import numpy as np
import pyvista as pv
import vtkmodules.vtkCommonCore as vcore

# VTK tet face order (hoembed::TetFaceNodes corners).
FACE_CORNERS = np.array([[0, 1, 3], [1, 2, 3], [2, 0, 3], [0, 2, 1]])
TET10_EDGES = [(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)]


def box_mesh(n, size, order):
    """Box [0,size] split into n cubes of 6 Kuhn tets (same layout as the tests' box)."""
    nx, ny, nz = n
    g = np.stack(
        np.meshgrid(*[np.linspace(0, s, k + 1) for s, k in zip(size, n)], indexing="ij"), axis=-1
    )
    pts = g.transpose(2, 1, 0, 3).reshape(-1, 3)
    kk, jj, ii = np.meshgrid(np.arange(nz), np.arange(ny), np.arange(nx), indexing="ij")
    base = np.stack([ii.ravel(), jj.ravel(), kk.ravel()], axis=1)  # cube order k, j, i
    tets = []
    for perm in itertools.permutations(range(3)):
        c = np.zeros_like(base)
        ids = [base]
        for a in perm:
            c = c.copy()
            c[:, a] = 1
            ids.append(base + c)
        tets.append(
            np.stack([(q[:, 2] * (ny + 1) + q[:, 1]) * (nx + 1) + q[:, 0] for q in ids], axis=1)
        )
    tets = np.stack(tets, axis=1).reshape(-1, 4)  # cube-major, then permutation
    e = pts[tets[:, 1:]] - pts[tets[:, :1]]
    neg = np.linalg.det(e) < 0
    tets[neg, 1], tets[neg, 2] = tets[neg, 2].copy(), tets[neg, 1].copy()
    if order == 2:
        pairs = np.stack([np.sort(tets[:, [a, b]], axis=1) for a, b in TET10_EDGES], axis=1)
        uniq, inv = np.unique(pairs.reshape(-1, 2), axis=0, return_inverse=True)
        mids = 0.5 * (pts[uniq[:, 0]] + pts[uniq[:, 1]])
        conn = np.hstack([tets, len(pts) + inv.reshape(-1, 6)])
        pts = np.vstack([pts, mids])
        ctype = pv.CellType.QUADRATIC_TETRA
    else:
        conn = tets
        ctype = pv.CellType.TETRA
    k = conn.shape[1]
    cells = np.hstack([np.full((len(conn), 1), k), conn]).ravel().astype(np.int64)
    return pv.UnstructuredGrid(
        cells, np.full(len(conn), ctype, np.uint8), pts.astype(float), deep=True
    )


def fingerprint(mesh):
    """hoembed::MeshFingerprint (FNV-1a 64 over little-endian int64 values), 16 hex digits."""
    conn = mesh.cells.reshape(mesh.n_cells, -1)[:, 1:]
    vals = np.column_stack([np.asarray(mesh.celltypes, np.int64), conn]).ravel()
    data = np.concatenate([[mesh.n_points, mesh.n_cells], vals]).astype("<i8").tobytes()
    h = 14695981039346656037
    for b in data:
        h = ((h ^ b) * 1099511628211) & 0xFFFFFFFFFFFFFFFF
    return f"{h:016x}"


def thorny_beam_surface(
    length=8.0,
    width=1.0,
    spacing=0.0125,
    height=0.3,
    radius=0.1,
    pitch=0.25,
    rows=(0.375, 0.625),
    clear=1.0,
    base_offset=0.0,
):
    """Fine surface of the beam [0,length]x[0,width]^2 with cone thorns on the 4 long faces.

    Returns (points v, rest points p on the box, normals n, d, triangles) where v = p + d n.
    Thorn centres are grid nodes when pitch/2 is a multiple of spacing (sharp tips).
    `base_offset` > 0 lifts every vertex (all of them then have d != 0, the worst case
    for speed; v = p + d n(p) then no longer holds near the box edges)."""
    verts, bases, normals, dists, tris = [], [], [], [], []

    def sheet(origin, ea, eb, na, nb, normal, thorns):
        a = np.linspace(0, 1, na + 1)
        b = np.linspace(0, 1, nb + 1)
        A, B = np.meshgrid(a, b, indexing="ij")
        p = origin + A.reshape(-1, 1) * ea + B.reshape(-1, 1) * eb
        d = np.full(len(p), float(base_offset))
        if thorns:
            s = p @ (ea / np.linalg.norm(ea))  # along the beam
            t = (p - origin) @ (eb / np.linalg.norm(eb))  # across the face
            cx = np.arange(clear + pitch / 2, length - clear, pitch)
            for row in rows:
                r = np.hypot(s[:, None] - cx[None, :], (t - row)[:, None]).min(axis=1)
                d = np.maximum(d, base_offset + height * np.clip(1.0 - r / radius, 0.0, None))
        start = sum(len(x) for x in verts)
        idx = start + np.arange((na + 1) * (nb + 1)).reshape(na + 1, nb + 1)
        q0, q1, q2, q3 = idx[:-1, :-1], idx[1:, :-1], idx[1:, 1:], idx[:-1, 1:]
        if np.dot(np.cross(ea, eb), normal) > 0:
            t1, t2 = np.stack([q0, q1, q2], -1), np.stack([q0, q2, q3], -1)
        else:
            t1, t2 = np.stack([q0, q2, q1], -1), np.stack([q0, q3, q2], -1)
        tris.append(np.vstack([t1.reshape(-1, 3), t2.reshape(-1, 3)]))
        verts.append(p + d[:, None] * normal)
        bases.append(p)
        normals.append(np.tile(normal, (len(p), 1)))
        dists.append(d)

    L, W = length, width
    nl, nw = int(round(L / spacing)), int(round(W / spacing))
    ex, ey, ez = np.eye(3)
    sheet(np.zeros(3), L * ex, W * ey, nl, nw, -ez, True)  # z = 0
    sheet(W * ez, L * ex, W * ey, nl, nw, ez, True)  # z = W
    sheet(np.zeros(3), L * ex, W * ez, nl, nw, -ey, True)  # y = 0
    sheet(W * ey, L * ex, W * ez, nl, nw, ey, True)  # y = W
    sheet(np.zeros(3), W * ey, W * ez, nw, nw, -ex, False)  # x = 0
    sheet(L * ex, W * ey, W * ez, nw, nw, ex, False)  # x = L
    return (
        np.vstack(verts),
        np.vstack(bases),
        np.vstack(normals),
        np.concatenate(dists),
        np.vstack(tris),
    )


def _locate(mesh, n, size, p, axis=None, chunk=200000):
    """Cell of the box mesh containing p (on or inside the box), the barycentric
    coordinates of p in it and, where `axis` >= 0 (p on the box plane normal to that axis),
    the local face of that cell lying in the plane (else -1); by the structured cube index
    and the 6 Kuhn tets of the cube."""
    conn = mesh.cells.reshape(mesh.n_cells, -1)[:, 1:5]
    X = np.asarray(mesh.points)
    x0 = X[conn[:, 0]]
    T = np.stack([X[conn[:, 1]] - x0, X[conn[:, 2]] - x0, X[conn[:, 3]] - x0], axis=2)
    Tinv = np.linalg.inv(T)
    n = np.asarray(n)
    h = np.asarray(size, float) / n
    if axis is None:
        axis = np.full(len(p), -1)
    cells = np.empty(len(p), np.int64)
    lam = np.empty((len(p), 4))
    faces = np.full(len(p), -1, np.int8)
    for s in range(0, len(p), chunk):
        q = p[s : s + chunk]
        m = len(q)
        ijk = np.clip(np.floor(q / h).astype(np.int64), 0, n - 1)
        cube = (ijk[:, 2] * n[1] + ijk[:, 1]) * n[0] + ijk[:, 0]
        cand = cube[:, None] * 6 + np.arange(6)[None, :]
        l123 = np.einsum(
            "cij,cj->ci", Tinv[cand.ravel()], np.repeat(q, 6, axis=0) - x0[cand.ravel()]
        ).reshape(-1, 6, 3)
        lm = np.concatenate([1.0 - l123.sum(axis=2, keepdims=True), l123], axis=2)
        score = lm.min(axis=2)  # (m, 6): >= 0 where the tet contains p
        ax = axis[s : s + chunk]
        onface = ax >= 0
        # For points on a box plane: the (tet, face) whose 3 corners lie in that plane.
        cc = X[conn[cand]]  # (m, 6, 4, 3)
        axc = np.where(onface, ax, 0)
        coord = np.take_along_axis(cc, axc[:, None, None, None], axis=3)[..., 0]  # (m, 6, 4)
        target = q[np.arange(m), axc]
        inplane = np.abs(coord - target[:, None, None]) < 1e-9  # corner in the plane
        ok = np.stack([inplane[:, :, FACE_CORNERS[f]].all(axis=2) for f in range(4)], axis=2)
        ok &= (score >= -1e-9)[:, :, None]
        flat = ok.reshape(m, 24)
        has = flat.any(axis=1)
        pick = flat.argmax(axis=1)
        best = np.where(onface & has, pick // 4, score.argmax(axis=1))
        if (onface & ~has).any():
            raise RuntimeError("a point on the box boundary has no boundary face")
        cells[s : s + chunk] = cand[np.arange(m), best]
        lam[s : s + chunk] = lm[np.arange(m), best]
        faces[s : s + chunk] = np.where(onface, pick % 4, -1)
    return cells, lam, faces, Tinv, x0


def _set_field(ds, name, value):
    arr = vcore.vtkStringArray()
    arr.SetName(name)
    arr.InsertNextValue(value)
    ds.GetFieldData().AddArray(arr)


def embed(mesh, n, size, v, p, normals, d, tris, method):
    """The embedded surface (pyvista.PolyData with the embedding arrays) of vertices
    v = p + d n in the straight box mesh `mesh` of n cubes over `size`."""
    axis = np.where(d != 0, np.abs(normals).argmax(axis=1), -1)
    cells, lam, face, Tinv, x0 = _locate(mesh, n, size, p, axis)
    if method == "normal-offset":
        pc = lam[:, 1:]
        dist = d
    else:
        pc = np.einsum("cij,cj->ci", Tinv[cells], v - x0[cells])
        face = np.full(len(p), -1, np.int8)
        dist = np.zeros(len(p))
    surf = pv.PolyData(v, faces=np.hstack([np.full((len(tris), 1), 3), tris]).ravel(), deep=True)
    surf.point_data["EmbeddingCellId"] = cells
    surf.point_data["EmbeddingParametricCoords"] = pc
    surf.point_data["EmbeddingDistance"] = dist
    surf.point_data["EmbeddingResidual"] = np.zeros(len(p))
    surf.point_data["EmbeddingFace"] = face
    _set_field(surf, "EmbeddingMethod", method)
    _set_field(surf, "EmbeddingMeshFingerprint", fingerprint(mesh))
    return surf


def bend_twist(x, length=8.0, width=1.0, radius=5.0, twist=0.12, amount=1.0):
    """A smooth deformation of all of space: twist about the beam axis (twist * x rad),
    then bend the axis onto an arc of the given radius in the x-z plane. `amount` in
    [0, 1] scales both (amount 0 is the identity)."""
    x = np.asarray(x, float)
    c = 0.5 * width
    if amount == 0:
        return x.copy()
    a = amount * twist * x[:, 0]
    y, z = x[:, 1] - c, x[:, 2] - c
    yt = np.cos(a) * y - np.sin(a) * z
    zt = np.sin(a) * y + np.cos(a) * z
    if not np.isfinite(radius):
        out = x.copy()
        out[:, 1], out[:, 2] = yt + c, zt + c
        return out
    R = radius / amount
    th = x[:, 0] / R
    out = np.empty_like(x)
    out[:, 0] = (R + zt) * np.sin(th)
    out[:, 1] = yt + c
    out[:, 2] = (R + zt) * np.cos(th) - R + c
    return out
