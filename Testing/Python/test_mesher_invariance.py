"""vtkTet10Mesher is deterministic and scale-invariant (issue 27): the same surface gives
the same mesh on every run, and the surface scaled by 2^k gives that mesh scaled by 2^k
(powers of two scale doubles exactly; the decimation runs on the surface scaled to a
diagonal in [0.5, 1)). The same connectivity always; the points to the last bit of a few
coordinates: repeated runs in one process were seen to differ by one unit in the last
place (1.7e-18 on a coordinate of ~0.01), with one thread too - a cause not yet found."""

import hoembed
import numpy as np
import pytest
import pyvista as pv


def bumpy():
    s = pv.Sphere(theta_resolution=80, phi_resolution=80).triangulate().clean()
    r = np.linalg.norm(s.points, axis=1, keepdims=True)
    s.points *= 1 + 0.08 * np.sin(5 * s.points[:, :1]) * np.cos(4 * s.points[:, 1:2]) / r
    return s


def mesh(surface, k, order=2):
    s = surface.copy()
    s.points = s.points * 2.0**k
    g = hoembed.tet10_mesh(s, n_elements=300, order=order)
    return np.asarray(g.points) / 2.0**k, np.asarray(g.cells)


def check_invariant(surface, n, order=2):
    def mesh(k):
        s = surface.copy()
        s.points = s.points * 2.0**k
        g = hoembed.tet10_mesh(s, n_elements=n, order=order)
        return np.asarray(g.points) / 2.0**k, np.asarray(g.cells)

    p0, c0 = mesh(0)
    assert len(c0) > 0
    for k in (0, -10, 10):  # 0 again: the same run twice
        p, c = mesh(k)
        assert np.array_equal(c, c0), f"connectivity differs at 2^{k}"
        # a few ulps of the mesh's size at most (see above)
        np.testing.assert_allclose(
            p, p0, rtol=0, atol=1e-14 * np.ptp(p0, axis=0).max(), err_msg=f"points differ at 2^{k}"
        )


@pytest.mark.parametrize("order", [2, 1])
def test_generated_bumpy_sphere(order):
    check_invariant(bumpy(), 300, order)


def test_bunny_watertight(data_dir):
    # 909 cells at 2^-10 against 934 at 2^0 before the decimation ran at a fixed scale
    s = pv.read(data_dir / "bunny_watertight.obj").extract_surface().triangulate()
    check_invariant(s, 1000)
