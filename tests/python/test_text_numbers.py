"""finken.text_numbers (the number grammar of every reader) and finken.cli_types (numeric options built on it).

Exact tests: each string is either read to the stated value or refused with the stated message. The refused
ones are what Python's float() and int() accept although no writer of the toolkit produces them (issue 28:
`1_5` read as 15, Arabic-Indic digits, vehicle 1e300 and -1).
"""
import argparse
import math

import numpy as np
import pytest

from finken.cli_types import integer, real
from finken.text_numbers import (MAX_ID, ColumnError, parse_column, parse_finite, parse_id, parse_integer,
                                 parse_number)

FLOAT_ACCEPTS_BUT_NOT_A_NUMBER = ["1_5", "\u0661\u0665", "\uff11\uff15", "\u0967", "1\u00a0", "0x10", "1e", ".",
                                  "-", "1.2.3", "nanx", "++1", "1 2"]


@pytest.mark.parametrize("text, value", [
    ("0", 0.0), ("1.5", 1.5), (" -2.25\t", -2.25), ("+.5", 0.5), ("3.", 3.0), ("1e-05", 1e-05), ("2E+3", 2000.0),
    ("1e999", math.inf), ("-inf", -math.inf), ("Infinity", math.inf),
])
def test_ascii_decimal_numbers_are_read(text, value):
    assert parse_number(text) == value


@pytest.mark.parametrize("text", FLOAT_ACCEPTS_BUT_NOT_A_NUMBER)
def test_what_float_also_accepts_is_refused(text):
    with pytest.raises(ValueError, match="is not a number"):
        parse_number(text)


def test_nan_words_read_as_nan_and_finite_refuses_them():
    assert all(math.isnan(parse_number(t)) for t in ("nan", "NaN", "-nan", "NAN"))
    assert parse_finite("2.5") == 2.5
    for text in ("nan", "inf", "-Infinity", "1_5", "x"):
        with pytest.raises(ValueError, match=f"'{text}' is not a finite number"):
            parse_finite(text)


@pytest.mark.parametrize("text, value", [("0", 0), ("7", 7), ("7.0", 7), ("7e0", 7), (str(MAX_ID), MAX_ID)])
def test_ids(text, value):
    assert parse_id(text) == value


@pytest.mark.parametrize("text", ["-1", "-7", "1e300", "1.5", str(MAX_ID + 1), "nan", "inf", "1_5", "\u0661"])
def test_not_ids(text):
    with pytest.raises(ValueError, match=f"is not an integer from 0 to {MAX_ID}"):
        parse_id(text)


def test_integers_decimal_and_hex():
    assert parse_integer("-12") == -12 and parse_integer(" 010 ") == 10
    assert parse_integer("0x300", hex_ok=True) == 0x300 and parse_integer("0X7ff", hex_ok=True) == 0x7FF
    for text, hex_ok in (("0x300", False), ("1_0", False), ("0x3_00", True), ("\uff16\uff14", False),
                         ("1.0", False), ("", False)):
        with pytest.raises(ValueError, match="is not an integer"):
            parse_integer(text, hex_ok)


def test_column_empty_fields_are_nan_and_the_first_bad_field_is_named():
    values = parse_column(["1.5", "", "nan", "-2e1", "inf"])
    np.testing.assert_array_equal(values, [1.5, np.nan, np.nan, -20.0, np.inf])
    assert parse_column([]).shape == (0,)
    for texts, index in ((["1", "2", "1_5", "x"], 2), (["\u0661", "1"], 0), (["1", "2\n3"], 1)):
        with pytest.raises(ColumnError) as err:
            parse_column(texts)
        assert err.value.index == index and err.value.reason == f"'{texts[index]}' is not a number"


def test_column_agrees_with_the_single_value_grammar():
    texts = ["1", "-0.5", "1_5", ".5", "1e", "NaN", "\u0665", "+3.", "0x1", "inf", "1.2.3", "e5"]
    for text in texts:
        try:
            expected = parse_number(text)
        except ValueError:
            with pytest.raises(ColumnError):
                parse_column([text])
        else:
            np.testing.assert_array_equal(parse_column([text]), [expected])


@pytest.mark.parametrize("kind, text, value", [
    (integer(0, 2**64 - 1), "18446744073709551615", 2**64 - 1),
    (integer(1), "3", 3),
    (integer(0, 65535, hex_ok=True), "0x300", 0x300),
    (real(), "-1.5", -1.5),
    (real(0, inf_ok=True), "inf", math.inf),
    (real(0, inf_ok=True), "0", 0.0),
    (real(0, low_open=True), "1e-3", 0.001),
])
def test_option_types_accept(kind, text, value):
    assert kind(text) == value


@pytest.mark.parametrize("kind, text, message", [
    (integer(0, 2**64 - 1), "-1", "'-1' is not an integer from 0 to 18446744073709551615"),
    (integer(0, 2**64 - 1), "18446744073709551616", "is not an integer from 0 to"),
    (integer(1), "0", "'0' is not an integer >= 1"),
    (integer(1), "2.0", "is not an integer >= 1"),
    (integer(0, 65535, hex_ok=True), "0x3_00", "is not an integer from 0 to 65535"),
    (real(), "nan", "'nan' is not a finite number"),
    (real(), "inf", "'inf' is not a finite number"),
    (real(), "1_0", "'1_0' is not a finite number"),
    (real(0, inf_ok=True), "-1", "'-1' is not a number >= 0"),
    (real(0, inf_ok=True), "nan", "'nan' is not a number >= 0"),
    (real(0, low_open=True), "0", "'0' is not a finite number > 0"),
])
def test_option_types_refuse(kind, text, message):
    with pytest.raises(argparse.ArgumentTypeError, match=message):
        kind(text)
