"""Deck text transformations and runs shared by the pROM validation scripts (tools/prom/error_map.py,
tools/prom/angle_sweep.py, tools/bench/prom_speed.py): includes made absolute, the
non-parametric ROM deck of one parameter point (a zero-width box and one sample with its whole
local basis, the thesis's "standard, non-parametric ROM"), and the FRF of a pROM/ROM artifact at
a PVAL point.
"""
from __future__ import annotations

import re
from pathlib import Path

from paraflex_tools.results import read_frf
from paraflex_tools.runner import run_checked


def absolute_includes(text: str, base: Path) -> str:
    """`text` with every INCLUDE path made absolute, relative to `base` (the deck's directory)."""
    return re.sub(r"INCLUDE\s+'([^']+)'", lambda m: f"INCLUDE '{(base / m.group(1)).resolve()}'", text)


def frf(paraflex: str, artifact: Path, pval: str, band: tuple[float, float], lines: int, work: Path, pair: str):
    """Frequencies and H[pair, pair] of SOL 111 on `artifact` at the PVAL card `pval`: FREQ1 with
    `lines` lines over `band`, the deck and its output in `work`."""
    deck = work / f"frf_{artifact.stem}.dat"
    df = (band[1] - band[0]) / lines
    deck.write_text(f"SOL 111\nCEND\nROM = '{artifact}'\nPVAL = 1\nFREQUENCY = 1\nBEGIN BULK\n{pval}"
                    f"FREQ1,1,{max(band[0], df)!r},{df!r},{lines - 1}\nENDDATA\n")
    out = work / f"frf_{artifact.stem}.h5"
    run_checked(deck, out, paraflex)
    result = read_frf(out)
    k = result.inputs.index(pair)
    return result.frequency_hz, result.H[:, k, k]


def one_sample_whole_basis(text: str) -> str:
    """The PMOR of a ROM of one point: NSAMP = 1 and ERRTOL = 1e-14, so the size selection keeps
    the whole local basis (a reference ROM must not be truncated by it)."""
    return re.sub(r"^PMOR,(\d+),\d+,([^,\n]+),([^,\n]+)(,[^,\n]*)?", r"PMOR,\1,1,\2,\3,1.e-14", text, flags=re.M)


def rom_deck_e_rho(text: str, mid: int, e: float, rho: float) -> str:
    """The deck at (E, ρ): the MAT1 (free field, in `text`) at the point, a zero-width box and
    one sample with its whole local basis."""
    point = re.sub(rf"^(MAT1,{mid},)[^,]+(,[^,]*,[^,]+,)[^,\n]+", rf"\g<1>{e!r}\g<2>{rho!r}", text, flags=re.M)
    point = re.sub(rf"^PMPAR,(\d+),(\w+),E,{mid},[^\n]+$", rf"PMPAR,\1,\2,E,{mid},{e!r},{e!r}", point, flags=re.M)
    point = re.sub(rf"^PMPAR,(\d+),(\w+),RHO,{mid},[^\n]+$", rf"PMPAR,\1,\2,RHO,{mid},{rho!r},{rho!r}", point, flags=re.M)
    return one_sample_whole_basis(point)


def inline_material(text: str, mid: int) -> str:
    """`text` with the include that holds MAT1 `mid` inlined (so rom_deck_e_rho can change it)."""
    mat_re = rf"^MAT1,{mid},([^,]+),([^,]*),([^,]+),([^,\n]+)"
    if re.search(mat_re, text, flags=re.M) is None:
        for inc in re.findall(r"INCLUDE '([^']+)'", text):
            body = Path(inc).read_text()
            if re.search(mat_re, body, flags=re.M):
                return text.replace(f"INCLUDE '{inc}'", absolute_includes(body, Path(inc).parent))
    return text


PMPAR_THETA_RE = r"^PMPAR,(\d+),(\w+),THETA,(\d+),([^,\n]+),([^,\n]+)$"


def theta_box(text: str, deck: Path):
    """(name, PCOMP id, low, high) of the deck's one PMPAR of kind THETA."""
    m = re.search(PMPAR_THETA_RE, text, flags=re.M)
    if m is None:
        raise SystemExit(f"{deck}: needs one PMPAR of kind THETA")
    return m.group(2), int(m.group(3)), float(m.group(4)), float(m.group(5))


def rom_deck_theta(text: str, pid: int, theta: float) -> str:
    """The deck at Θ: PCOMP ply angles ±Θ, zero-width THETA box, one sample with its whole
    local basis."""
    lines = text.splitlines()
    out, in_pcomp = [], False
    for line in lines:
        if line.startswith("PCOMP,"):
            in_pcomp = int(line.split(",")[1]) == pid
        elif not line.startswith(","):
            in_pcomp = False
        if in_pcomp and line.startswith(","):
            f = line.split(",")
            for k in range(3, len(f), 4):  # ply fields: MID T THETA SOUT, from field 1
                if f[k].strip():
                    f[k] = f"{'-' if f[k].strip().startswith('-') else ''}{theta!r}"
            line = ",".join(f)
        out.append(line)
    text = "\n".join(out) + "\n"
    text = re.sub(PMPAR_THETA_RE, lambda m: f"PMPAR,{m.group(1)},{m.group(2)},THETA,{m.group(3)},{theta!r},{theta!r}", text, flags=re.M)
    return one_sample_whole_basis(text)
