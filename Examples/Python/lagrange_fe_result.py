"""A fine surface carried by a curved FE result from solvers nobody here wrote.

gmsh meshes a CAD cylinder with curved second-order tetrahedra; scikit-fem solves linear
elasticity on that mesh with isoparametric P2 elements (a cantilever under gravity); the
result is written as VTK Lagrange tetrahedra (VTK_LAGRANGE_TETRAHEDRON, VTK's node order,
matched by parametric coordinates) with the displacement as point data; HOEmbed embeds a
fine triangle surface of the same cylinder (gmsh's, from the CAD surface) in the rest
mesh and transfers it onto the deformed one.

    .venv/bin/python Examples/Python/lagrange_fe_result.py [--out DIR] [--picture PNG]

Needs the gmsh and scikit-fem wheels. Prints the embedding residual, the transfer at rest,
and, for the surface points inside the mesh, the rest and transferred positions against
VTK's own vtkLagrangeTetra evaluated at HOEmbed's cell and parametric coordinates, and
writes DIR/fe_result.vtu, DIR/surface_rest.vtp, DIR/surface_deformed.vtp and the picture.
"""

import argparse
import json
import pathlib

import gmsh
import hoembed
import numpy as np
import pyvista as pv
import vtk
from skfem import (
    Basis,
    ElementTetP2,
    ElementVector,
    LinearForm,
    MeshTet,
    MeshTet2,
    asm,
    condense,
    solve,
)
from skfem.models.elasticity import lame_parameters, linear_elasticity

LENGTH, RADIUS = 4.0, 0.5


def gmsh_cylinder(size, order):
    """gmsh's mesh of the CAD cylinder along x: (points, tets in gmsh's node order, the
    reference coordinates of gmsh's nodes) for order >= 1, or the surface triangles when
    `order` is 0 (a 2D mesh of the same CAD surface)."""
    gmsh.initialize()
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add("cylinder")
        gmsh.model.occ.addCylinder(0, 0, 0, LENGTH, 0, 0, RADIUS)
        gmsh.model.occ.synchronize()
        gmsh.option.setNumber("Mesh.MeshSizeMax", size)
        gmsh.option.setNumber("Mesh.MeshSizeMin", size)
        gmsh.model.mesh.generate(2 if order == 0 else 3)
        if order > 1:
            gmsh.model.mesh.setOrder(order)
        tags, coords, _ = gmsh.model.mesh.getNodes()
        index = {t: i for i, t in enumerate(tags)}
        points = np.ascontiguousarray(coords.reshape(-1, 3))
        dim = 2 if order == 0 else 3
        types, _, nodes = gmsh.model.mesh.getElements(dim)
        etype = types[0]
        _, _, _, n, local, _ = gmsh.model.mesh.getElementProperties(etype)
        cells = np.array([index[t] for t in nodes[0]]).reshape(-1, n)
        return points, cells, np.asarray(local).reshape(n, -1)
    finally:
        gmsh.finalize()


def vtk_order(local, n_points):
    """perm[i] = the gmsh node at VTK_LAGRANGE_TETRAHEDRON's node i, by parametric
    coordinates (both reference tetrahedra are (0,0,0), (1,0,0), (0,1,0), (0,0,1))."""
    cell = vtk.vtkLagrangeTetra()
    cell.GetPointIds().SetNumberOfIds(n_points)
    cell.GetPoints().SetNumberOfPoints(n_points)
    cell.Initialize()
    pc = cell.GetParametricCoords()
    vtk_pc = np.array([pc[i] for i in range(3 * n_points)]).reshape(-1, 3)
    d = np.linalg.norm(vtk_pc[:, None, :] - local[None, :, :], axis=2)
    perm = d.argmin(axis=1)
    assert np.allclose(d.min(axis=1), 0.0, atol=1e-9) and len(set(perm)) == n_points
    if n_points == 10:  # the mids in VTK's tet10 order, which scikit-fem's numbering uses
        for k, (a, b) in enumerate([(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)]):
            assert np.allclose(vtk_pc[4 + k], 0.5 * (vtk_pc[a] + vtk_pc[b]))
    return perm


def solve_cantilever(points, tets, young=1e4, poisson=0.3, rho=1.0, g=9.81):
    """scikit-fem's P2 linear-elasticity solution (clamped at x = 0, gravity along -z)
    on the curved tet10 mesh: the displacement at every mesh point."""
    corners = np.unique(tets[:, :4])
    # skfem numbers vertices 0..nv-1: renumber so that corners come first
    order = np.concatenate([corners, np.setdiff1d(np.arange(len(points)), corners)])
    new = np.empty(len(points), dtype=int)
    new[order] = np.arange(len(points))
    pts, cells = points[order], new[tets]
    nv = len(corners)
    lin = MeshTet(pts[:nv].T.copy(), cells[:, :4].T.copy())
    edge_index = {tuple(sorted(e)): i for i, e in enumerate(lin.edges.T)}
    mid = np.full(lin.edges.shape[1], -1)
    for c in cells:  # VTK's tet10 edge order of the mid nodes
        for k, (a, b) in enumerate([(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)]):
            mid[edge_index[tuple(sorted((c[a], c[b])))]] = c[4 + k]
    mesh = MeshTet2(np.hstack([pts[:nv].T, pts[mid].T]), cells[:, :4].T.copy())
    basis = Basis(mesh, ElementVector(ElementTetP2()), intorder=4)
    K = asm(linear_elasticity(*lame_parameters(young, poisson)), basis)

    @LinearForm
    def weight(v, w):
        return -rho * g * v[2]

    f = asm(weight, basis)
    clamped = basis.get_dofs(lambda x: x[0] < 1e-9).all()
    u = solve(*condense(K, f, D=clamped))
    disp = np.zeros((len(points), 3))
    dofs = np.zeros((len(points), 3), dtype=int)
    dofs[:nv] = basis.nodal_dofs.T
    dofs[mid] = basis.edge_dofs.T
    disp[order] = u[dofs]
    return disp


def lagrange_grid(points, cells, perm):
    n = cells.shape[1]
    conn = np.hstack([np.full((len(cells), 1), n), cells[:, perm]]).ravel()
    types = np.full(len(cells), pv.CellType.LAGRANGE_TETRAHEDRON, dtype=np.uint8)
    return pv.UnstructuredGrid(conn, types, points.copy())


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--out", default="lagrange_output")
    ap.add_argument(
        "--picture",
        default=None,
        help="PNG of rest and deformed (default: DIR/lagrange_fe_result.png)",
    )
    ap.add_argument("--size", type=float, default=0.3, help="gmsh's element size of the FE mesh")
    ap.add_argument(
        "--surface-size", type=float, default=0.03, help="gmsh's triangle size of the fine surface"
    )
    args = ap.parse_args()
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)

    points, tets, local = gmsh_cylinder(args.size, 2)
    perm = vtk_order(local, tets.shape[1])
    # skfem wants VTK's tet10 order (corners, then mids of 01 12 20 03 13 23)
    vtk_tets = tets[:, perm]
    disp = solve_cantilever(points, vtk_tets)
    rest = lagrange_grid(points, tets, perm)
    rest.point_data["Displacement"] = disp
    deformed = rest.copy()
    deformed.points = points + disp
    rest.save(out / "fe_result.vtu")

    spts, stris, _ = gmsh_cylinder(args.surface_size, 0)
    surface = pv.PolyData(spts, np.hstack([np.full((len(stris), 1), 3), stris]).ravel())
    surface = surface.clean()
    print(
        f"gmsh + scikit-fem: {rest.n_cells} curved P2 Lagrange tetrahedra, tip deflection "
        f"{-disp[:, 2].min():.3f}; fine surface {surface.n_points} vertices"
    )

    embedded = hoembed.embed(surface, rest)
    diag = float(np.linalg.norm(np.ptp(rest.points, axis=0)))
    residual = float(embedded.point_data["EmbeddingResidual"].max()) / diag
    at_rest = hoembed.transfer(embedded, rest)
    rest_error = float(np.abs(at_rest.points - surface.points).max()) / diag
    moved = hoembed.transfer(embedded, deformed)
    moved.save(out / "surface_deformed.vtp")
    embedded.save(out / "surface_rest.vtp")

    # Inside the mesh, VTK's own cells check the transfer: vtkLagrangeTetra evaluated at
    # HOEmbed's (cell, parametric coordinates) gives back the rest point, and on the
    # deformed mesh the transferred point (scikit-fem's displacement as VTK interpolates
    # it). VTK's own point location (vtkCellLocator::FindCell, what vtkProbeFilter uses)
    # is shown for contrast: it inverts a linear approximation of a curved Lagrange cell.
    inside = np.flatnonzero(np.asarray(embedded.point_data["EmbeddingClosestDistance"]) == 0.0)
    cell_ids = np.asarray(embedded.point_data["EmbeddingCellId"])
    pcoords = np.asarray(embedded.point_data["EmbeddingParametricCoords"])
    cell = vtk.vtkGenericCell()
    locator = vtk.vtkCellLocator()
    locator.SetDataSet(rest)
    locator.BuildLocator()
    sub = vtk.reference(0)
    weights = [0.0] * tets.shape[1]
    y = [0.0, 0.0, 0.0]
    rest_back = moved_vtk = vtk_locate = 0.0
    for v in inside:
        for grid, target, which in ((rest, surface.points[v], 0), (deformed, moved.points[v], 1)):
            grid.GetCell(int(cell_ids[v]), cell)
            cell.EvaluateLocation(sub, list(pcoords[v]), y, weights)
            err = float(np.linalg.norm(np.array(y) - target))
            if which == 0:
                rest_back = max(rest_back, err)
            else:
                moved_vtk = max(moved_vtk, err)
        pc = [0.0, 0.0, 0.0]
        if locator.FindCell(surface.points[v], 1e-12, cell, pc, weights) >= 0:
            cell.EvaluateLocation(sub, pc, y, weights)
            vtk_locate = max(vtk_locate, float(np.linalg.norm(np.array(y) - surface.points[v])))
    rest_back, moved_vtk, vtk_locate = rest_back / diag, moved_vtk / diag, vtk_locate / diag
    print(f"largest embedding residual {residual:.2e} of the diagonal")
    print(f"transfer at rest: largest move {rest_error:.2e} of the diagonal")
    print(
        f"{len(inside)} surface points inside the mesh, against vtkLagrangeTetra at HOEmbed's "
        f"coordinates: rest {rest_back:.2e}, deformed {moved_vtk:.2e} of the diagonal; "
        f"VTK's own point location maps back to {vtk_locate:.2e}"
    )

    picture = pathlib.Path(args.picture) if args.picture else out / "lagrange_fe_result.png"
    pl = pv.Plotter(shape=(1, 2), off_screen=True, window_size=(1400, 450))
    for col, (surf, title) in enumerate(
        ((surface, "rest"), (moved, "scikit-fem P2 under gravity"))
    ):
        pl.subplot(0, col)
        pl.add_mesh(surf, color="wheat", smooth_shading=True, show_edges=False)
        pl.add_text(title, font_size=11)
        pl.camera_position = [(2.0, -7.5, 1.2), (2.0, 0.0, -0.25), (0, 0, 1)]
    pl.screenshot(str(picture))
    pl.close()
    print("wrote", out / "fe_result.vtu", out / "surface_deformed.vtp", picture)
    summary = {
        "cells": rest.n_cells,
        "surface_vertices": surface.n_points,
        "residual": residual,
        "rest_move": rest_error,
        "inside": len(inside),
        "inside_rest_vs_vtk": rest_back,
        "inside_deformed_vs_vtk": moved_vtk,
        "vtk_point_location": vtk_locate,
    }
    print(json.dumps(summary))


if __name__ == "__main__":
    main()
