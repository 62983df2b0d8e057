"""Response and RotD spectra on a poly motion (docs/design.md §16): on the segments of the ground
pair and of a linear building's floors, aligned with the record or cut at arbitrary points, they
are fs.response_spectrum and fs.rotd_spectrum (independent exact recurrences) to rounding."""

from __future__ import annotations

import numpy as np
import pytest

import floorslide as fs
from floorslide.building.poly_segments import GroundPolyMotion, LinearPolyMotion
from floorslide.errors import ModelError
from floorslide.spectra.poly_segments import rotd_on_poly, spectrum_on_poly
from tests.conftest import ROOT
from tests.poly_motions import Counted, Harmonic, OneSegment, Recut

T = [0.0, 0.02, 0.05, 0.1, 0.2, 0.5, 1.0, 2.0, 5.0]
Z = [0.02, 0.05]


@pytest.fixture(scope="module")
def sylmar():
    """Northridge 1994, Sylmar (RSN 1084), its first 1200 samples (6 s, both PGAs in them)."""
    (p,) = fs.read_pairs(ROOT / "data" / "records" / "pairs" / "index.csv", where={"rsn": "1084"})
    return p.h1[:1200].copy(), p.h2[:1200].copy(), p.dt


def _rel(x, y) -> float:
    """Largest elementwise relative difference."""
    x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
    return float(np.max(np.abs(x - y) / np.abs(y)))


def _building(kind):
    if kind == "pair":
        return fs.BuildingPair(fs.ShearBuilding.from_period(2, 0.3),
                               fs.ShearBuilding.from_period(2, 0.5))  # fmt: skip
    return None if kind == "ground" else fs.ShearBuilding.from_period(2, 0.4, 0.05)


def _motion(kind, h1, h2, dt, split):
    if kind == "ground":
        return GroundPolyMotion(h1, h2, dt, split=split), None
    return LinearPolyMotion(_building(kind), h1, h2, dt, split=split), 2


@pytest.mark.parametrize("split", [None, 7])
@pytest.mark.parametrize("kind", ["ground", "floor"])
def test_spectrum_is_response_spectrum(sylmar, kind, split):
    """x, y and the azimuth 30° (the building is linear: the floor's motion along 30° is its
    response to the ground's). Measured ≤ 2.8e-14 elementwise relative (psa, sa, sv, sd; periods
    0.02–5 s and 0, damping 2 % and 5 %)."""
    h1, h2, dt = sylmar
    m, fl = _motion(kind, h1, h2, dt, split)
    th = np.radians(30.0)
    for d, a in ((0, h1), (1, h2), (30.0, np.cos(th) * h1 + np.sin(th) * h2)):
        r = spectrum_on_poly(m, fl, T, Z, direction=d)
        ref = fs.response_spectrum(a, dt, T, Z, building=_building(kind), floor=fl)
        for name in ("psa", "sa", "sv", "sd"):
            x, y = getattr(r, name), getattr(ref, name)
            if name in ("sv", "sd"):  # 0 at period 0
                x, y = x[:, 1:], y[:, 1:]
            assert _rel(x, y) <= 1e-12, (d, name)
        np.testing.assert_allclose(r.psv, ref.psv, rtol=1e-12)
        assert r.periods.tolist() == T and r.damping.tolist() == Z


@pytest.mark.parametrize("split", [None, 7])
@pytest.mark.parametrize("kind", ["ground", "floor", "pair"])
def test_rotd_is_rotd_spectrum(sylmar, kind, split):
    """Measured ≤ 3.6e-14 elementwise relative (RotD50, RotD100, every angle's PSA; a model per
    direction included); the angle of RotD100 to 5e-13°, its time to 3e-15 s."""
    h1, h2, dt = sylmar
    m, fl = _motion(kind, h1, h2, dt, split)
    r = rotd_on_poly(m, fl, T, Z)
    ref = fs.rotd_spectrum((h1, h2), dt, T, Z, building=_building(kind), floor=fl)
    for name in ("rotd50", "rotd100", "psa_angles"):
        assert _rel(getattr(r, name), getattr(ref, name)) <= 1e-12, name
    d = np.abs(r.angle100 - ref.angle100)
    assert np.max(np.minimum(d, 180.0 - d)) <= 1e-9
    np.testing.assert_allclose(r.time100, ref.time100, rtol=0, atol=1e-9)
    for mine, theirs in ((r.h1, ref.h1), (r.h2, ref.h2)):
        assert _rel(mine.psa, theirs.psa) <= 1e-12


def test_one_pass_over_the_motion(sylmar):
    """RotD and the two directions' spectra read the motion once."""
    h1, h2, dt = sylmar
    m = Counted(GroundPolyMotion(h1[:300], h2[:300], dt))
    r = rotd_on_poly(m, None, T, Z)
    assert m.passes == 1 and r.h1 is not None and r.h2 is not None


def test_refusals(sylmar):
    h1, h2, dt = sylmar
    g = GroundPolyMotion(h1[:50], h2[:50], dt)
    for bad in (2, True, "x"):
        with pytest.raises(ModelError, match="direction") as e:
            spectrum_on_poly(g, None, [0.5], direction=bad)
        assert "\n" not in str(e.value)
    with pytest.raises(ModelError, match="floor 1"):
        spectrum_on_poly(g, 1, [0.5])
    with pytest.raises(ModelError, match="periods"):
        rotd_on_poly(g, None, None)
    with pytest.raises(ModelError, match="angles"):
        rotd_on_poly(g, None, [0.5], angles=1)


def test_undamped_oscillator_under_a_sine_is_the_closed_form():
    """``q'' + ω² q = −A sin Ωt`` from rest: ``q = A/(ω² − Ω²)·((Ω/ω) sin ωt − sin Ωt)``, whose
    extrema are where ``cos ωt = cos Ωt``: ``t = 2πk/(ω ± Ω)``; so ``sd`` is known exactly. The
    motion is degree-23 polynomials on segments of 0.1 s (``ω·L`` up to 2.1: the oscillators
    cut them in up to 5 pieces). Measured ≤ 1.1e-14 relative (T = 0.5 s, whose response repeats
    every second: its last peak carries the rounding of 300 pieces), the others ≤ 7e-16; the
    period 0 gives A (the sine's peak inside a segment) to 7e-16."""
    A, om, dt, t_end = 3.0, 2 * np.pi, 0.1, 10.0
    m = Harmonic(A, om, dt, 101, -np.pi / 2, None)
    periods = [0.0, 0.3, 0.5, 0.7, 1.6, 3.0]
    r = spectrum_on_poly(m, None, periods, 0.0)
    assert r.sa[0, 0] == pytest.approx(A, rel=1e-14)
    for i, T in enumerate(periods[1:], start=1):
        w = 2 * np.pi / T
        t = np.concatenate([2 * np.pi * np.arange(1, 1000) / (w + om),
                            2 * np.pi * np.arange(1, 1000) / abs(w - om), [t_end]])  # fmt: skip
        t = t[t <= t_end]
        q = A / (w**2 - om**2) * (om / w * np.sin(w * t) - np.sin(om * t))
        assert r.sd[0, i] == pytest.approx(np.max(np.abs(q)), rel=1e-13), T


def test_tiny_segments(sylmar):
    """Segments of 1e-9 of a step at both ends of every step (a building's events): measured
    ≤ 2.3e-15 relative to the aligned segments on the ground and a floor."""
    h1, h2, dt = sylmar
    for kind in ("ground", "floor"):
        m, fl = _motion(kind, h1, h2, dt, None)
        ref = rotd_on_poly(m, fl, T, Z)
        r = rotd_on_poly(Recut(m, [1e-9, 0.5, 1 - 1e-9]), fl, T, Z)
        assert _rel(r.psa_angles, ref.psa_angles) <= 1e-13
        assert _rel(r.h1.sd[:, 1:], ref.h1.sd[:, 1:]) <= 1e-13
        assert _rel(r.h2.sv[:, 1:], ref.h2.sv[:, 1:]) <= 1e-13


def _horner(c, t):
    """``Σ_j c_j t^j`` (Horner; mpmath numbers)."""
    s = 0
    for cj in reversed(c):
        s = s * t + cj
    return s


def _mp_peaks(A, T, xi, L):
    """sd, sv, sa of ``q'' + 2ξωq' + ω²q = −A τ^23`` on ``[0, L]`` from rest: its Taylor series
    to degree 120 at 50 digits (every term), the peaks from a 2001-point grid refined by the
    root of the derivative."""
    mpmath = pytest.importorskip("mpmath")
    with mpmath.workdps(50):
        w = 2 * mpmath.pi / T
        q = [mpmath.mpf(0)] * 121
        v = [mpmath.mpf(0)] * 121
        for j in range(120):
            q[j + 1] = v[j] / (j + 1)
            v[j + 1] = (-(w**2) * q[j] - 2 * xi * w * v[j] - (A if j == 23 else 0)) / (j + 1)
        s = [w**2 * a + 2 * xi * w * b for a, b in zip(q, v, strict=True)]
        out = []
        for c in (q, v, s):
            dc = [j * c[j] for j in range(1, len(c))]
            ts = np.linspace(0, L, 2001)
            vals = [abs(_horner(c, mpmath.mpf(t))) for t in ts]
            i = int(np.argmax(vals))
            best = vals[i]
            if 0 < i < ts.size - 1:
                t = mpmath.findroot(lambda t, dc=dc: _horner(dc, t), ts[i])
                best = max(best, abs(_horner(c, t)))
            out.append(float(best))
    return out


def test_a_large_degree_23_term():
    """One 1-s segment of ``a = 3 τ^23`` m/s² (its whole weight in the last coefficient: the
    series must cut it in pieces where its own terms decay, not just where ``ω·L`` is small).
    Against the 50-digit series, measured ≤ 3.3e-16 relative for T = 0.5 … 20 s."""
    m = OneSegment([0.0] * 23 + [3.0], 1.0)
    for T in (0.5, 5.0, 20.0):
        r = spectrum_on_poly(m, None, [T], 0.05)
        sd, sv, sa = _mp_peaks(3.0, T, 0.05, 1.0)
        assert r.sd[0, 0] == pytest.approx(sd, rel=1e-14)
        assert r.sv[0, 0] == pytest.approx(sv, rel=1e-14)
        assert r.sa[0, 0] == pytest.approx(sa, rel=1e-14)
