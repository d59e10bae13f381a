"""The four-bar of ``decks/fourbar/fmb`` in a work directory outside the repository: its link
decks copied with their mesh includes made absolute, their pROM artifacts built, and the drive
table beside them, so that the mechanism decks of that folder run there unchanged.
"""
from __future__ import annotations

import os
import shutil
from pathlib import Path

from paraflex_tools import REPO
from paraflex_tools.runner import run_checked

DECKS = REPO / "decks" / "fourbar" / "fmb"


def deck_text(name: str) -> str:
    """A deck of the four-bar folder with its ``../../../meshes/`` includes made absolute."""
    return (DECKS / name).read_text().replace("'../../../meshes/", f"'{REPO / 'meshes'}/")


def prepare_links(work: Path, links: dict[str, str], binary: str | os.PathLike) -> None:
    """Build each link artifact of ``links`` (deck name -> artifact name) in ``work`` and copy
    the drive table there."""
    for deck, artifact in links.items():
        (work / deck).write_text(deck_text(deck))
        run_checked(work / deck, work / artifact, binary)
    shutil.copy(DECKS / "drive.csv", work / "drive.csv")
