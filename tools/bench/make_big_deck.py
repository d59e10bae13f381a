"""Write a large small-field CQUAD4 shell deck for reader benchmarks.

Usage (from the repository root):

    .venv/bin/python tools/bench/make_big_deck.py [N_GRIDS] [OUT]

N_GRIDS defaults to 1,000,000, OUT to ``bench_<N_GRIDS>.bdf``.  The deck holds
exactly N_GRIDS GRID cards: an nx-by-ny flat plate with nx = floor(sqrt(N))
(plus a partial last row when N is not a multiple of nx), one CQUAD4 per cell
between full rows and over the partial row, PSHELL + MAT1, SPC1 on the first
row, EIGRL, and a SOL 103 executive / case control section.  Every card is in
8-character fields (numpy index arithmetic + ``paraflex_tools.cards.small_cards`` in chunks; about
6 s for 1M grids on the 2-core dev machine).
Output is deterministic.  Generated decks are benchmark inputs: do not commit
them (1M grids is about 106 MB).
"""
from __future__ import annotations

import math
import sys
import time
from pathlib import Path

import numpy as np

from paraflex_tools.cards import small_cards

HEADER = """\
$ paraflex reader benchmark deck: {n} grids, {ne} CQUAD4
$ written by tools/bench/make_big_deck.py
SOL 103
CEND
TITLE = paraflex benchmark plate {n} grids
METHOD = 1
SPC = 1
BEGIN BULK
PARAM   POST    -1
EIGRL          1                      10
MAT1           1  7.1+10             .33   2700.
PSHELL         1       1    .002       1               1
SPC1           1  123456       1    THRU{nx:>8d}
"""


def write_deck(n_grids: int, out: Path) -> tuple[int, int]:
    if n_grids < 4:
        raise ValueError("need at least 4 grids")
    nx = math.isqrt(n_grids)
    ny_full, rest = divmod(n_grids, nx)
    ids = np.arange(1, n_grids + 1, dtype=np.int64)
    i = (ids - 1) % nx
    j = (ids - 1) // nx
    dx = 1.0 / nx
    x = i * dx
    y = j * dx
    # cells between full rows j and j+1
    ci, cj = np.meshgrid(np.arange(nx - 1), np.arange(ny_full - 1), indexing="xy")
    ci, cj = ci.ravel(), cj.ravel()
    n1 = cj * nx + ci + 1
    quads = [np.column_stack([n1, n1 + 1, n1 + nx + 1, n1 + nx])]
    if rest >= 2:  # partial last row: cells over its first rest-1 gaps
        pi = np.arange(rest - 1)
        p1 = (ny_full - 1) * nx + pi + 1
        quads.append(np.column_stack([p1, p1 + 1, p1 + nx + 1, p1 + nx]))
    conn = np.concatenate(quads)
    ne = len(conn)
    eids = np.arange(1, ne + 1, dtype=np.int64)

    with open(out, "w", newline="\n") as f:
        f.write(HEADER.format(n=n_grids, ne=ne, nx=min(nx, n_grids)))
        # GRID: id, blank CP, x, y, z in 8-wide fixed columns
        chunk = 200_000
        ids_l, x_l, y_l = ids.tolist(), x.tolist(), y.tolist()
        for start in range(0, n_grids, chunk):
            stop = start + chunk
            rows = zip(ids_l[start:stop], x_l[start:stop], y_l[start:stop])
            f.write(small_cards("GRID", "%8d        %8.5f%8.5f      0.", rows))
        # CQUAD4: eid, pid 1, 4 grids
        quad = np.column_stack([eids, conn]).tolist()
        for start in range(0, ne, chunk):
            f.write(small_cards("CQUAD4", "%8d       1%8d%8d%8d%8d", quad[start:start + chunk]))
        f.write("ENDDATA\n")
    return n_grids, ne


def main(argv: list[str]) -> int:
    n_grids = int(argv[1].replace("_", "")) if len(argv) > 1 else 1_000_000
    out = Path(argv[2]) if len(argv) > 2 else Path(f"bench_{n_grids}.bdf")
    t0 = time.perf_counter()
    n, ne = write_deck(n_grids, out)
    dt = time.perf_counter() - t0
    size = out.stat().st_size / 1e6
    print(f"wrote {out}: {n} grids, {ne} CQUAD4, {size:.1f} MB in {dt:.2f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
