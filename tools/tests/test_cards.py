"""The Nastran card writer: field forms, real formatting and continuations."""
import pytest

from paraflex_tools.cards import (
    card,
    fits_small_field,
    free_cards,
    free_real,
    read_nastran_real,
    small_cards,
)


def test_free_reals_are_shortest_round_trip_with_point_and_upper_exponent():
    assert free_real(0.1) == "0.1"
    assert free_real(3.0) == "3.0"
    assert free_real(1.5e-07) == "1.5E-07"
    assert free_real(2e20) == "2E+20".replace("E", ".E")  # repr '2e+20' gains a decimal point
    assert float(free_real(1 / 3)) == 1 / 3


def test_free_card_blanks_ints_strings_and_continuations():
    assert card("GRID", 1, None, 0.5, 0, 2.0) == "GRID,1,,0.5,0,2.0\n"
    assert card("SPC1", 1, "123", *range(1, 11)) == "SPC1,1,123,1,2,3,4,5,6\n+,7,8,9,10\n"
    sixteen = card("X", *range(1, 17))
    assert sixteen == "X,1,2,3,4,5,6,7,8\n+,9,10,11,12,13,14,15,16\n"
    assert card("X", *range(1, 18)).endswith("\n+,17\n")


def test_small_field_uses_nastran_short_exponent_and_8_columns():
    text = card("GRID", 1, None, 0.001, -1.5e-7, 1.0, form="small")
    assert text == "GRID           1            .001  -1.5-7      1.\n"
    assert all(len(line) <= 72 for line in text.splitlines())


def test_small_field_continuation_after_eight_data_fields():
    text = card("SPC1", 1, "123", *range(1, 10), form="small")
    assert text == ("SPC1           1     123       1       2       3       4       5       6\n"
                    "               7       8       9\n")


def test_large_field_has_star_name_and_continuation():
    text = card("GRID", 1, None, 0.1234567890123, 2.0, 3.0, form="large")
    assert text == ("GRID*                  1                  .1234567890123              2.\n"
                    "*                     3.\n")


def test_fit_is_small_only_when_every_real_is_exact_in_8_columns():
    assert card("GRID", 7, None, 0.25, 1.5e-3, 0.0, form="fit") == card("GRID", 7, None, 0.25, 1.5e-3, 0.0, form="small")
    precise = card("GRID", 7, None, 0.123456789, 0.0, 0.0, form="fit")
    assert precise.startswith("GRID*") and precise == card("GRID", 7, None, 0.123456789, 0.0, 0.0, form="large")
    # ints and strings never force the large field
    assert card("ASET1", "123", 12345678, form="fit").startswith("ASET1   ")


def test_nastran_reals_read_back():
    assert read_nastran_real("1.-3") == 1e-3
    assert read_nastran_real(" -1.5+7 ") == -1.5e7
    assert read_nastran_real("2.5E-3") == 2.5e-3
    assert read_nastran_real("-4.") == -4.0
    assert fits_small_field(0.125) and fits_small_field(-1.5e-7)
    assert fits_small_field(0.1234567) and not fits_small_field(0.123456789)


def test_unknown_form_is_refused():
    with pytest.raises(ValueError, match="unknown card form"):
        card("GRID", 1, form="wide")


def test_free_cards_is_card_per_row():
    rows = [(1, None, 0.1, 2.0, 1e-7), (2, None, 0.3, 4.0, 0.0, 5, 6, 7, 8, 9)]
    assert free_cards("GRID", rows) == "".join(card("GRID", *r) for r in rows)


def test_small_cards_puts_the_name_in_the_first_eight_columns():
    text = small_cards("GRID", "%8d        %8.5f%8.5f      0.", [(1, 0.5, 0.25), (12, 1.0, 0.0)])
    assert text.splitlines() == [
        "GRID           1         0.50000 0.25000      0.",
        "GRID          12         1.00000 0.00000      0.",
    ]
    assert all(len(line) == 48 for line in text.splitlines())
