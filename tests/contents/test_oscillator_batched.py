"""The 2-DOF oscillator's batched kernel: many friction values in one call give, bit for bit,
what one call per value gives, and agree with the event kernel on every part (the reference)
to rounding, on real records on the ground and on building floors."""

from __future__ import annotations

import numpy as np
import pytest

import floorslide as fs
from floorslide.building.exact_motion import floor_motion
from floorslide.constants import G
from floorslide.contents import _oscillator_batch as batch
from floorslide.contents import _oscillator_kernel as cols
from floorslide.contents.oscillator import _exact_states, slide_oscillator
from floorslide.contents.sliding import friction_pairs
from tests.conftest import load_slammer

MU_K = np.array([0.0, 1e-4, 0.003, 0.02, 0.05, 0.1, 0.2, 0.35, 5.0, 1e6])
"""Free sliding, tiny, moderate, never sliding."""
MU_S = MU_K * np.array([1.0, 1.0, 1.5, 1.0, 1.3, 1.0, 1.2, 1.0, 1.0, 1.0])
"""Some static coefficients above the kinetic ones."""
OSC = dict(frequency=5.0, damping=0.02, mass_ratio=1.0)

FLOORS = {
    "ground": (None, 0),
    "fixed roof": (fs.ShearBuilding.from_period(1, 0.2, 0.05), 1),
    "isolated roof": (
        fs.IsolatedBuilding(fs.ShearBuilding.from_period(2, 0.3, 0.05), 1.0, 2.5, 0.1),
        2,
    ),
}


@pytest.fixture(scope="module")
def kobe():
    """Kobe 1995 Kakogawa (KAK-000), 3,999 samples at dt = 0.01 s, m/s²."""
    return load_slammer("Kobe_1995_KAK-000.txt")


FIELDS = (
    "peak_slide",
    "residual_slide",
    "peak_deformation",
    "peak_top_accel",
    "peak_base_accel",
    "slide_fraction",
    "slip_phases",
)


@pytest.mark.parametrize("where", list(FLOORS))
@pytest.mark.parametrize("record", ["kobe", "elcentro"])
def test_batched_equals_one_call_per_mu(where, record, request):
    acc, dt = request.getfixturevalue(record)
    building, floor = FLOORS[where]
    fm = floor_motion(building, acc, floor, dt)
    together = slide_oscillator(fm, None, MU_K, mu_s=MU_S, histories=True, **OSC)
    for i, (mk, ms) in enumerate(zip(MU_K, MU_S, strict=True)):
        one = slide_oscillator(fm, None, mk, mu_s=ms, histories=True, **OSC)
        for name in FIELDS:
            assert getattr(one, name)[0] == getattr(together, name)[i], (name, mk)
        for name in ("u", "z", "top_accel", "base_accel"):
            np.testing.assert_array_equal(getattr(one, name)[0], getattr(together, name)[i])
    # the same through the building given to the solver (its own streamed motion)
    if building is not None:
        direct = slide_oscillator(acc, dt, MU_K, mu_s=MU_S, building=building, floor=floor, **OSC)
        for name in FIELDS:
            np.testing.assert_array_equal(getattr(direct, name), getattr(together, name))


@pytest.mark.parametrize("where", list(FLOORS))
@pytest.mark.parametrize("record", ["kobe", "elcentro"])
def test_agrees_with_the_event_kernel_on_every_part(where, record, request):
    """Against the event kernel run on every part (the solver before the batched kernel):
    the same slips, peaks and histories to rounding, 1e-13 of each oscillator's peak. Except
    for a base that (nearly) never sticks (mu_k ≤ 1e-4): its slide integrates a velocity that
    no stick phase resets, whose rounding errors add up over the record; there the event
    kernel's own result moves by 4–7e-14 of the peak when the samples move by half an ulp
    (Kobe KAK, ground), and the two kernels differ by up to 1.5e-13: 5e-13 there."""
    acc, dt = request.getfixturevalue(record)
    building, floor = FLOORS[where]
    fm = floor_motion(building, acc, floor, dt)
    mk, ms = friction_pairs(MU_K, MU_S)
    w = 2 * np.pi * OSC["frequency"]
    args = (fm, fm.acc, mk, ms, w, OSC["damping"], OSC["mass_ratio"], True)
    counts = np.zeros(batch.C_NCOL, dtype=np.int64)
    S1, H1 = _exact_states(*args, batched=True, counts=counts)
    S0, H0 = _exact_states(*args, batched=False)
    # most parts are cleared by the bounds
    cleared = counts[batch.CLEARED] + counts[5 + batch.CLEARED]
    assert cleared > 0.8 * counts.sum()
    np.testing.assert_array_equal(S1[:, cols.O_SLIPS], S0[:, cols.O_SLIPS])
    np.testing.assert_array_equal(S1[:, cols.O_MODE], S0[:, cols.O_MODE])
    tol = np.where(mk <= 1e-4, 5e-13, 1e-13)
    scale = {
        cols.O_U: S0[:, cols.O_PEAK_U],
        cols.O_PEAK_U: S0[:, cols.O_PEAK_U],
        cols.O_PEAK_Z: S0[:, cols.O_PEAK_Z],
        cols.O_PEAK_TOP: S0[:, cols.O_PEAK_TOP],
        cols.O_PEAK_BASE: S0[:, cols.O_PEAK_BASE],
        cols.O_SLIDE_TIME: np.full(mk.size, (acc.size - 1) * dt),
    }
    for col, s in scale.items():
        err = np.abs(S1[:, col] - S0[:, col])
        assert np.all(err <= tol * s), (col, err / np.maximum(s, 1e-300))
    for j, col in enumerate((cols.O_PEAK_U, cols.O_PEAK_Z, cols.O_PEAK_TOP, cols.O_PEAK_BASE)):
        err = np.abs(H1[:, :, j] - H0[:, :, j]).max(axis=1)
        assert np.all(err <= tol * S0[:, col]), (j, err / np.maximum(S0[:, col], 1e-300))
    # never sliding: the fixed-base oscillator, stuck throughout
    assert S1[-1, cols.O_SLIPS] == 0 and S1[-1, cols.O_PEAK_U] == 0.0
    # free sliding: in slip from the first motion on
    assert S1[0, cols.O_SLIDE_TIME] > 0.9 * (acc.size - 1) * dt


def test_propagators_are_the_event_kernels_series():
    """The propagators step a state as the event kernel's Taylor series does (to rounding),
    and the curvature weights bound the second derivative of what they weigh."""
    from floorslide.building._instep import poly_val
    from floorslide.contents._oscillator_kernel import _phase_series

    w, xi, r, ho, K = 2 * np.pi * 5.0, 0.02, 0.7, 0.01, 15
    PHI, GF, EF, WS, WF = batch.phase_propagators(ho, K, w, xi, r)
    rng = np.random.default_rng(3)
    Y = np.zeros((4, K + 1))
    for p, mode in ((batch.STICK, 0), (batch.SLIP, 1), (batch.SLIP, -1)):
        y0 = rng.normal(size=4) * [0.1, 0.3 * (mode != 0), 0.01, 0.2]
        cs = np.zeros(K + 1)
        cs[:2] = rng.normal(size=2) * [3.0, 50.0]
        fkg = 0.2 * G
        _phase_series(y0, mode, cs, K, w, xi, r, fkg if mode else 0.0, False, Y)
        ref = np.array([poly_val(Y[i], K, ho) for i in range(4)])
        got = PHI[p] @ y0 + GF[p] @ cs + (mode * fkg * EF if mode else 0.0)
        rows = slice(2, 4) if mode == 0 else slice(0, 4)
        np.testing.assert_allclose(got[rows], ref[rows], rtol=1e-14, atol=1e-15 * np.abs(ref).max())
        # |z''| on the part against its bound (5)
        t = np.linspace(0.0, ho, 101)
        d2 = np.polynomial.polynomial.polyval(t, np.polynomial.polynomial.polyder(Y[2], 2))
        inputs = np.concatenate([np.abs(y0), [abs(mode * fkg)] if p == batch.SLIP else [0.0]])
        bound = WS[p, batch.B_Z, : 4 + p] @ inputs[: 4 + p] + WF[p, batch.B_Z] @ np.abs(cs)
        assert np.abs(d2).max() <= bound


def test_batched_handles_a_floor_at_rest_and_no_friction():
    """A record that starts and ends at rest, mu = 0 and a huge mu on a building's floor (the
    floor at rest has rounding-level coefficients): finite, and the stuck one never slides."""
    acc, dt = load_slammer("ImperialValley_1940_ELC-180.txt")
    acc = np.concatenate([np.zeros(50), acc[:600], np.zeros(50)])
    b = fs.ShearBuilding.from_period(1, 0.2, 0.05)
    res = slide_oscillator(acc, dt, [0.0, 1e6], building=b, floor=1, histories=True, **OSC)
    assert np.all(np.isfinite(res.u)) and np.all(np.isfinite(res.z))
    assert res.slip_phases[1] == 0 and res.peak_slide[1] == 0.0
    assert res.slide_fraction[0] > 0.5


def test_monotone_rise_is_first_rise():
    """Newton's first rise of a certified increasing polynomial settles on the machine number
    root isolation finds (stops and breakaways of the oscillator's series, degree 15), and
    defers to root isolation otherwise."""
    from floorslide.contents._oscillator_kernel import _phase_series, monotone_rise
    from floorslide.numerics.polynomial import first_rise, scratch

    K, w, xi, r = 15, 2 * np.pi * 5.0, 0.02, 1.0
    rng = np.random.default_rng(7)
    Y = np.zeros((4, K + 1))
    work = scratch(K + 1)
    cs = np.zeros(K + 1)
    found = 0
    for _ in range(400):
        mode = int(rng.choice([0, 1, -1]))
        y0 = np.array([0.0, 0.0, 0.0, 0.0])
        y0[2:] = rng.normal(size=2) * [0.005, 0.2]
        cs[:2] = rng.normal(size=2) * [3.0, 80.0]
        fkg = rng.uniform(0.0, 0.5) * G
        if mode:
            y0[1] = mode * abs(rng.normal()) * 0.02
        _phase_series(y0, mode, cs, K, w, xi, r, fkg, False, Y)
        if mode:
            p = -mode * Y[1]
        else:
            p = r * cs - 2 * xi * w * Y[3] - w * w * Y[2]
            p = p * float(rng.choice([1.0, -1.0]))
            p[0] -= abs(p[0]) * rng.uniform(0.0, 0.5) + 1e-3
        for hi in (0.01, 0.004):
            a = first_rise(p, K, 0.0, hi, 0.0, work)
            b = monotone_rise(p, K, hi, work)
            assert a == b, (a, b)
            found += a > 0.0
    assert found > 50
