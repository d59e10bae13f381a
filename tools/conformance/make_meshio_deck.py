"""Mesh a small box with gmsh, convert it with meshio's Nastran writer.

Produces ``decks/conformance/meshio_box_*.bdf``: decks written by a third-party
writer (meshio 5.3.5, ``meshio/nastran/_nastran.py``), to check that the deck
reader copes with what real tools emit:

* ``meshio_box_tet_default.bdf``  CTETRA, meshio defaults: GRID* large field
                                  (``point_format="fixed-large"``, floats like
                                  ``1.23456789E+3``), cells small field
* ``meshio_box_tet_small.bdf``    ``point_format="fixed-small"``: GRID in 8
                                  columns, coordinates cut to 8 characters
* ``meshio_box_tet_free.bdf``     ``point_format="free"``: free-field GRIDs
                                  with coordinates up to 16 characters (longer
                                  than MSC's 8), cells small field
                                  (``cell_format="free"`` crashes in meshio
                                  5.3.5: ``nipl1`` is never assigned)
* ``meshio_box_hex_default.bdf``  transfinite + recombined CHEXA, defaults:
                                  8-node CHEXA needs a continuation, which meshio
                                  writes with explicit markers ``+1<hex eid>``
                                  in columns 73-80 and at the start of the next
                                  line
* ``meshio_box_hex_large.bdf``    CHEXA with ``cell_format="fixed-large"``
                                  (``CHEXA*`` + ``*1<hex eid>`` markers)

What meshio writes (read from the writer): a ``$ Nastran file written by
meshio v5.3.5`` comment, ``BEGIN BULK`` with *no* executive or case control,
GRIDs numbered 1..N with blank CP, elements numbered 1..M, PID taken from the
cell data ``nastran:ref`` (blank if absent -- pyNastran then rejects a CTETRA /
CHEXA card because its PID is required), then ``ENDDATA``.  This script passes
``nastran:ref`` = 1 for every cell and inserts ``PSOLID 1 1`` and a MAT1 before
``ENDDATA`` so the PID resolves.  Nothing else is changed.

Deterministic: single-threaded gmsh with fixed algorithm and sizes.

Run from the repository root:  .venv/bin/python tools/conformance/make_meshio_deck.py
"""
from __future__ import annotations

import tempfile
from pathlib import Path

import gmsh
import meshio
import numpy as np

REPO = Path(__file__).resolve().parents[2]
OUT_DIR = REPO / "decks" / "conformance"

BOX = (2.0, 1.0, 0.5)
APPENDED = (
    "$ appended by tools/conformance/make_meshio_deck.py: property for PID 1\n"
    "PSOLID         1       1\n"
    "MAT1           1  7.+10             .33   2700.\n"
)


def mesh_box(hexa: bool) -> meshio.Mesh:
    """Mesh BOX with gmsh (tets, or transfinite hexes) and return the 3D cells."""
    gmsh.initialize(["-noenv"], readConfigFiles=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.option.setNumber("General.NumThreads", 1)
        gmsh.option.setNumber("Mesh.RandomSeed", 1)
        gmsh.model.add("box")
        gmsh.model.occ.addBox(0.0, 0.0, 0.0, *BOX)
        gmsh.model.occ.synchronize()
        if hexa:
            # 6 x 4 x 3 hexes; x distribution graded so cells are not all equal
            counts = {0: 7, 1: 5, 2: 4}
            for dim, tag in gmsh.model.getEntities(1):
                xmin, ymin, zmin, xmax, ymax, zmax = gmsh.model.getBoundingBox(dim, tag)
                axis = int(np.argmax([xmax - xmin, ymax - ymin, zmax - zmin]))
                coef = 1.2 if axis == 0 else 1.0
                gmsh.model.mesh.setTransfiniteCurve(tag, counts[axis], "Progression", coef)
            for _, tag in gmsh.model.getEntities(2):
                gmsh.model.mesh.setTransfiniteSurface(tag)
                gmsh.model.mesh.setRecombine(2, tag)
            for _, tag in gmsh.model.getEntities(3):
                gmsh.model.mesh.setTransfiniteVolume(tag)
                gmsh.model.mesh.setRecombine(3, tag)
        else:
            gmsh.option.setNumber("Mesh.Algorithm", 6)      # Frontal-Delaunay 2D
            gmsh.option.setNumber("Mesh.Algorithm3D", 1)    # Delaunay 3D
            gmsh.option.setNumber("Mesh.MeshSizeMin", 0.3)
            gmsh.option.setNumber("Mesh.MeshSizeMax", 0.3)
        gmsh.model.mesh.generate(3)
        with tempfile.TemporaryDirectory() as tmp:
            msh = Path(tmp) / "box.msh"
            gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
            gmsh.write(str(msh))
            mesh = meshio.read(msh)
    finally:
        gmsh.finalize()

    kind = "hexahedron" if hexa else "tetra"
    cells = [block for block in mesh.cells if block.type == kind]
    data = np.concatenate([block.data for block in cells])
    used = np.unique(data)
    # keep only the points the 3D cells use, renumbered compactly
    remap = np.full(len(mesh.points), -1, dtype=np.int64)
    remap[used] = np.arange(len(used))
    points = mesh.points[used]
    return meshio.Mesh(points, [(kind, remap[data])],
                       cell_data={"nastran:ref": [np.ones(len(data), dtype=np.int64)]})


def write_deck(mesh: meshio.Mesh, path: Path, **fmt) -> None:
    with tempfile.TemporaryDirectory() as tmp:
        raw = Path(tmp) / "raw.bdf"
        meshio.write(raw, mesh, file_format="nastran", **fmt)
        text = raw.read_text()
    assert text.endswith("ENDDATA\n"), text[-40:]
    text = text[: -len("ENDDATA\n")] + APPENDED + "ENDDATA\n"
    path.write_text(text)
    print(f"wrote {path.relative_to(REPO)} ({len(mesh.points)} grids, "
          f"{len(mesh.cells[0].data)} {mesh.cells[0].type}) {fmt or 'defaults'}")


def main() -> None:
    OUT_DIR.mkdir(parents=True, exist_ok=True)
    tets = mesh_box(hexa=False)
    write_deck(tets, OUT_DIR / "meshio_box_tet_default.bdf")
    write_deck(tets, OUT_DIR / "meshio_box_tet_small.bdf", point_format="fixed-small")
    # cell_format="free" crashes in meshio 5.3.5 (nipl1 is never set), so only
    # the GRIDs are free field here
    write_deck(tets, OUT_DIR / "meshio_box_tet_free.bdf", point_format="free")
    hexes = mesh_box(hexa=True)
    write_deck(hexes, OUT_DIR / "meshio_box_hex_default.bdf")
    write_deck(hexes, OUT_DIR / "meshio_box_hex_large.bdf", cell_format="fixed-large")


if __name__ == "__main__":
    main()
