"""Hard cases of rocking blocks (issue 15): impact cascades that must end, the uplift threshold
hit exactly, restitution 1 and 0, very slender and stocky blocks, a million samples."""

from __future__ import annotations

import tracemalloc

import numpy as np
import pytest

import floorslide as fs
from floorslide.constants import G
from tests.conftest import load_slammer

B, H = 0.25, 1.2
ALPHA = np.arctan(B / H)
P = np.sqrt(3 * G / (4 * 0.5 * np.hypot(B, H)))


def quarter(theta: float) -> float:
    """Linearised time from rest at θ to the impact (a quarter of the free period),
    ``arccosh(α/(α − θ))/p`` written without cancellation for small θ:
    ``arccosh(1 + x) = log1p(x + √(x(x + 2)))`` with ``x = θ/(α − θ)``."""
    x = theta / (ALPHA - theta)
    return np.log1p(x + np.sqrt(x * (x + 2.0))) / P


def next_peak(theta: float, rr: float) -> float:
    """The next extreme after an impact: ``α² − (α − θ')² = r²(α² − (α − θ)²)``, solved as
    ``θ' = r²E/(α + √(α² − r²E))`` with ``E = θ(2α − θ)`` (no cancellation)."""
    e = rr**2 * theta * (2 * ALPHA - theta)
    return e / (ALPHA + np.sqrt(ALPHA**2 - e))


@pytest.mark.parametrize("rr", [0.5, 0.9])
def test_impact_cascade_ends_in_rest_after_the_geometric_series(rr):
    """Free rocking from θ0 with r < 1: infinitely many impacts in finite time in theory; the
    solver must end the cascade (no hang), at rest, having rocked for the sum of the half
    cycles: ``T/4(θ0) + Σ_k 2·T/4(θ_k)`` with ``α² − (α − θ_{k+1})² = r²(α² − (α − θ_k)²)``."""
    theta0 = 0.3 * ALPHA
    total, th = quarter(theta0), theta0
    while th > 1e-40 * ALPHA:
        th = next_peak(th, rr)
        total += 2 * quarter(th)
    r = fs.rock(np.zeros(2001), 0.005, B, H, restitution=rr, initial_angle=theta0, histories=True)
    assert r.rocking_time[0] == pytest.approx(total, rel=1e-9)
    assert r.theta[0, -1] == 0.0
    assert 10 < r.impacts[0] < 10000
    assert r.mode == ("rock",)


def test_restitution_zero_stops_at_the_first_impact():
    theta0 = 0.6 * ALPHA
    r = fs.rock(np.zeros(1001), 0.005, B, H, restitution=0.0, initial_angle=theta0)
    assert r.impacts[0] == 1
    assert r.rocking_time[0] == pytest.approx(quarter(theta0), rel=1e-12)


def test_record_exactly_at_the_uplift_threshold_does_not_uplift():
    """A floor acceleration that reaches ``g·B/H = g tan α`` exactly (at a sample, and on a
    plateau) without exceeding it leaves the block at rest; a hair above, it uplifts."""
    level = G * B / H
    acc = np.concatenate(
        [np.linspace(0, -level, 51), np.full(50, -level), np.linspace(-level, 0, 51)]
    )
    r = fs.rock(acc, 0.01, B, H)
    assert r.mode == ("rest",) and r.uplifts[0] == 0
    r = fs.rock(np.nextafter(acc, -np.inf) * (acc != 0), 0.01, B, H)
    assert r.uplifts[0] == 1 and r.mode in (("rock",), ("overturn",))


@pytest.mark.parametrize("width,height", [(0.05, 1.0), (0.684, 1.0)])  # α ≈ 0.05 and 0.6
@pytest.mark.parametrize("method", ["exact", "nonlinear"])
def test_very_slender_and_stocky_blocks_on_real_records(width, height, method):
    acc, dt = load_slammer("Kobe_1995_KAK-000.txt")
    for scale in (1.0, 3.0):
        r = fs.rock(acc * scale, dt, width, height, method=method, histories=True)
        assert np.isfinite(r.peak_ratio).all() and 0.0 <= r.peak_ratio[0] <= 1.0
        finite = r.theta[0][np.isfinite(r.theta[0])]
        assert np.all(np.abs(finite) <= r.alpha[0] * (1 + 1e-12))
    # the slender block uplifts and rocks under Kobe KAK (PGA 0.25 g); the stocky one does not
    # (0.25 g < g tan 0.6)
    r = fs.rock(acc, dt, width, height, method=method)
    assert bool(r.uplifts[0] > 0) == (width < 0.1)


def test_a_million_samples_in_bounded_memory():
    """10⁶ samples: twenty identical 100-s bursts, each a 1-s sine at 1.05 × the uplift level
    then rest. Memory O(1) beyond the record (no history); every burst rocks the block and lets
    it come to rest again exactly as the first does (no drift over 2,000 s)."""
    dt = 0.002
    t = np.arange(50_000) * dt
    burst = np.where(t < 1.0, 1.05 * G * B / H * np.sin(2 * np.pi * 1.3 * t), 0.0)
    acc = np.tile(burst, 20)
    assert acc.size == 1_000_000
    tracemalloc.start()
    r = fs.rock(acc, dt, B, H)
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    assert peak < 5e6
    one = fs.rock(burst, dt, B, H)
    assert one.uplifts[0] == 1 and one.impacts[0] > 100 and one.mode == ("rock",)
    assert r.uplifts[0] == 20 and r.impacts[0] == 20 * one.impacts[0]
    assert r.peak_ratio[0] == one.peak_ratio[0]
    assert r.rocking_time[0] == pytest.approx(20 * one.rocking_time[0], rel=1e-12)
