#!/usr/bin/env bash
# Reading speed: paraflex check vs pyNastran read_bdf + cross_reference on a generated deck
# with N grids (default 1,000,000). Prints wall time and peak memory of both. Not a test.
set -euo pipefail
cd "$(dirname "$0")/../.."
N=${1:-1000000}
DECK=${BENCH_DIR:-/tmp}/paraflex_big_${N}.bdf
[ -f "$DECK" ] || .venv/bin/python tools/bench/make_big_deck.py "$N" "$DECK"
echo "deck: $DECK ($(du -h "$DECK" | cut -f1))"
echo "== paraflex check (read + validate + mass properties)"
/usr/bin/time -f "paraflex: %e s wall, %M kB peak RSS" "${CARGO_TARGET_DIR:-target}/release/paraflex" check "$DECK" > /dev/null
echo "== pyNastran read_bdf + cross_reference"
.venv/bin/python tools/bench/read_pynastran.py "$DECK"
