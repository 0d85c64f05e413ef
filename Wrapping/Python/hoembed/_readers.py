"""Surface files that VTK 9.1's readers do not turn into a surface, for the CLI's reader.

- PLY files whose triangles are stored as strips (an element ``tristrips`` with one list
  property, strips separated by -1, as some scanners and Stanford's tools write them):
  VTK's PLY reader reads only ``face`` elements and reports "no polygons". read_ply reads
  vertices, faces and strips (ASCII and binary), checking every index.
- glTF / .glb files: pyvista (vtkGLTFReader) gives a multiblock of meshes;
  surface_of merges the blocks into one surface.
- OFF files (Geomview's object file format, common in geometry processing data sets): VTK
  has no reader for them. read_off reads the ASCII form: one vertex and one face per
  line after the counts (extra values on a line, colours or normals, are ignored), polygons
  as fans; the binary form is refused (its writers disagree on the face records).
"""

import numpy as np

_PLY_TYPES = {
    "char": "i1",
    "int8": "i1",
    "uchar": "u1",
    "uint8": "u1",
    "short": "i2",
    "int16": "i2",
    "ushort": "u2",
    "uint16": "u2",
    "int": "i4",
    "int32": "i4",
    "uint": "u4",
    "uint32": "u4",
    "float": "f4",
    "float32": "f4",
    "double": "f8",
    "float64": "f8",
}


class PlyError(ValueError):
    """A PLY file this reader cannot read, with the reason."""


class OffError(ValueError):
    """An OFF file this reader cannot read, with the reason."""


def ply_elements(path):
    """(format, [(name, count, [(prop, type) or (prop, count type, item type)])], body
    offset) from the header of the PLY file at `path`."""
    with open(path, "rb") as fh:
        head = fh.read(1 << 16)
    end = head.find(b"end_header")
    if not head.startswith(b"ply") or end < 0:
        raise PlyError("not a PLY file (no 'ply' ... 'end_header' header)")
    body = head.index(b"\n", end) + 1 if b"\n" in head[end:] else len(head)
    fmt, elements = None, []
    for line in head[:end].decode("ascii", "replace").splitlines()[1:]:
        w = line.split()
        if not w or w[0] in ("comment", "obj_info"):
            continue
        if w[0] == "format" and len(w) >= 2:
            fmt = w[1]
        elif w[0] == "element" and len(w) == 3 and w[2].isdigit():
            elements.append((w[1], int(w[2]), []))
        elif (
            w[0] == "property"
            and elements
            and w[1] == "list"
            and len(w) == 5
            and w[2] in _PLY_TYPES
            and w[3] in _PLY_TYPES
        ):
            elements[-1][2].append((w[4], _PLY_TYPES[w[2]], _PLY_TYPES[w[3]]))
        elif w[0] == "property" and elements and len(w) == 3 and w[1] in _PLY_TYPES:
            elements[-1][2].append((w[2], _PLY_TYPES[w[1]]))
        else:
            raise PlyError(f"bad PLY header line '{line.strip()}'")
    if fmt not in ("ascii", "binary_little_endian", "binary_big_endian"):
        raise PlyError(f"unknown PLY format {fmt!r}")
    return fmt, elements, body


def has_strips(path):
    """True when the PLY file stores triangle strips (an element 'tristrips')."""
    try:
        return any(name == "tristrips" for name, _, _ in ply_elements(path)[1])
    except PlyError:
        return False


class _Binary:
    def __init__(self, data, order):
        self.data, self.order, self.pos = data, order, 0

    def take(self, dtype, count):
        dt = np.dtype(dtype).newbyteorder(self.order)
        end = self.pos + dt.itemsize * count
        if end > len(self.data):
            raise PlyError("the binary PLY file is truncated")
        out = np.frombuffer(self.data, dt, count, self.pos)
        self.pos = end
        return out

    def record(self, props):
        """One element record: scalars as floats, lists as integer arrays."""
        values = {}
        for p in props:
            if len(p) == 3:
                n = int(self.take(p[1], 1)[0])
                values[p[0]] = self.take(p[2], n).astype(np.int64)
            else:
                values[p[0]] = float(self.take(p[1], 1)[0])
        return values

    def table(self, props, count):
        """`count` records of scalars only, as one array per property."""
        dt = np.dtype([(p[0], np.dtype(p[1]).newbyteorder(self.order)) for p in props])
        end = self.pos + dt.itemsize * count
        if end > len(self.data):
            raise PlyError("the binary PLY file is truncated")
        out = np.frombuffer(self.data, dt, count, self.pos)
        self.pos = end
        return {p[0]: out[p[0]].astype(np.float64) for p in props}


class _Ascii:
    def __init__(self, data):
        self.words = data.split()
        self.pos = 0

    def take(self, count):
        if self.pos + count > len(self.words):
            raise PlyError("the ASCII PLY file ends early (truncated)")
        try:
            out = np.array(self.words[self.pos : self.pos + count], dtype=np.float64)
        except ValueError:
            raise PlyError("the ASCII PLY file has a value that is not a number") from None
        self.pos += count
        return out

    def record(self, props):
        values = {}
        for p in props:
            if len(p) == 3:
                n = self.take(1)[0]
                if n != int(n) or n < 0:
                    raise PlyError(f"bad list length {n} in the ASCII PLY file")
                values[p[0]] = self.take(int(n)).astype(np.int64)
            else:
                values[p[0]] = float(self.take(1)[0])
        return values

    def table(self, props, count):
        flat = self.take(count * len(props)).reshape(count, len(props))
        return {p[0]: flat[:, k] for k, p in enumerate(props)}


def _strip_triangles(ids):
    """Triangles of the strips in `ids` (strips separated by -1), with the strip's
    alternating orientation; triangles with a repeated vertex (the joints some writers
    put between strips) are dropped."""
    tris = []
    for strip in np.split(ids, np.flatnonzero(ids < 0)):
        strip = strip[strip >= 0]
        if len(strip) < 3:
            continue
        a, b, c = strip[:-2], strip[1:-1], strip[2:]
        t = np.stack([a, b, c], axis=1)
        odd = np.arange(len(t)) % 2 == 1
        t[odd] = t[odd][:, [1, 0, 2]]
        tris.append(t)
    if not tris:
        return np.zeros((0, 3), np.int64)
    t = np.concatenate(tris)
    keep = (t[:, 0] != t[:, 1]) & (t[:, 1] != t[:, 2]) & (t[:, 0] != t[:, 2])
    return t[keep]


def _fan(polygon):
    """The triangles of a polygon (point ids, at least 3) as a fan from its first corner."""
    return np.stack([np.full(len(polygon) - 2, polygon[0]), polygon[1:-1], polygon[2:]], axis=1)


def _triangles(parts, npoints, error, what):
    """The triangle arrays in `parts` as one (m x 3), every id checked against `npoints`
    (raising `error` naming `what` holds the first bad id)."""
    tris = np.concatenate(parts) if parts else np.zeros((0, 3), np.int64)
    if len(tris) and (tris.min() < 0 or tris.max() >= npoints):
        bad = tris[(tris < 0) | (tris >= npoints)][0]
        raise error(f"{what} names vertex {bad}, outside 0..{npoints - 1}")
    return tris


def read_ply(path):
    """Points (n x 3) and triangles (m x 3) of a PLY file's vertices, faces (fans) and
    triangle strips. Raises PlyError naming the problem."""
    fmt, elements, body = ply_elements(path)
    with open(path, "rb") as fh:
        fh.seek(body)
        data = fh.read()
    stream = (
        _Ascii(data)
        if fmt == "ascii"
        else _Binary(data, "<" if fmt == "binary_little_endian" else ">")
    )
    points, tris = None, []
    for name, count, props in elements:
        if all(len(p) == 2 for p in props):
            table = stream.table(props, count)
            if name == "vertex":
                if not all(k in table for k in "xyz"):
                    raise PlyError("the vertex element lacks x, y or z")
                points = np.stack([table["x"], table["y"], table["z"]], axis=1)
            continue
        records = [stream.record(props) for _ in range(count)]
        lists = [p[0] for p in props if len(p) == 3]
        if name == "face":
            key = "vertex_indices" if "vertex_indices" in lists else lists[0]
            for r in records:
                if len(r[key]) >= 3:
                    tris.append(_fan(r[key]))
        elif name == "tristrips":
            key = "vertex_indices" if "vertex_indices" in lists else lists[0]
            for r in records:
                tris.append(_strip_triangles(r[key]))
    if points is None or len(points) == 0:
        raise PlyError("the PLY file has no vertices")
    return points, _triangles(tris, len(points), PlyError, "a face or strip")


def read_off(path):
    """Points (n x 3) and triangles (m x 3, polygons as fans) of an ASCII OFF file.
    Raises OffError naming the problem."""
    with open(path, "rb") as fh:
        data = fh.read()
    if b"BINARY" in data.split(b"\n", 1)[0].split():
        raise OffError(
            "binary OFF is not read (its writers disagree on the face records); save it as ASCII OFF, PLY or OBJ"
        )
    try:
        text = data.decode("ascii")
    except UnicodeDecodeError:
        raise OffError("not an ASCII OFF file (non-ASCII bytes)") from None
    lines = [ln.split("#", 1)[0].split() for ln in text.splitlines()]
    lines = [ln for ln in lines if ln]
    if not lines or not lines[0][0].endswith("OFF"):
        raise OffError("not an OFF file (the first line is not OFF, COFF, NOFF, ...)")
    key = lines[0][0]
    if key[:-3].strip("STCN"):  # 4OFF, nOFF: 4 or n dimensions
        raise OffError(f"the OFF variant {key!r} is not read (only 3D: OFF, COFF, NOFF, STOFF)")
    counts = lines[0][1:] if len(lines[0]) > 1 else (lines[1] if len(lines) > 1 else [])
    body = lines[1:] if len(lines[0]) > 1 else lines[2:]
    try:
        nv, nf = int(counts[0]), int(counts[1])
    except (IndexError, ValueError):
        raise OffError("the OFF header lacks the vertex and face counts") from None
    if nv <= 0 or nf < 0:
        raise OffError(f"bad OFF counts: {nv} vertices, {nf} faces")
    if len(body) < nv + nf:
        raise OffError(
            f"the OFF file ends early: {nv} vertices and {nf} faces declared, {len(body)} lines found"
        )
    try:
        points = np.array([ln[:3] for ln in body[:nv]], dtype=np.float64)
    except ValueError:
        raise OffError(
            "an OFF vertex line has fewer than 3 numbers or one that is not a number"
        ) from None
    tris = []
    for k, ln in enumerate(body[nv : nv + nf]):
        try:
            n = int(ln[0])
            f = np.array(ln[1 : 1 + n], dtype=np.int64)
        except ValueError:
            raise OffError(f"OFF face {k} is not a list of whole numbers") from None
        if n < 0 or len(f) != n:
            raise OffError(f"OFF face {k} declares {n} vertices but lists {len(f)}")
        if n >= 3:
            tris.append(_fan(f))
    return points, _triangles(tris, nv, OffError, "an OFF face")


def surface_of(data):
    """One pyvista.PolyData from what pyvista.read returned: a surface as it is, a volume
    or a multiblock (glTF scenes: one block per mesh, nested) merged and reduced to its
    surface. None when nothing with cells is in it."""
    import pyvista

    if isinstance(data, pyvista.MultiBlock):
        parts = []

        def collect(block):
            for b in block:
                if isinstance(b, pyvista.MultiBlock):
                    collect(b)
                elif b is not None and b.n_cells > 0:
                    parts.append(b if isinstance(b, pyvista.PolyData) else b.extract_surface())

        collect(data)
        if not parts:
            return None
        data = parts[0].merge(parts[1:]) if len(parts) > 1 else parts[0]
        # merge gives an unstructured grid when it merges several parts
        if not isinstance(data, pyvista.PolyData):
            data = data.extract_surface()
        return data
    if isinstance(data, pyvista.PolyData):
        return data
    try:
        return data.extract_surface()
    except Exception:
        return None
