"""The two passes of the exact spectra (peaks at the samples first, then the skip tests against
them): the screen of the second pass never skips a step the full skip tests would flag, and the
spectra equal those of searching every step — on Kobe, on the bundled raw K-NET record (with and
without its offset), and on floors, linear and on nonlinear isolation."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest
from numba import njit

import floorslide as fs
from floorslide.building.exact_motion import single_use_motion
from floorslide.spectra import _kernels as K
from floorslide.spectra import segmented
from floorslide.spectra.core import _exact, _kernel_data
from tests.conftest import load_slammer

ROOT = Path(__file__).resolve().parents[2]
NB = K.NB


@pytest.fixture(scope="module")
def knet() -> tuple[np.ndarray, float]:
    """AOM008 N-S (raw K-NET, 100 Hz, 13,800 samples), m/s²."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        tr = fs.read_record(ROOT / "tests" / "data" / "raw" / "AOM0081801241951.NS")[0]
    return np.asarray(tr.data, float), float(tr.stats.delta)


@njit
def _screen_against_tests(setup, X, acc, up, dt, S, FK, W):
    """Step every block of oscillators through the record twice in lockstep from the state
    after the first pass — by the screen and by the full tests — and count the oscillator·steps
    the full tests flag but the screen does not (must be none) and those the screen passes."""
    C = setup.C
    PX = setup.PX
    n = X.shape[1]
    nosc = setup.w.size
    steps = X.shape[0] - 1
    AK = np.zeros(steps + 1)
    for k in range(steps + 1):
        AK[k] = K._sample(acc, k, up)
    if n > 0:
        c = np.zeros(max(setup.G_K.max(), setup.b_K) + 2)
        xs = np.empty(n)
        xn = np.empty(n)
        f0 = setup.b_beta[0] * AK[0]
        for j in range(n):
            f0 += setup.b_R[0, j] * X[0, j]
        K._floor_piece(setup, X, 0, AK, steps, dt, f0, FK, W, c, xs, xn)
    missed = 0
    passed = 0
    flag_s = np.zeros(NB, dtype=np.int64)
    flag_t = np.zeros(NB, dtype=np.int64)
    for blk in range(C.shape[0]):
        nb = min(NB, nosc - blk * NB)
        Ss = S[blk].copy()
        St = S[blk].copy()
        for k in range(steps):
            a = AK[k]
            a1 = AK[k + 1]
            if n > 0:
                K._coupling(Ss, PX[blk], X, k, n)
                K._coupling(St, PX[blk], X, k, n)
                K._screen_floor(C[blk], Ss, flag_s, nb, a, a1)
                K._stage_floor(
                    C[blk], St, flag_t, nb, a, a1, dt, FK[k, 0], FK[k, 1], FK[k, 3], FK[k, 2],
                    FK[k, 4]
                )  # fmt: skip
            else:
                K._screen_ground(C[blk], Ss, flag_s, nb, a, a1)
                K._stage_ground(C[blk], St, flag_t, nb, a, a1, dt)
            for o in range(nb):
                if flag_s[o] != 0:
                    passed += 1
                if (flag_t[o] & ~flag_s[o]) != 0:
                    missed += 1
    return missed, passed


def _first_pass(fm, T, Z):
    """The kernel data, the states after the first pass with the screen thresholds, the step."""
    if fm.ground:
        system, up = (0, b""), 1
    else:
        A, B = fm.building.state_matrices()
        Ca, Da, _ = fm.building.output_matrices([fm.floor], "acceleration")
        system = (A.shape[0], np.concatenate([A.ravel(), B[:, 0], Ca[0], Da[0]]).tobytes())
        up = fm.substeps
    h = fm.dt / up
    setup = _kernel_data(float(h), T.tobytes(), Z.tobytes(), *system, period_major=True)
    S = K.spectrum_state(setup.C.shape[0], fm.beta[0] * fm.acc[0])
    FB = np.zeros(K.NFB)
    for k0, X in fm.chunks():
        K.sample_peaks(setup, X, k0, fm.acc, up, h, S, FB)
    K.screen_thresholds(setup.C, S, setup.w.size, FB, h, not fm.ground)
    return setup, S, up, h


@pytest.mark.parametrize("case", ["Kobe", "K-NET raw", "K-NET offset removed", "stiff floor"])
def test_screen_never_skips_a_step_the_tests_flag(case, knet, coarse_record):
    """The screen (end values against the samples' peak less a record-wide bound of the chord
    deviation) lets through every oscillator·step the full skip tests flag with the same peaks,
    and far from all of them."""
    building = floor = None
    if case == "Kobe":
        acc, dt = load_slammer("Kobe_1995_KAK-000.txt")
    elif case.startswith("K-NET"):
        acc, dt = knet
        acc = acc[:6000] - (acc.mean() if "removed" in case else 0.0)
    else:
        acc, dt = coarse_record
        building, floor = fs.ShearBuilding.from_period(1, 0.1, 0.02), 1
    T = np.geomspace(0.02, 5.0, 50)
    Z = np.array([0.02, 0.05])
    fm = single_use_motion(building, acc, dt, floor)
    setup, S, up, h = _first_pass(fm, T, Z)
    (_k0, X), *rest = list(fm.chunks())
    assert not rest  # one chunk: the whole record
    FK = np.zeros((X.shape[0], 6))
    W = np.zeros((X.shape[1] + setup.b_K + 5, X.shape[0] + 1))
    missed, passed = _screen_against_tests(setup, X, acc, up, h, S, FK, W)
    assert missed == 0
    assert passed < 0.5 * T.size * Z.size * (X.shape[0] - 1)


@pytest.mark.parametrize("offset", [True, False])
def test_knet_spectra_equal_every_step_searched(offset, knet):
    """On the raw K-NET record (a mean of 6 % of its PGA, much high-frequency content against its
    peak) the spectra equal those of searching every step of every oscillator."""
    acc, dt = knet
    acc = acc[2000:5000] - (0.0 if offset else acc.mean())
    T = np.geomspace(0.02, 5.0, 40)
    Z = np.array([0.02, 0.05])
    fm = single_use_motion(None, acc, dt, None)
    got = _exact(fm, T, Z)
    full = _exact(fm, T, Z, search_all=True)
    for a, b in zip(got, full, strict=True):
        np.testing.assert_allclose(a, b, rtol=1e-13, atol=0)


@pytest.mark.parametrize(
    "isolator",
    [
        fs.BilinearIsolator(q_ratio=0.06, yield_disp=0.02, period=2.5),
        fs.FrictionPendulum(mu=0.06, period=3.0),
    ],
)
def test_segments_kept_or_repeated_give_the_same_spectra(isolator, elcentro, monkeypatch):
    """On nonlinear isolation the second pass takes a segment between events from what the first
    pass kept (its end state and bounds) or, beyond EVENT_MEMORY, repeats its series: the same
    spectra, bit for bit."""
    acc, dt = elcentro
    acc = acc[:1500]
    sup = fs.ShearBuilding.from_period(stories=1, period=0.3, damping=0.02)
    fm = fs.NonlinearIsolatedBuilding(sup, 1.0, isolator).motion(acc, dt, floors=[1]).floor(1)
    T = np.geomspace(0.02, 5.0, 30)
    kept = fs.response_spectrum(fm, periods=T, damping=[0.02, 0.05])
    monkeypatch.setattr(segmented, "EVENT_MEMORY", 0)
    repeated = fs.response_spectrum(fm, periods=T, damping=[0.02, 0.05])
    for q in ("sd", "sv", "sa"):
        np.testing.assert_array_equal(getattr(kept, q), getattr(repeated, q))
