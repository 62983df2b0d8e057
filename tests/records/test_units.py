"""Units of acceleration: spellings, factors, and errors that list what is accepted."""

from __future__ import annotations

import pytest

from floorslide.errors import UnitsError
from floorslide.records.units import FACTORS, canonical_units, to_si_factor


@pytest.mark.parametrize(
    ("spelling", "canonical"),
    [
        ("g", "g"),
        ("G", "g"),
        (" g's ", "g"),
        ("gal", "gal"),
        ("Gal", "gal"),
        ("cm/s**2", "gal"),
        ("cm/s^2", "gal"),
        ("cm/s2", "gal"),
        ("cm/sec2", "gal"),
        ("cm/sec/sec", "gal"),
        ("CM/S/S", "gal"),
        ("cm/s²", "gal"),
        ("cm s-2", "gal"),
        ("m/s**2", "m/s**2"),
        ("m/s^2", "m/s**2"),
        ("m/s2", "m/s**2"),
        ("m/sec/sec", "m/s**2"),
        ("m·s⁻²", "m/s**2"),
        ("mps2", "m/s**2"),
        ("mm/s**2", "mm/s**2"),
        ("mm/s^2", "mm/s**2"),
        ("mg", "mg"),
        ("in/s**2", "in/s**2"),
        ("in/sec/sec", "in/s**2"),
        ("nm/s**2", "nm/s**2"),
    ],
)
def test_spellings(spelling, canonical):
    assert canonical_units(spelling) == canonical


def test_factors():
    assert to_si_factor("g") == 9.80665
    assert to_si_factor("gal") == 0.01
    assert to_si_factor("m/s**2") == 1.0
    assert to_si_factor("mm/s**2") == 0.001
    assert to_si_factor("mg") == pytest.approx(9.80665e-3, rel=1e-15)
    assert to_si_factor("in/s**2") == 0.0254
    assert set(FACTORS) >= {"g", "gal", "m/s**2", "mm/s**2"}


@pytest.mark.parametrize("bad", ["furlongs", "", "m/s", "cm", "g/s", "kg", "counts"])
def test_unknown_units_are_an_error_listing_the_accepted_ones(bad):
    with pytest.raises(UnitsError, match="unknown units") as info:
        canonical_units(bad)
    assert "m/s**2" in str(info.value) and "gal" in str(info.value)


def test_non_string_units():
    with pytest.raises(UnitsError):
        canonical_units(9.81)  # type: ignore[arg-type]
