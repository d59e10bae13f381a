"""Time pyNastran reading a deck: the baseline for the Rust deck reader.

Usage (from the repository root):

    .venv/bin/python tools/bench/read_pynastran.py DECK [--no-xref]

Prints, for ``BDF().read_bdf(DECK, xref=False)`` followed by
``model.cross_reference()``: wall time of each phase and of both, the number
of grids/elements read, and the peak resident set size of the process
(``resource.getrusage(RUSAGE_SELF).ru_maxrss``, which Linux reports in KiB;
the figure includes the Python interpreter and the imported modules, about
100 MB for pyNastran + numpy, measured just before reading).
"""
from __future__ import annotations

import resource
import sys
import time

from pyNastran.bdf.bdf import BDF


def peak_rss_mb() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def main(argv: list[str]) -> int:
    if len(argv) < 2:
        print(__doc__, file=sys.stderr)
        return 2
    deck = argv[1]
    xref = "--no-xref" not in argv[2:]
    base_rss = peak_rss_mb()

    model = BDF(debug=None)
    model.log.level = "error"
    t0 = time.perf_counter()
    model.read_bdf(deck, xref=False, punch=None)
    t1 = time.perf_counter()
    if xref:
        model.cross_reference()
    t2 = time.perf_counter()

    print(f"deck            {deck}")
    print(f"grids           {len(model.nodes)}")
    print(f"elements        {len(model.elements)}")
    print(f"read_bdf        {t1 - t0:8.2f} s (xref=False)")
    if xref:
        print(f"cross_reference {t2 - t1:8.2f} s")
    print(f"total           {t2 - t0:8.2f} s")
    print(f"peak RSS        {peak_rss_mb():8.1f} MB (before reading: {base_rss:.1f} MB)")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
