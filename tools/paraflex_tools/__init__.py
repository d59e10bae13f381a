"""Python helpers shared by paraflex's deck generators, benchmarks and plot scripts.

* :mod:`paraflex_tools.cards`: Nastran bulk-data cards (free, small, large field).
* :mod:`paraflex_tools.runner`: locating and running the paraflex binary.
* :mod:`paraflex_tools.results`: reading paraflex's HDF5 result files.

Installed (editable) into the project's venv by ``make venv``: ``pip install -e tools``.
"""
from pathlib import Path

#: The checkout the package is installed from (``pip install -e tools``): decks, meshes, target.
REPO = Path(__file__).resolve().parents[2]
