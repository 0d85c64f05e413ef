"""Built-in models, generated in code (real scans cannot be shipped).

``thorny_tail()`` is the default model of ``hoembed demo``: a tapered tube curled like a
seahorse tail, covered with sharp thorns far smaller than any element of a coarse FE
mesh, so only a good embedding keeps their shape when the tail bends (paper Figs. 3-5).
"""

import numpy as np
import pyvista

__all__ = ["thorny_tail"]


def _centreline(u, length, curl):
    """A planar spiral that curls up by `curl` turns, lifted slightly out of its plane."""
    theta = 2.0 * np.pi * curl * u**1.5
    radius = length / (2.0 * np.pi * curl) * (1.0 - 0.55 * u)
    c = np.stack([radius * np.sin(theta), radius * (1 - np.cos(theta)), 0.15 * length * u], axis=-1)
    return c


def thorny_tail(
    rings=360,
    sectors=128,
    length=10.0,
    thickness=1.0,
    curl=0.6,
    thorn_height=0.35,
    thorn_rows=10,
    thorn_pitch=0.045,
):
    """A closed, manifold, consistently oriented triangle surface of a curled thorny tail.

    Parameters
    ----------
    rings, sectors : int
        Resolution along and around the tail (triangles: 2 * rings * sectors); the
        defaults give 92k triangles.
    length, thickness : float
        Arc length of the centreline and the tube's largest diameter.
    curl : float
        Turns of the spiral (0: straight).
    thorn_height : float
        Height of the thorns relative to the local tube radius.
    thorn_rows, thorn_pitch : int, float
        Thorns around the tube and their spacing along it (fraction of the length).

    Returns
    -------
    pyvista.PolyData
    """
    u = np.linspace(0.0, 1.0, rings + 2)[1:-1]  # interior rings; the poles close the ends
    v = np.linspace(0.0, 2.0 * np.pi, sectors, endpoint=False)
    c = _centreline(u, length, curl)
    dc = np.gradient(c, u, axis=0)
    T = dc / np.linalg.norm(dc, axis=1, keepdims=True)
    ref = np.array([0.0, 0.0, 1.0])
    N = np.cross(T, ref)
    N /= np.linalg.norm(N, axis=1, keepdims=True)
    B = np.cross(T, N)
    # Tube radius: rounded head, long taper to a blunt tip.
    base = 0.5 * thickness * np.sqrt(np.clip(np.sin(np.pi * u), 0, None)) * (1.0 - 0.6 * u)
    # Thorns: sharp cones on a staggered grid in (u, v).
    uu, vv = np.meshgrid(u, v, indexing="ij")
    centres_u = np.arange(thorn_pitch, 1.0 - thorn_pitch / 2, thorn_pitch)
    bump = np.zeros_like(uu)
    width_u = 0.4 * thorn_pitch
    width_v = 0.35 * 2.0 * np.pi / thorn_rows
    for k, cu in enumerate(centres_u):
        shift = (k % 2) * np.pi / thorn_rows
        dv = np.angle(np.exp(1j * (vv - shift) * thorn_rows)) / thorn_rows  # to nearest row
        d = np.sqrt(((uu - cu) / width_u) ** 2 + (dv / width_v) ** 2)
        bump = np.maximum(bump, np.clip(1.0 - d, 0.0, None) ** 1.6)
    r = base[:, None] * (1.0 + thorn_height * bump)
    ring_pts = c[:, None, :] + r[..., None] * (
        np.cos(vv)[..., None] * N[:, None, :] + np.sin(vv)[..., None] * B[:, None, :]
    )
    c0 = _centreline(np.array([0.0]), length, curl)[0]
    c1 = _centreline(np.array([1.0]), length, curl)[0]
    points = np.vstack([ring_pts.reshape(-1, 3), c0, c1])
    south, north = rings * sectors, rings * sectors + 1

    def pid(i, j):
        return i * sectors + (j % sectors)

    faces = []
    i = np.arange(rings - 1)[:, None]
    j = np.arange(sectors)[None, :]
    a, b = pid(i, j), pid(i, j + 1)
    cc, d = pid(i + 1, j + 1), pid(i + 1, j)
    quads = np.stack([a, b, cc, d], axis=-1).reshape(-1, 4)
    faces.append(np.column_stack([np.full(len(quads), 3), quads[:, 0], quads[:, 1], quads[:, 2]]))
    faces.append(np.column_stack([np.full(len(quads), 3), quads[:, 0], quads[:, 2], quads[:, 3]]))
    jj = np.arange(sectors)
    faces.append(
        np.column_stack([np.full(sectors, 3), np.full(sectors, south), pid(0, jj + 1), pid(0, jj)])
    )
    last = rings - 1
    faces.append(
        np.column_stack(
            [np.full(sectors, 3), np.full(sectors, north), pid(last, jj), pid(last, jj + 1)]
        )
    )
    surface = pyvista.PolyData(points, np.vstack(faces).ravel(), deep=True)
    if surface.volume < 0:  # make the normals point outward
        surface = surface.flip_normals()
    return surface
