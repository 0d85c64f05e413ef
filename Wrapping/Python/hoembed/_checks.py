"""Argument checks of the pyvista-level embed() and transfer(), shared by both bindings:
the VTK build's package (embedding.py, transfer.py over the VTK filters) and the pip
wheel's (Wrapping/Pip/hoembed, over the nanobind module). Pure Python."""

from ._errors import HOEmbedArgumentError, check_callable, check_dataset, check_int

# values of hoembed::EmbeddingMethod (= vtkEmbeddingCoordinatesFilter's Method)
EMBED_METHODS = {"normal-offset": 0, "barycentric": 1}
# values of hoembed::TransferNormals (= vtkDeformationTransferFilter's NormalMode)
NORMAL_MODES = {"recompute": 0, "rotate": 1, "deform": 2}


def embed_arguments(surface, fe_mesh, method, n_partitions, progress):
    """Check embed()'s arguments; returns (method value, n_partitions as int)."""
    if not isinstance(method, str) or method not in EMBED_METHODS:
        raise HOEmbedArgumentError(
            f"embed: method must be one of {sorted(EMBED_METHODS)}, not {method!r}")
    check_dataset("embed", "surface", surface, "vtkPolyData")
    check_dataset("embed", "fe_mesh", fe_mesh, "vtkUnstructuredGrid")
    n_partitions = check_int("embed", "n_partitions", n_partitions, 0, 1 << 20)
    check_callable("embed", "progress", progress)
    return EMBED_METHODS[method], n_partitions


def transfer_arguments(embedded_surface, deformed_mesh, normals):
    """Check transfer()'s arguments; returns the normal mode's value."""
    if not isinstance(normals, str) or normals not in NORMAL_MODES:
        raise HOEmbedArgumentError(
            f"transfer: normals must be 'recompute', 'rotate' or 'deform', not {normals!r}")
    check_dataset("transfer", "embedded_surface", embedded_surface, "vtkPolyData")
    check_dataset("transfer", "deformed_mesh", deformed_mesh, "vtkUnstructuredGrid")
    return NORMAL_MODES[normals]
