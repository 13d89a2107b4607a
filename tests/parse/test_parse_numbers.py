"""core/parse/numbers.py: whole numbers, ports and decimal numbers in ASCII digits only."""

from __future__ import annotations

import pytest

from panther_ops.core.parse.numbers import NumberError, ascii_int, decimal, int_in_range, port, whole

OTHER_DIGITS = ("８０８１", "\u0663", "\u096a", "8\u00b9", "1_0", " 1", "1 ", "+", "")
"""Full-width, Arabic-Indic and Devanagari digits, a superscript, '_', spaces, no digits."""


@pytest.mark.parametrize("text", OTHER_DIGITS)
def test_only_ascii_digits(text: str) -> None:
    for parse in (ascii_int, lambda t: int_in_range(t, 0, 10**6), port, lambda t: whole(t, 0),
                  decimal):
        with pytest.raises(NumberError):
            parse(text)


def test_whole_numbers_and_ports() -> None:
    assert ascii_int("0042") == 42 and ascii_int("-3", signed=True) == -3
    with pytest.raises(NumberError, match="ASCII digits"):
        ascii_int("-3")
    assert int_in_range("232", 0, 232) == 232 and int_in_range("7", 1) == 7
    with pytest.raises(NumberError, match="from 0 to 232"):
        int_in_range("233", 0, 232)
    with pytest.raises(NumberError, match="of 1 or more"):
        whole(0, 1)
    assert whole(10**9, 0) == 10**9 and whole("5", 1, 500) == 5
    assert port(22) == 22 and port("65535") == 65535
    for bad in (0, 65536, True, 22.0, "22.0", None):
        with pytest.raises(NumberError, match="1 to 65535"):
            port(bad)


def test_decimal() -> None:
    for text, value in (("53.1978", 53.1978), ("-12", -12.0), (".5", 0.5), ("5.", 5.0), ("1e-3", 0.001),
                        ("+2E2", 200.0)):
        assert decimal(text) == value
    assert decimal(3) == 3.0 and decimal(2.5, 0, 3) == 2.5
    for bad in ("nan", "inf", "-Infinity", "1e999", float("nan"), True, None, "1.2.3", "1e", "e5", "０.５"):
        with pytest.raises(NumberError):
            decimal(bad)
    with pytest.raises(NumberError, match=r"a number from -90 to 90$"):
        decimal("200", -90, 90)
    with pytest.raises(NumberError, match=r"a number of 0\.1 or more"):
        decimal(0, 0.1)
    with pytest.raises(NumberError, match="a number up to 60"):
        decimal(61, None, 60)
