"""Shared plumbing for the scene generators in ``meshes/``: a deterministic gmsh session, the
gmsh → meshio → Nastran include conversion, node sets of physical groups, and include files of
cards.

Every scene script builds its geometry with the gmsh API inside :func:`gmsh_session`, names
physical groups, then calls :func:`extract` to get a :class:`SceneMesh` and writes

* ``<name>.bdf``: GRIDs and elements only (meshio's Nastran writer, large-field GRIDs, PID per
  element = the property id given for its physical group), no BEGIN BULK / ENDDATA, so that a
  deck pulls it in with ``INCLUDE``;
* optional extra includes (RBE2 spiders, master grids, ASET1, SENSORs) written with
  :func:`write_cards` from :func:`paraflex_tools.cards.card` texts.

Determinism: one gmsh thread, fixed random seed, fixed algorithms; node and element numbering
follow gmsh's tags in sorted order, so the same script and size give byte-identical files.
"""
from __future__ import annotations

import contextlib
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

import gmsh
import meshio
import numpy as np

# gmsh element type → (meshio cell type, permutation from gmsh to meshio/Nastran node order)
_GMSH_TYPES = {
    2: ("triangle", None),
    3: ("quad", None),
    4: ("tetra", None),
    5: ("hexahedron", None),
    6: ("wedge", None),
    # gmsh's 10-node tetra lists the last two edge nodes as (3,2),(3,1); Nastran wants (2,4),(3,4)
    11: ("tetra10", [0, 1, 2, 3, 4, 5, 6, 7, 9, 8]),
}


@contextlib.contextmanager
def gmsh_session(name: str):
    """Initialise gmsh quietly and deterministically; always finalise."""
    gmsh.initialize(["-noenv"], readConfigFiles=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.option.setNumber("General.NumThreads", 1)
        gmsh.option.setNumber("Mesh.RandomSeed", 1)
        gmsh.model.add(name)
        yield gmsh.model
    finally:
        gmsh.finalize()


@dataclass
class SceneMesh:
    """The elements of the chosen physical groups with compact grid ids 1..N."""

    points: np.ndarray                       # (N, 3) coordinates, grid id = row + 1
    cells: list[tuple[str, np.ndarray]]      # meshio cell blocks, 0-based point rows
    pids: list[np.ndarray]                   # property id per cell, per block
    gmsh_to_grid: dict[int, int] = field(repr=False)  # gmsh node tag → grid id

    def grids_of(self, dim: int, physical_tag: int) -> list[int]:
        """Sorted grid ids of the nodes of a physical group (e.g. a face for an RBE2 spider).

        Nodes of the group that no exported element uses are an error: a spider on them would
        hang on grids without stiffness."""
        tags, _ = gmsh.model.mesh.getNodesForPhysicalGroup(dim, physical_tag)
        missing = [int(t) for t in tags if int(t) not in self.gmsh_to_grid]
        if missing:
            raise ValueError(f"physical group ({dim}, {physical_tag}) has {len(missing)} nodes "
                             "outside the exported elements")
        return sorted(self.gmsh_to_grid[int(t)] for t in tags)

    def n_elements(self) -> int:
        return sum(len(c) for _, c in self.cells)


def extract(groups: dict[tuple[int, int], int]) -> SceneMesh:
    """Collect the elements of physical groups ``{(dim, physical tag): PID}`` from the current
    gmsh mesh. Grids are the nodes those elements use, numbered in gmsh tag order."""
    blocks: dict[tuple[str, int], list[np.ndarray]] = {}
    for (dim, ptag), pid in sorted(groups.items()):
        for entity in gmsh.model.getEntitiesForPhysicalGroup(dim, ptag):
            etypes, _, enodes = gmsh.model.mesh.getElements(dim, int(entity))
            for etype, nodes in zip(etypes, enodes):
                if int(etype) not in _GMSH_TYPES:
                    raise ValueError(f"gmsh element type {etype} has no Nastran counterpart here")
                kind, perm = _GMSH_TYPES[int(etype)]
                conn = np.asarray(nodes, dtype=np.int64).reshape(-1, _nodes_per(kind))
                if perm is not None:
                    conn = conn[:, perm]
                blocks.setdefault((kind, pid), []).append(conn)
    if not blocks:
        raise ValueError("no elements in the requested physical groups")
    used = np.unique(np.concatenate([c.ravel() for cs in blocks.values() for c in cs]))
    all_tags, coords, _ = gmsh.model.mesh.getNodes()
    coords = np.asarray(coords).reshape(-1, 3)
    row_of_tag = {int(t): i for i, t in enumerate(all_tags)}
    points = np.array([coords[row_of_tag[int(t)]] for t in used])
    gmsh_to_grid = {int(t): i + 1 for i, t in enumerate(used)}
    cells, pids = [], []
    for (kind, pid), conns in sorted(blocks.items(), key=lambda kv: (kv[0][1], kv[0][0])):
        conn = np.concatenate(conns)
        cells.append((kind, np.searchsorted(used, conn)))
        pids.append(np.full(len(conn), pid, dtype=np.int64))
    return SceneMesh(points, cells, pids, gmsh_to_grid)


_NODES_PER = {"triangle": 3, "quad": 4, "tetra": 4, "hexahedron": 8, "wedge": 6, "tetra10": 10}


def _nodes_per(kind: str) -> int:
    return _NODES_PER[kind]


def write_mesh_include(mesh: SceneMesh, path: Path, provenance: str) -> None:
    """GRIDs and elements through meshio's Nastran writer, stripped of BEGIN BULK / ENDDATA."""
    m = meshio.Mesh(mesh.points, mesh.cells, cell_data={"nastran:ref": mesh.pids})
    with tempfile.TemporaryDirectory() as tmp:
        raw = Path(tmp) / "raw.bdf"
        meshio.write(raw, m, file_format="nastran", point_format="fixed-large")
        lines = raw.read_text().splitlines(keepends=True)
    body = [ln for ln in lines
            if not ln.startswith(("BEGIN BULK", "ENDDATA", "$ Nastran file written by meshio"))]
    header = (f"$ {path.name}: generated by {provenance} -- do not edit.\n"
              f"$ {len(mesh.points)} grids, {mesh.n_elements()} elements "
              f"(meshio {meshio.__version__}, gmsh {gmsh.__version__})\n")
    _write_atomically(path, header + "".join(body))


def write_cards(path: Path, provenance: str, cards: list[str], comment: str = "") -> None:
    head = f"$ {path.name}: generated by {provenance} -- do not edit.\n"
    if comment:
        head += "".join(f"$ {ln}\n" for ln in comment.splitlines())
    _write_atomically(path, head + "".join(cards))


def _write_atomically(path: Path, text: str) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_suffix(path.suffix + ".tmp")
    tmp.write_text(text)
    tmp.replace(path)


def set_shell_mcid(path: Path, mcid: int) -> None:
    """Give every CQUAD4/CTRIA3 of an include written by :func:`write_mesh_include` the material
    system ``mcid`` (field 8 of CQUAD4, field 7 of CTRIA3; meshio leaves it blank, i.e. THETA =
    0: the material x axis along each element's G1→G2 edge, which varies across a free mesh).
    With MCID the x axis of that system projected onto each element is the material x axis, so
    a PCOMP layup has one orientation over the whole component; MCID = 0 is the basic system."""
    field_of = {"CQUAD4": 8, "CTRIA3": 7}
    out = []
    for line in path.read_text().splitlines(keepends=True):
        name = line[:8].strip()
        if name in field_of:
            body = line.rstrip("\n").rstrip()
            start = 8 * (field_of[name] - 1)
            if len(body) > start or "," in body or name + "*" in line[:8]:
                raise ValueError(f"{path.name}: unexpected element line {line!r}")
            line = body.ljust(start) + f"{mcid:>8d}\n"
        out.append(line)
    _write_atomically(path, "".join(out))


def fit_large_field(mesh: SceneMesh) -> None:
    """Round the grid coordinates in place so that meshio's large-field GRID writer can print
    them: it asserts ≤ 16 characters for ``np.format_float_scientific(x, precision=11)``, which a
    negative coordinate with 12 significant digits (``-1.23456789012E-3``, 17 characters) or a
    round-off value like ``-1.2E-19`` breaks. Coordinates become 11 significant digits (a
    relative change ≤ 5e-12) and |x| < 1e-9 becomes 0 (gmsh round-off around zero)."""
    pts = mesh.points
    pts[np.abs(pts) < 1e-9] = 0.0
    mesh.points = np.array([[float(f"{x:.10e}") for x in row] for row in pts]).reshape(pts.shape)


def fix_tetra10_cards(path: Path) -> None:
    """meshio 5.3.5 writes 10-node tetrahedra as ``CTETRA_`` (its internal name for them); the
    Nastran card is ``CTETRA`` with 10 grids. Rename them in an include written by
    :func:`write_mesh_include`."""
    text = path.read_text()
    _write_atomically(path, text.replace("\nCTETRA_ ", "\nCTETRA  "))
