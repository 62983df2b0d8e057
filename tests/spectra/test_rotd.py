"""RotD50 and RotD100 spectra (Boore 2010; docs/design.md §10d) against closed forms, the exact
1-D spectra along every angle, an independent reference on a building with a model per
direction, and their invariances."""

from __future__ import annotations

import numpy as np
import pytest

import floorslide as fs
from floorslide.building.directions import plane_motions
from floorslide.errors import ModelError
from floorslide.records.pairs import read_pairs
from floorslide.spectra.rotd import _peaks
from tests.conftest import ROOT
from tests.reference_rotd import rotated_peaks

T = np.array([0.0, 0.05, 0.3, 1.0, 4.0])
Z = [0.02, 0.05]
STIFF = fs.ShearBuilding.from_period(3, 0.35, damping=0.03)
SOFT = fs.ShearBuilding.from_period(3, 0.8)
HALF = 1 / np.cos(np.deg2rad(0.5))  # RotD100 ≤ max over 1° angles / cos(0.5°)


@pytest.fixture(scope="module")
def pairs():
    """Two real PEER pairs: Northridge Sylmar (8,773 samples) and Imperial Valley El Centro #6
    (7,818: h1 padded by one zero)."""
    ps = read_pairs(ROOT / "data" / "records" / "pairs" / "index.csv")
    return [ps[0], ps[2]]


def rel(a, b):
    """Largest difference relative to the scale of `b`: each value's own, or along angles (the
    last axis of ``psa_angles``-shaped arrays) the largest of its spectral ordinate."""
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    scale = np.abs(b).max(axis=-1, keepdims=True) if b.ndim == 3 else np.abs(b)
    return float((np.abs(a - b) / np.maximum(scale, 1e-300)).max())


@pytest.mark.parametrize("theta", [0.0, 30.0, 90.0, 137.3])
@pytest.mark.parametrize("where", ["ground", "floor"])
def test_one_component_along_an_azimuth(pairs, theta, where):
    """``x = a cos θ``, ``y = a sin θ``: RotD100 is the 1-D PSA of ``a`` (its vector always
    points along θ) and RotD50 that PSA times ``median_j |cos(θ_j − θ)|``; the direction of
    RotD100 is θ (measured: ≤ 2e-15 on the ground, ≤ 2e-14 on the floor)."""
    a, dt = pairs[0].h1, pairs[0].dt
    kw = dict(building=SOFT, floor=3) if where == "floor" else {}
    th = np.deg2rad(theta)
    r = fs.rotd_spectrum((a * np.cos(th), a * np.sin(th)), dt, T, Z, directions=False, **kw)
    one = fs.response_spectrum(a, dt, T, Z, **kw).psa
    assert rel(r.rotd100, one) <= 1e-12
    factor = np.median(np.abs(np.cos(np.deg2rad(r.angles) - th)))
    assert rel(r.rotd50, one * factor) <= 1e-12
    assert rel(r.psa_angles, one[..., None] * np.abs(np.cos(np.deg2rad(r.angles) - th))) <= 1e-12
    off = (r.angle100 - theta % 180 + 90) % 180 - 90
    assert np.abs(off).max() <= 1e-9


@pytest.mark.parametrize("which", [0, 1])
@pytest.mark.parametrize("where", ["ground", "floor"])
def test_every_angle_is_the_1d_spectrum_along_it(pairs, which, where):
    """Independent reference: the exact 1-D spectrum of ``pair.along(θ_j)`` at each of the 180
    angles (on a floor the building is linear, so the floor motion along θ is its response to
    the record along θ). Each angle and their median (RotD50) agree to ≤ 1e-12 (measured
    ≤ 1.1e-14); RotD100 lies between the largest of them and that over cos(0.5°), and equals the
    1-D spectrum along its own direction ``angle100``."""
    pair = pairs[which]
    kw = dict(building=SOFT, floor=3) if where == "floor" else {}
    periods = T if where == "ground" else T[[0, 1, 3]]
    r = fs.rotd_spectrum(pair, periods=periods, damping=0.05, directions=False, **kw)
    ref = np.array(
        [fs.response_spectrum(pair.along(a), pair.dt, periods, 0.05, **kw).psa[0] for a in r.angles]
    ).T  # (periods, angles)
    assert rel(r.psa_angles[0][None], ref[None]) <= 1e-12
    assert rel(r.rotd50[0], np.median(ref, axis=1)) <= 1e-12
    top = ref.max(axis=1)
    assert np.all(r.rotd100[0] >= top * (1 - 1e-12))
    assert np.all(r.rotd100[0] <= top * HALF * (1 + 1e-12))
    along = [
        fs.response_spectrum(pair.along(a), pair.dt, [t], 0.05, **kw).psa[0, 0]
        for a, t in zip(r.angle100[0], periods, strict=True)
    ]
    assert rel(r.rotd100[0], along) <= 1e-12


@pytest.mark.parametrize("which", [0, 1])
def test_floor_of_a_building_pair_against_an_independent_reference(pairs, which):
    """A different model per direction (0.8 s and 0.35 s): no single 1-D spectrum gives the
    rotated response, so an independent reference (tests/reference_rotd.py: SciPy's matrix
    exponential on a dense grid, Chebyshev interpolation inside intervals) gives every angle's
    peak and the vector's. Agreement ≤ 1e-12 (measured ≤ 5.3e-14)."""
    pair = pairs[which]
    periods = np.array([0.05, 0.3, 1.0, 3.0])
    r = fs.rotd_spectrum(
        pair, periods=periods, building=fs.BuildingPair(SOFT, STIFF), floor=3, directions=False
    )
    peaks, mags = rotated_peaks(
        (SOFT, STIFF), 3, pair.h1, pair.h2, pair.dt, periods, 0.05, r.angles
    )
    w2 = (2 * np.pi / periods) ** 2
    assert rel(r.psa_angles, (peaks * w2[:, None])[None]) <= 1e-12
    assert rel(r.rotd50[0], np.median(peaks, axis=1) * w2) <= 1e-12
    assert rel(r.rotd100[0], mags * w2) <= 1e-12


@pytest.mark.parametrize("where", ["ground", "floor"])
def test_turning_the_axes_changes_nothing(pairs, where):
    """RotD100 does not depend on the recording's axes (≤ 1e-12, measured ≤ 3e-14), nor does
    RotD50 when the axes turn by a multiple of the angle step; the direction of RotD100 turns
    with them."""
    pair = pairs[0]
    kw = dict(building=SOFT, floor=2) if where == "floor" else {}
    r = fs.rotd_spectrum(pair, periods=T, damping=Z, directions=False, **kw)
    for phi in (37.0, 123.0, 12.345):
        t = fs.rotd_spectrum(pair.rotated(phi), periods=T, damping=Z, directions=False, **kw)
        assert rel(t.rotd100, r.rotd100) <= 1e-12
        if phi == round(phi):
            assert rel(t.rotd50, r.rotd50) <= 1e-12
        turn = (t.angle100 - (r.angle100 - phi) + 90) % 180 - 90
        assert np.abs(turn).max() <= 1e-6


def test_samples_method_is_below_and_converges(pairs):
    """``method="samples"`` reads peaks at the samples only: never above the exact values and
    converging to them as the same piecewise-linear record is sampled more finely (error ∝ dt²:
    ×16 finer, ≥ 100 times smaller), while the exact values do not move (≤ 1e-12)."""
    pair = pairs[1]
    n = 2500  # the strong part
    h1, h2, dt = pair.h1[:n], pair.h2[:n], pair.dt
    periods = [0.0, 0.03, 0.1, 0.5]
    exact = fs.rotd_spectrum((h1, h2), dt, periods, directions=False)
    errors = []
    for k in (1, 4, 16):
        t = np.arange((n - 1) * k + 1) / k
        fine = (np.interp(t, np.arange(n), h1), np.interp(t, np.arange(n), h2))
        ex = fs.rotd_spectrum(fine, dt / k, periods, directions=False)
        assert rel(ex.rotd100, exact.rotd100) <= 1e-12
        assert rel(ex.rotd50, exact.rotd50) <= 1e-12
        sa = fs.rotd_spectrum(fine, dt / k, periods, method="samples", directions=False)
        assert np.all(sa.psa_angles <= exact.psa_angles * (1 + 1e-12))
        assert np.all(sa.rotd100 <= exact.rotd100 * (1 + 1e-12))
        errors.append(max(rel(sa.rotd100, exact.rotd100), rel(sa.rotd50, exact.rotd50)))
    assert errors[0] > 1e-4  # dt = 0.005 s misses in-step peaks at 0.03 s
    assert errors[2] <= errors[0] / 100


@pytest.mark.parametrize("where", ["ground", "pair"])
def test_searching_every_step_changes_nothing(pairs, where):
    """The skip rules (rigorous bounds) leave every peak as a search of every step along every
    angle finds it (≤ 1e-13; measured: identical)."""
    pair = pairs[0]
    n = 1500
    building = fs.BuildingPair(SOFT, STIFF) if where == "pair" else None
    floor = 3 if building else None
    fm1, fm2 = plane_motions(building, pair.h1[:n], pair.h2[:n], pair.dt, floor)
    periods, theta = np.array([0.0, 0.04, 0.2, 2.0]), np.arange(36) * 5.0
    Zs = np.array([0.05])
    fast = _peaks(fm1, fm2, periods, Zs, theta, True)
    slow = _peaks(fm1, fm2, periods, Zs, theta, True, search_all=True)
    assert rel(fast[0], slow[0]) <= 1e-13
    assert rel(fast[1], slow[1]) <= 1e-13


def test_streamed_motion_gives_the_same_peaks(pairs):
    """A floor motion streamed chunk by chunk (long records) gives the peaks of one kept whole
    (≤ 1e-13)."""
    pair = pairs[1]
    periods, theta, Zs = np.array([0.0, 0.05, 0.5, 3.0]), np.arange(180.0), np.array([0.05])
    whole = plane_motions(fs.BuildingPair(SOFT, STIFF), pair.h1, pair.h2, pair.dt, 2)
    stream = plane_motions(fs.BuildingPair(SOFT, STIFF), pair.h1, pair.h2, pair.dt, 2, max_bytes=0)
    assert not stream[0].motion.kept_whole
    a = _peaks(*whole, periods, Zs, theta, True)
    b = _peaks(*stream, periods, Zs, theta, True)
    assert rel(b[0], a[0]) <= 1e-13
    assert rel(b[1], a[1]) <= 1e-13


def test_spectra_per_direction(pairs):
    """``h1`` and ``h2`` are the ordinary spectra of each direction's floor motion (each
    direction's model under its component) and equal the angles 0° and 90° (≤ 1e-12)."""
    pair = pairs[0]
    r = fs.rotd_spectrum(pair, periods=T, damping=Z, building=fs.BuildingPair(SOFT, STIFF), floor=3)
    for sp, b, a, j in ((r.h1, SOFT, pair.h1, 0), (r.h2, STIFF, pair.h2, 90)):
        fm = fs.building_motion(b, a, pair.dt).floor(3)
        alone = fs.response_spectrum(fm, periods=T, damping=Z)
        assert rel(sp.psa, alone.psa) <= 1e-12
        assert rel(r.psa_angles[..., j], sp.psa) <= 1e-12
    assert np.all(r.rotd100 >= np.maximum(r.h1.psa, r.h2.psa) * (1 - 1e-12))


def test_period_zero_on_the_ground(pairs):
    """At period 0 on the ground the record is linear inside steps: RotD100 is the largest
    ``|(a1, a2)|`` at the samples and each angle's value the peak of ``a1 cos θ + a2 sin θ``
    there (≤ 1e-15)."""
    pair = pairs[0]
    r = fs.rotd_spectrum(pair, periods=[0.0, 1.0], directions=False)
    assert r.rotd100[0, 0] == pytest.approx(np.hypot(pair.h1, pair.h2).max(), rel=1e-15)
    th = np.deg2rad(r.angles)[:, None]
    per_angle = np.abs(pair.h1 * np.cos(th) + pair.h2 * np.sin(th)).max(axis=1)
    assert rel(r.psa_angles[0, 0], per_angle) <= 1e-15
    assert r.rotd50[0, 0] == pytest.approx(np.median(per_angle), rel=1e-15)


def test_components_of_different_lengths_are_padded(pairs):
    """The shorter component is padded with zeros, and the notes say so."""
    pair = pairs[1]
    r = fs.rotd_spectrum((pair.h1[:-10], pair.h2), pair.dt, [0.0, 0.5], directions=False)
    assert any("padded" in n for n in r.notes)
    assert r.rotd100.shape == (1, 2)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        (dict(angles=1), "angles must be from 2"),
        (dict(angles=2.5), "whole number"),
        (dict(periods=[-1.0]), "periods"),
        (dict(periods=None), "periods are required"),
        (dict(periods=[np.nan]), "periods"),
        (dict(method="fft"), "unknown method"),
        (dict(damping=1.2), "damping"),
        (dict(floor=2), "floor= needs building="),
        (dict(periods={"min": 0.01, "max": 10, "n": 10000}, angles=3600), "at most 20000000"),
    ],
)
def test_bad_input_is_one_line(kwargs, match):
    a = np.sin(np.arange(400) * 0.05)
    args = dict(periods=[0.5]) | kwargs
    with pytest.raises(ModelError, match=match) as err:
        fs.rotd_spectrum((a, a), 0.01, **args)
    assert "\n" not in str(err.value)


def test_bad_components():
    a = np.zeros(100)
    with pytest.raises(ModelError, match="two horizontal components"):
        fs.rotd_spectrum(np.zeros((3, 100)), 0.01, [0.5])
    with pytest.raises(ModelError, match="dt is required"):
        fs.rotd_spectrum((a, a), None, [0.5])
    with pytest.raises(fs.RecordError, match="NaN"):
        fs.rotd_spectrum((a, np.full(100, np.nan)), 0.01, [0.5])
    lrb = fs.BilinearIsolator(q_ratio=0.06, period=2.5, yield_disp=0.02)
    nonlinear = fs.NonlinearIsolatedBuilding(SOFT, 1.0, lrb)
    with pytest.raises(ModelError, match="method"):
        fs.rotd_spectrum((a, a), 0.01, [0.5], building=nonlinear, floor=1, method="samples")


def test_stiff_buildings_coarse_dt(pairs):
    """Hard case: stiff models (0.1 s and 0.05 s) under a record thinned to dt = 0.02 s — many
    sub-steps per step for the building (14) and the oscillators — against the independent
    reference (≤ 1e-12; measured ≤ 4.2e-14)."""
    pair = pairs[0]
    h1, h2, dt = pair.h1[:6000:4], pair.h2[:6000:4], 4 * pair.dt
    b1 = fs.ShearBuilding.from_period(2, 0.1)
    b2 = fs.ShearBuilding.from_period(2, 0.05, damping=0.02)
    periods = np.array([0.02, 0.1, 1.0])
    r = fs.rotd_spectrum((h1, h2), dt, periods, building=(b1, b2), floor=2, directions=False)
    peaks, mags = rotated_peaks((b1, b2), 2, h1, h2, dt, periods, 0.05, r.angles)
    w2 = (2 * np.pi / periods) ** 2
    assert rel(r.psa_angles, (peaks * w2[:, None])[None]) <= 1e-12
    assert rel(r.rotd100[0], mags * w2) <= 1e-12


def test_period_zero_only_on_a_floor(pairs):
    """Periods 0 only: the peaks of the floor acceleration, inside steps; the spectra per
    direction are the true peak floor accelerations (≤ 1e-12; measured ≤ 1.2e-16)."""
    pair = pairs[0]
    r = fs.rotd_spectrum(pair, periods=[0.0], building=fs.BuildingPair(SOFT, STIFF), floor=3)
    p1 = fs.building_motion(SOFT, pair.h1, pair.dt).floor(3).peak()[0]
    p2 = fs.building_motion(STIFF, pair.h2, pair.dt).floor(3).peak()[0]
    assert rel(r.h1.psa[0, 0], p1) <= 1e-12
    assert rel(r.h2.psa[0, 0], p2) <= 1e-12
    assert rel(r.psa_angles[0, 0, [0, 90]], np.array([p1, p2])) <= 1e-12
    assert max(p1, p2) * (1 - 1e-12) <= r.rotd100[0, 0] <= np.hypot(p1, p2)
