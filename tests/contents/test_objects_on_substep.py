"""The rigid-block pass of one sub-step (``objects_on_substep``, called by the linear path's
``slide_kernel`` and by the kernel of buildings on nonlinear isolation): driven by hand,
sub-step by sub-step, with the floor's velocity and displacement increments formed here, it
gives the states of ``fs.slide`` bit for bit."""

from __future__ import annotations

import numpy as np
import pytest

import floorslide as fs
from floorslide.building._instep import curvature_tail_weights, substep_inputs
from floorslide.building.exact_motion import building_motion
from floorslide.constants import G
from floorslide.contents import _kernels as ck
from floorslide.numerics.polynomial import scratch
from tests.conftest import SLAMMER

MUS = np.array([0.02, 0.05, 0.1, 0.2, 0.5])


def by_hand(fm, mus) -> np.ndarray:
    """Final states of blocks on floor motion `fm`, stepped by ``objects_on_substep``."""
    R, beta, rv, rd, h, m = fm.R, fm.beta, fm.rv, fm.rd, fm.h, fm.substeps
    acc = fm.acc
    K = R.shape[0] - 1
    states = np.zeros((mus.size, ck.NCOL))
    states[:, ck.LIMIT_AT] = -1.0
    # as slide_kernel at t = 0: friction transmits at most mu·g
    states[:, ck.PEAK_ACC] = np.minimum(abs(beta[0] * acc[0]), mus * G)
    XW = np.zeros((3, R.shape[1]))
    WA, WS = curvature_tail_weights(R, beta, h, XW[2])
    MU = np.array([mus, mus])
    buf, rw = np.empty(5 * K + 17 + ck.NCOL), scratch(K + 3)
    flags = np.array([0, 1, 1, 10000, 0, mus.size])
    for k0, X in fm.chunks():
        for kk in range((X.shape[0] - 1) // m):
            k = k0 + kk
            slope = (acc[k + 1] - acc[k]) / (m * h)
            for r in range(m):
                aa, ab = substep_inputs(acc[k], acc[k + 1], r, m)
                xp, x = X[kk * m + r], X[kk * m + r + 1]
                vr0 = rv @ xp if rv.size else 0.0
                dV = (rv @ x if rv.size else 0.0) - vr0 + 0.5 * h * (aa + ab)
                dD = (rd @ x - rd @ xp if rd.size else 0.0) - vr0 * h
                dD += aa * h * h / 2.0 + slope * h * h * h / 6.0
                t0 = (k * m + r) * h
                XW[0], XW[1] = xp, x
                pk = np.array([aa, ab, slope, h, t0, WA, WS, dV, dD, G, 0.0, G, G, G * h,
                               G * h * h / 2.0, G])  # fmt: skip
                ck.objects_on_substep(R, beta, XW, MU, states, buf, rw, pk, flags)
    return states


@pytest.mark.parametrize("where", ["fixed roof", "isolated roof"])
def test_objects_on_substep_is_the_slide_kernel_loop(where):
    ag = np.loadtxt(SLAMMER / "ImperialValley_1940_ELC-180.txt")[:1500] * G
    dt = 0.01
    sup = fs.ShearBuilding.from_period(stories=2, period=0.3, damping=0.03)
    b = sup if where == "fixed roof" else fs.IsolatedBuilding(sup, 1.0, period=2.5, damping=0.1)
    fm = building_motion(b, ag, dt).floor(2)
    ref = fs.slide(fm, None, MUS, MUS)
    states = by_hand(fm, MUS)
    assert ref.slip_phases.sum() > 5  # the blocks do slide and stick
    np.testing.assert_array_equal(states[:, ck.PEAK_DISP], ref.peak_slide)
    np.testing.assert_array_equal(states[:, ck.DISP], ref.residual_slide)
    np.testing.assert_array_equal(states[:, ck.PEAK_ACC], ref.peak_abs_accel)
    np.testing.assert_array_equal(states[:, ck.SLIPS].astype(int), ref.slip_phases)
