"""Nastran bulk-data cards as text: free field, small field (8 columns), large field (16
columns), or the narrowest fixed format that keeps every real exact.

One function, :func:`card`, writes every form. A field is ``None`` (blank), an ``int``, a
``float`` or a ``str`` (written as given). Every card ends with a newline.

* ``free``: ``NAME,f2,...,f9`` and then ``+,f10,...,f17`` continuation lines (8 data fields a
  line); reals are the shortest text that reads back as the same double, always with a decimal
  point and an upper-case exponent (``0.1``, ``1.5E-07``, ``3.0``).
* ``small`` / ``large``: the fixed formats of pyNastran's field writers (reals such as ``1.-3``,
  Nastran's exponent without ``E``; large-field cards have the ``*`` continuation).
* ``fit``: ``small`` when the 8-column text of every real reads back as exactly the same double,
  else ``large``.

:func:`free_cards` writes many cards of one kind at once (a mesh's GRIDs, its elements): the
same text as :func:`card` in free form, without the per-card overhead; :func:`small_cards`
writes one-line small-field cards from a %-format of their 8-column fields, for decks of 10⁶
cards in reader benchmarks (about 6 s for a million GRIDs, where :func:`card` takes minutes).
"""
from __future__ import annotations

from pyNastran.bdf.field_writer_16 import print_card_16
from pyNastran.bdf.field_writer_8 import print_card_8, print_float_8

FORMS = ("free", "small", "large", "fit")
FIELDS_PER_LINE = 8


def card(name: str, *fields, form: str = "free") -> str:
    """The card ``name`` with data fields ``fields`` in ``form`` (one of :data:`FORMS`)."""
    if form == "free":
        return _free_card(name, fields)
    if form == "small":
        return print_card_8([name, *fields])
    if form == "large":
        return print_card_16([name, *fields])
    if form == "fit":
        narrow = all(fits_small_field(v) for v in fields if isinstance(v, float))
        return card(name, *fields, form="small" if narrow else "large")
    raise ValueError(f"unknown card form {form!r}; expected one of {', '.join(FORMS)}")


def free_cards(name: str, rows) -> str:
    """``card(name, *row)`` in free form for every row of ``rows`` (rows of ints, floats,
    ``None`` and strings), as one string."""
    return "".join(_free_card(name, row) for row in rows)


def small_cards(name: str, fields: str, rows) -> str:
    """One small-field card ``name`` per row: ``fields`` is the %-format of the data fields
    (8 columns each, e.g. ``"%8d        %8.5f"``), applied to each row (a tuple)."""
    line = f"{name:<8s}{fields}\n"
    return "".join([line % tuple(row) for row in rows])


def free_field(value) -> str:
    """One free-field entry: blank for ``None``, shortest round-trip text for a real."""
    if value is None:
        return ""
    if isinstance(value, float):
        return free_real(value)
    return str(value)


def free_real(x: float) -> str:
    """The shortest text that reads back as ``x`` (``repr``), with a decimal point and ``E``."""
    text = repr(float(x))
    if "e" not in text:
        return text
    mantissa, exponent = text.split("e")
    if "." not in mantissa:
        mantissa += "."
    return mantissa + "E" + exponent


def fits_small_field(x: float) -> bool:
    """True when the 8-column text of ``x`` reads back as exactly ``x``."""
    return read_nastran_real(print_float_8(x)) == x


def read_nastran_real(text: str) -> float:
    """A real as Nastran reads it, including the exponent without ``E`` (``1.5-3`` = 1.5e-3)."""
    text = text.strip()
    for sign in "+-":
        k = text.rfind(sign)
        if k > 0 and text[k - 1] not in "eE":
            return float(text[:k] + "e" + text[k:])
    return float(text)


def _free_card(name: str, fields) -> str:
    texts = [free_field(v) for v in fields]
    lines = [",".join([name, *texts[:FIELDS_PER_LINE]])]
    for start in range(FIELDS_PER_LINE, len(texts), FIELDS_PER_LINE):
        lines.append(",".join(["+", *texts[start:start + FIELDS_PER_LINE]]))
    return "\n".join(lines) + "\n"
