"""One reading of a number written as text (floorslide.text_numbers): no underscores, counts
in any whole-number spelling."""

from __future__ import annotations

import pytest

from floorslide.text_numbers import UNDERSCORE_HINT, is_count, parse_count, parse_number


@pytest.mark.parametrize("text", ["0_05", "1_000", "-1_0.5", "1e1_0"])
def test_underscores_are_refused(text):
    """Python's float reads '0_05' as 5.0 and '1_000' as 1000."""
    with pytest.raises(ValueError, match=UNDERSCORE_HINT):
        parse_number(text)
    assert not is_count(text)


@pytest.mark.parametrize(
    ("text", "count"),
    [("2000", 2000), ("2000.", 2000), ("2000.0", 2000), ("2.0E+03", 2000), (" +7 ", 7)],
)
def test_counts_in_any_whole_number_spelling(text, count):
    assert parse_count(text) == count and is_count(text)


@pytest.mark.parametrize("text", ["2000.5", "nan", "inf", "-inf", "1e400", "", "two"])
def test_counts_that_are_not_whole_numbers(text):
    with pytest.raises(ValueError):
        parse_count(text)
    assert not is_count(text)
