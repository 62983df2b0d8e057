"""True peaks inside steps are found whatever the number of critical points in a sub-step
(issue 20: ``foh_peaks`` searched a sub-step only where the derivative changed sign between its
ends, and missed a peak between two close zeros of the derivative)."""

from __future__ import annotations

import numpy as np
import pytest

import floorslide as fs
from tests.reference import linear_peaks
from tests.spectra.test_two_critical_points import DT, two_zero_record


@pytest.mark.parametrize("xi", [0.05, 0.0])
def test_one_storey_displacement_peak_between_two_close_zeros(xi):
    w = 0.45 / DT  # one sub-step per record step (ρ·dt ≤ 0.5)
    acc = two_zero_record(w, xi)
    b = fs.ShearBuilding.from_period(stories=1, period=2 * np.pi / w, damping=xi)
    A, B = b.state_matrices()
    C, _, _ = b.output_matrices([1], "displacement")
    ref = linear_peaks(A, B[:, 0], C, acc, DT)[0]
    at_samples = np.abs(fs.floor_motions(b, acc, DT, floors=[1], output="displacement")).max()
    assert (ref - at_samples) / ref > 1e-5  # the peak is inside a step
    got = fs.peak_floor_acceleration(b, acc, DT, floors=[1], output="displacement")
    assert got.peak[0] == pytest.approx(ref, rel=1e-10)
