"""The exact nonlinear-isolation solver against the independent event-located DOP853 reference
(tests/reference_isolators.py) on real records: every output within 1e-8."""

from __future__ import annotations

import numpy as np
import pytest

import floorslide as fs
from floorslide.building.isolators import BilinearIsolator, FrictionPendulum
from floorslide.building.nonlinear import NonlinearIsolatedBuilding, isolator_response
from tests.conftest import SLAMMER, G
from tests.reference_isolators import isolated_response

RECORDS = {
    "ELC-180": ("ImperialValley_1940_ELC-180.txt", 0.01, 1000),
    "RRS-228": ("Northridge_1994_RRS-228.txt", 0.01, 800),
    "YER-270": ("Landers_1992_YER-270.txt", 0.02, 1400),
}


def reference_isolator(b: NonlinearIsolatedBuilding) -> dict:
    c = b.constants
    if b.kind == "bilinear":
        return {"kind": "bilinear", "k1": c["k1"], "k2": c["k2"], "Q": c["Q"], "c": c["c"]}
    return {"kind": "friction_pendulum", "R": c["R"], "mu": c["mu"], "mu_s": c["mu_s"], "c": c["c"]}


CASES = {
    "bilinear": BilinearIsolator(q_ratio=0.06, period=2.5, yield_disp=0.02),
    "bilinear-damped": BilinearIsolator(q_ratio=0.04, period=3.0, alpha=0.1, damping=0.05),
    "pendulum": FrictionPendulum(mu=0.06, period=3.0),
    "pendulum-static": FrictionPendulum(mu=0.05, mu_s=0.08, radius=2.5),
}


@pytest.mark.parametrize("record", list(RECORDS))
@pytest.mark.parametrize("case", list(CASES))
def test_against_the_reference(record, case):
    name, dt, n = RECORDS[record]
    acc = np.loadtxt(SLAMMER / name)[:n] * G * 1.5  # strong enough to yield and slide
    sup = fs.ShearBuilding.from_period(stories=2, period=0.4, damping=0.03)
    b = NonlinearIsolatedBuilding(sup, 1.0, CASES[case])
    r = isolator_response(b, acc, dt)
    ref = isolated_response(
        b.mass, b.stiffness_matrix, b.damping_matrix, reference_isolator(b), acc, dt, rtol=1e-13
    )
    assert len(r.event_times) > 5  # the layer does change branch
    scale_u = np.abs(ref["u"][:, 0]).max()
    np.testing.assert_allclose(r.isolator_displacement, ref["u"][:, 0], rtol=0, atol=1e-8 * scale_u)
    scale_a = np.abs(ref["a_abs"]).max()
    np.testing.assert_allclose(r.floor_acceleration, ref["a_abs"].T, rtol=0, atol=1e-8 * scale_a)
    scale_f = np.abs(ref["f_iso"]).max()
    np.testing.assert_allclose(r.isolator_force, ref["f_iso"], rtol=0, atol=1e-8 * scale_f)
    assert r.peak_displacement == pytest.approx(ref["peak_isolator"], rel=1e-8)
    assert r.residual_displacement == pytest.approx(ref["residual_isolator"], abs=1e-8 * scale_u)
    # the reference takes the force at the samples and at its events, on the branch *after*
    # each event; the supremum includes the side before: sliding into a stop,
    # (W/R)|u0| + mu·W, and stuck up to a breakaway, (W/R)|u0| + mu_s·W — and, with viscous
    # damping, peaks between those points, which only the exact solver finds
    sup_ref = ref["peak_force_ratio"]
    if b.kind == "friction_pendulum":
        c = b.constants
        u_ref = ref["u"][:, 0]
        for (t, kind), u in zip(ref["events"], ref["event_u0"], strict=True):
            k = min(int(t / dt), u_ref.size - 2)
            if kind == "slip":  # the friction pointed the way the mat then moves
                side = c["mu_s"] * np.sign(u_ref[k + 1] - u)
            else:  # the way it moved into the stop
                side = c["mu"] * np.sign(u - u_ref[k])
            sup_ref = max(sup_ref, abs(c["k"] * u + side * c["W"]) / c["W"])
    if b.constants["c"] == 0.0:
        assert r.peak_force_ratio == pytest.approx(sup_ref, rel=1e-8)
    else:
        assert sup_ref * (1 - 1e-8) <= r.peak_force_ratio <= sup_ref * (1 + 1e-3)
    # the true PFA is at least every sample of the reference, and not above it by more than
    # what lies between samples
    assert np.all(r.pfa >= np.abs(ref["a_abs"]).max(axis=0) * (1 - 1e-8))
