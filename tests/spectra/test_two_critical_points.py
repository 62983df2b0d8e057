"""An exact spectrum finds every peak inside a step, even when the response's derivative has
two close zeros in one step (issue: the kernel assumed at most one critical point per step
for ω·dt ≤ 0.5, which bounds the zeros of a damped sinusoid, not of β + a damped sinusoid)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.linalg import expm

import floorslide as fs
from floorslide.building.exact_motion import single_use_motion
from floorslide.spectra.core import _exact
from tests.reference import linear_peaks

DT = 0.01


def _foh(A, b, t):
    aug = np.zeros((4, 4))
    aug[:2, :2] = A
    aug[:2, 2] = b
    aug[2, 3] = 1.0
    E = expm(aug * t)
    return E[:2, :2], E[:2, 2], E[:2, 3]


def two_zero_record(w, xi, z1=0.55, z2=0.9, q0=0.05, ak=1.0, n=80):
    """An 80-sample record whose oscillator (w, xi) has q' = 0 at z1·dt and z2·dt inside its
    last step, so that its largest |q| is the local maximum at z1·dt, between the samples, where
    q' changes sign twice in one step: the last step's start state and input solve
    q'(z1·dt) = q'(z2·dt) = 0; the earlier samples are the least-norm input that brings the
    oscillator from rest to that state."""
    A = np.array([[0.0, 1.0], [-(w**2), -2 * xi * w]])
    b = np.array([0.0, -1.0])
    M, r = [], []
    for z in (z1 * DT, z2 * DT):
        P, g0, g1 = _foh(A, b, z)
        M.append([P[1, 1], g1[1] / DT])
        r.append(-(P[1, 0] * q0 + g0[1] * ak - g1[1] * ak / DT))
    v0, a_last = np.linalg.solve(M, r)
    k = n - 2
    Pd, g0, g1 = _foh(A, b, DT)
    p, qv = g0 - g1 / DT, g1 / DT
    G = np.zeros((2, k + 1))
    for j in range(k + 1):
        e = np.zeros(k + 1)
        e[j] = 1.0
        x = np.zeros(2)
        for i in range(k):
            x = Pd @ x + p * e[i] + qv * e[i + 1]
        G[:, j] = x
    free = list(range(1, k))
    sol = np.linalg.lstsq(G[:, free], np.array([q0, v0]) - G[:, k] * ak, rcond=None)[0]
    acc = np.zeros(n)
    acc[free] = sol
    acc[k] = ak
    acc[k + 1] = a_last
    return acc


@pytest.mark.parametrize(("wdt", "xi"), [(0.45, 0.05), (0.2, 0.05), (0.45, 0.0)])
def test_displacement_peak_between_two_close_zeros(wdt, xi):
    w = wdt / DT
    acc = two_zero_record(w, xi)
    A = np.array([[0.0, 1.0], [-(w**2), -2 * xi * w]])
    ref = linear_peaks(A, np.array([0.0, -1.0]), np.array([[1.0, 0.0]]), acc, DT)[0]
    end = abs(fs.response_spectrum(acc, DT, [2 * np.pi / w], xi, method="samples").sd[0, 0])
    assert (ref - end) / ref > 1e-5  # the peak is inside the last step, above the samples
    sp = fs.response_spectrum(acc, DT, [2 * np.pi / w], xi)
    assert sp.sd[0, 0] == pytest.approx(ref, rel=1e-10)
    sd, _, _ = _exact(
        single_use_motion(None, acc, DT, None), np.array([2 * np.pi / w]), np.array([xi]), True
    )
    assert sd[0, 0] == pytest.approx(ref, rel=1e-10)


def test_on_a_floor_too():
    """The same record through a rigid-ish floor (T = 0.01 s): the floor motion is nearly the
    record, and the spectrum on the floor must find the in-step peak as well."""
    w = 0.45 / DT
    acc = two_zero_record(w, 0.05)
    b = fs.ShearBuilding.from_period(stories=1, period=0.005, damping=0.05)
    T = np.array([2 * np.pi / w])
    sp = fs.response_spectrum(acc, DT, T, 0.05, building=b, floor=1)
    A, B = b.state_matrices()
    Ca, Da, _ = b.output_matrices([1], "acceleration")
    n = A.shape[0]
    Aug = np.zeros((n + 2, n + 2))
    Aug[:n, :n] = A
    Aug[n, n + 1] = 1.0
    Aug[n + 1, :n] = -Ca[0]
    Aug[n + 1, n] = -(w**2)
    Aug[n + 1, n + 1] = -2 * 0.05 * w
    baug = np.concatenate([B[:, 0], [0.0, -Da[0, 0]]])
    C = np.zeros((1, n + 2))
    C[0, n] = 1.0
    ref = linear_peaks(Aug, baug, C, acc, DT)[0]
    assert sp.sd[0, 0] == pytest.approx(ref, rel=1e-9)
