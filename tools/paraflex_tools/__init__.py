"""Python helpers shared by paraflex's deck generators, benchmarks and plot scripts.

* :mod:`paraflex_tools.cards`: Nastran bulk-data cards (free, small, large field).
* :mod:`paraflex_tools.runner`: locating and running the paraflex binary.
* :mod:`paraflex_tools.results`: reading paraflex's HDF5 result files (statics, modes, FRF,
  transient, multibody and estimation results by subcase).
* :mod:`paraflex_tools.prom`: a pROM artifact evaluated at any parameter point (matrices,
  frequencies, FRFs) in numpy.
* :mod:`paraflex_tools.meshing`: gmsh → meshio → Nastran includes of the scene generators.
* :mod:`paraflex_tools.analytic`, :mod:`paraflex_tools.mitc_plate`: reference solutions used by
  more than one generator (Timoshenko beam, MITC plate).
* :mod:`paraflex_tools.prom_decks`: deck transformations of the pROM validation scripts.

Installed (editable) into the project's venv by ``make venv``: ``pip install -e tools``.
"""
from pathlib import Path

#: The checkout the package is installed from (``pip install -e tools``): decks, meshes, target.
REPO = Path(__file__).resolve().parents[2]
