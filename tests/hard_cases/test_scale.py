"""Hard cases across the chain: flexible undamped isolation, 50 storeys, a million samples."""

from __future__ import annotations

import tracemalloc

import numpy as np
import pytest

from floorslide.building.model import IsolatedBuilding, ShearBuilding
from floorslide.contents.sliding import slide
from floorslide.spectra import response_spectrum
from tests.spectra.test_spectra import oscillator_reference


def reference_slide(acc, dt, mu, **kw):
    return slide(acc, dt, mu, method="solve_ivp", rtol=1e-12, max_step=dt / 16, **kw)


def test_slide_on_flexible_undamped_isolation(elcentro):
    acc, dt = elcentro
    acc = acc[:700]
    iso = IsolatedBuilding(ShearBuilding.from_period(2, 0.3, 0.02), 1.0, 6.0, 0.0)
    res = slide(acc, dt, [0.01, 0.02], building=iso, floor=2)
    ref = reference_slide(acc, dt, [0.01, 0.02], building=iso, floor=2)
    assert res.peak_slide[0] > 1e-4
    np.testing.assert_allclose(res.peak_slide, ref.peak_slide, rtol=1e-8, atol=1e-12)


def test_slide_and_frs_on_a_fifty_storey_roof(elcentro):
    acc, dt = elcentro
    acc = acc[:250]
    b = ShearBuilding.from_period(50, 5.0, 0.05, profile="shear")
    res = slide(acc, dt, [0.005], building=b, floor=50)
    ref = reference_slide(acc, dt, [0.005], building=b, floor=50)
    assert res.peak_slide[0] > 0
    np.testing.assert_allclose(res.peak_slide, ref.peak_slide, rtol=1e-7)
    sp = response_spectrum(acc, dt, [0.5], 0.05, building=b, floor=50)
    A, B = b.state_matrices()
    Ca, _, _ = b.output_matrices([50])
    ref_sp = oscillator_reference(A, B[:, 0], Ca[0], 0.0, acc, dt, 0.5, 0.05)
    np.testing.assert_allclose([sp.sd[0, 0], sp.sv[0, 0], sp.sa[0, 0]], ref_sp, rtol=1e-8)


@pytest.mark.parametrize("where", ["ground", "isolated roof"])
def test_million_samples_through_building_sliding_and_spectra(where):
    """10⁶ samples (dt = 1 ms, 2 Hz sine): the chain runs in memory O(1) beside the record, and
    the steady response 900 s later is the one after the transient (no drift)."""
    n, dt = 1_000_000, 0.001
    acc = 2.0 * np.sin(2 * np.pi * 2.0 * np.arange(n) * dt)
    kw = {}
    if where != "ground":
        kw = dict(
            building=IsolatedBuilding(ShearBuilding.from_period(2, 0.3, 0.05), 1.0, 2.5, 0.1),
            floor=2,
        )
    slide(acc[:200], dt, 0.1, **kw)
    response_spectrum(acc[:200], dt, [0.3], 0.05, **kw)
    tracemalloc.start()
    res = slide(acc, dt, [0.05, 0.1], **kw)
    sp = response_spectrum(acc, dt, [0.1, 0.5, 2.0], 0.05, **kw)
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    assert peak < 2e6  # the record alone is 8 MB
    assert np.all(np.isfinite(res.peak_slide)) and np.all(np.isfinite(sp.psa))
    short = slide(acc[:200_001], dt, [0.05, 0.1], **kw)
    # steady state: the peak over 200 s equals the peak over 1000 s (no drift, no accumulation)
    np.testing.assert_allclose(
        sp.sd, response_spectrum(acc[:200_001], dt, [0.1, 0.5, 2.0], 0.05, **kw).sd, rtol=1e-9
    )
    assert np.all(np.isfinite(short.peak_slide))
