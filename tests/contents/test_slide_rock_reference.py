"""The slide–rock reference (tests/reference_sliderock.py, design §10g) against the closed forms
and independent references it must reproduce: Housner's rocking block where friction never
lets go (tests/reference_rocking.py, full equation), the Coulomb sliding block where the block
is too squat to rock (tests/reference.py), Shenton's (1996) classification from rest at
``μ_c`` derived here from Newton's laws, and the energy balance on real records."""

from __future__ import annotations

import math

import numpy as np
import pytest

from floorslide.constants import G
from tests.conftest import load_slammer
from tests.reference import rigid_block_ground
from tests.reference_rocking import rock_reference
from tests.reference_sliderock import (
    OVERTURNED,
    REST,
    ROCK,
    SLIDE,
    SLIDE_ROCK,
    critical_friction,
    slide_rock_reference,
)

ROCKERS = {
    # file, samples, width, height, scale
    "elc": ("ImperialValley_1940_ELC-180.txt", 1500, 0.3, 1.2, 1.0),
    "kobe": ("Kobe_1995_KAK-000.txt", 2000, 0.25, 1.2, 1.0),
    "elc-overturns": ("ImperialValley_1940_ELC-180.txt", 1500, 0.3, 1.2, 2.0),
}


@pytest.mark.parametrize("key", list(ROCKERS))
def test_huge_friction_is_housners_rocking_block(key):
    name, n, width, height, scale = ROCKERS[key]
    acc, dt = load_slammer(name)
    acc = acc[:n] * scale
    ref = rock_reference(acc, dt, width=width, height=height, method="nonlinear")
    sr = slide_rock_reference(acc, dt, width, height, mu_k=100.0)
    alpha = ref["alpha"]
    assert ref["impacts"] > 10 or ref["overturned"]
    assert sr["impacts"] == ref["impacts"]
    assert sr["overturned"] == ref["overturned"]
    np.testing.assert_array_equal(np.isnan(sr["theta"]), np.isnan(ref["theta"]))
    ok = ~np.isnan(ref["theta"])
    assert np.max(np.abs(sr["theta"][ok] - ref["theta"][ok])) <= 1e-10 * alpha
    assert abs(sr["peak_ratio"] - ref["peak_ratio"]) <= 1e-10
    assert sr["mode_time"][ROCK] == pytest.approx(ref["rocking_time"], rel=1e-10)
    assert sr["mode_time"][SLIDE] == sr["mode_time"][SLIDE_ROCK] == 0.0
    assert sr["peak_slide"] == 0.0
    rocking = (sr["mode"] == ROCK) & ok
    np.testing.assert_array_equal(rocking, ok & (ref["theta"] != 0.0))
    if ref["overturned"]:
        assert sr["overturn_time"] == pytest.approx(ref["t_overturn"], rel=1e-10)
        assert (sr["mode"][~ok] == OVERTURNED).all()
    else:
        total = (acc.size - 1) * dt
        assert math.fsum(sr["mode_time"]) == pytest.approx(total, rel=1e-13)


SLIDERS = {
    # file, samples, width, height, mu_k, mu_s (tan α = width/height > mu_s)
    "elc": ("ImperialValley_1940_ELC-180.txt", 1500, 0.6, 1.0, 0.15, 0.2),
    "petrolia": ("CapeMendocino_1992_PET-090.txt", 1000, 0.5, 1.2, 0.2, 0.3),
    "kobe mu_s=mu_k": ("Kobe_1995_KAK-000.txt", 2000, 1.0, 1.0, 0.1, 0.1),
}


@pytest.mark.parametrize("key", list(SLIDERS))
def test_squat_block_is_the_coulomb_sliding_block(key):
    name, n, width, height, mu_k, mu_s = SLIDERS[key]
    acc, dt = load_slammer(name)
    acc = acc[:n]
    peak, residual = rigid_block_ground(acc, dt, mu_k, mu_s)
    sr = slide_rock_reference(acc, dt, width, height, mu_k, mu_s)
    assert peak > 1e-3
    assert abs(sr["peak_slide"] - peak) <= 1e-10 * peak
    assert abs(sr["residual_slide"] - residual) <= 1e-10 * peak
    assert sr["impacts"] == 0 and sr["peak_ratio"] == 0.0
    assert sr["mode_time"][ROCK] == sr["mode_time"][SLIDE_ROCK] == 0.0
    assert sr["mode_time"][SLIDE] > 10 * dt
    assert set(np.unique(sr["mode"])) == {REST, SLIDE}
    np.testing.assert_array_equal(sr["theta"], 0.0)


def onset_friction(a: float, width: float, height: float) -> float:
    """``|F| / N`` at the onset of rocking from rest under a floor acceleration ``-a g``, from
    Newton's laws for the block on its corner (θ = θ' = 0): ``I_O θ'' = m g R (a cos α - sin α)``
    with ``I_O = 4 m R²/3``, then the contact force from the centre of mass's acceleration."""
    b, h = width / 2, height / 2
    R, alpha = math.hypot(b, h), math.atan2(b, h)
    thdd = G * R * (a * math.cos(alpha) - math.sin(alpha)) / (4 * R * R / 3)
    # the centre of mass, at (-R sin u, R cos u) from the corner, u = alpha - θ
    ax, ay = R * math.cos(alpha) * thdd, R * math.sin(alpha) * thdd
    F = ax - a * G  # horizontal: m a_x = F - m a_f, a_f = -a g
    N = ay + G  # vertical: m a_y = N - m g
    return abs(F) / N


SHENTON = [
    # width, height, a = |a_f|/g
    (0.6, 1.2, 0.8),
    (0.4, 1.2, 0.5),
    (1.0, 1.2, 1.5),
]


@pytest.mark.parametrize(("width", "height", "a"), SHENTON)
def test_from_rest_follows_shentons_criterion(width, height, a):
    lam = width / height
    mu_c = critical_friction(a, lam)
    assert mu_c == pytest.approx(onset_friction(a, width, height), rel=1e-13)
    assert lam < mu_c < (1 + 4 * lam * lam) / (3 * lam)
    acc = np.full(3, -a * G)  # constant, beyond the level from t = 0: s = σ = +1
    dt = 0.005

    def start(mu_k, mu_s):
        r = slide_rock_reference(acc, dt, width, height, mu_k, mu_s)
        return r["mode"][0], r

    mode, r = start(lam * 1.05, mu_c * (1 + 1e-6))
    assert mode == ROCK and r["theta"][1] > 0.0 and r["events"][0] == (0.0, "rock")
    mode, r = start(lam * 1.05, mu_c * (1 - 1e-6))
    assert mode == SLIDE_ROCK and r["theta"][1] > 0.0 and r["slide"][1] > 0.0
    mode, r = start(lam * 0.95, mu_c * (1 - 1e-6))
    assert mode == SLIDE and r["theta"][1] == 0.0 and r["slide"][1] > 0.0
    mode, r = start(lam * 0.9, lam * 0.95)
    assert mode == SLIDE
    below = slide_rock_reference(np.full(3, -0.999 * lam * G), dt, width, height, lam, 2 * lam)
    assert (below["mode"] == REST).all()
    # the mirror: a positive floor acceleration tips the block the other way
    r = slide_rock_reference(-acc, dt, width, height, lam * 1.05, mu_c * (1 + 1e-6))
    assert r["mode"][0] == ROCK and r["theta"][1] < 0.0


def test_at_rest_below_the_level():
    acc = np.full(4, -0.49 * G)
    r = slide_rock_reference(acc, 0.01, 0.6, 1.2, 0.5, 0.6)  # level g·min(0.6, 0.5)
    assert (r["mode"] == REST).all() and r["mode_time"][REST] == pytest.approx(0.03)


ENERGY = {
    # file, samples, width, height, mu_k, mu_s: every mode visited
    "petrolia all modes": ("CapeMendocino_1992_PET-090.txt", 1000, 0.3, 1.2, 0.22, 0.27),
    "petrolia long slide-rock": ("CapeMendocino_1992_PET-090.txt", 1000, 0.3, 1.2, 0.25, 0.26),
    "elc": ("ImperialValley_1940_ELC-180.txt", 1500, 0.3, 1.2, 0.25, 0.26),
}


@pytest.mark.parametrize("key", list(ENERGY))
def test_energy_balance(key):
    name, n, width, height, mu_k, mu_s = ENERGY[key]
    acc, dt = load_slammer(name)
    r = slide_rock_reference(acc[:n], dt, width, height, mu_k, mu_s)
    e = r["energy"]
    assert r["mode_time"][SLIDE_ROCK] > 0.05 and r["impacts"] > 10
    if key == "petrolia all modes":
        assert (r["mode_time"] > 0.1).all()
    assert e["W_friction"] > 0.0 and e["W_impacts"] > 0.0
    balance = e["W_floor"] - e["W_friction"] - e["W_impacts"] - e["delta_E"]
    assert abs(balance) <= 1e-9 * e["W_floor"]


def test_energy_balance_on_a_roof():
    import floorslide as fs

    building = fs.ShearBuilding.from_period(stories=1, period=0.3, damping=0.03)
    ss = building.state_space(floors=[1])
    system = (np.asarray(ss.A), np.asarray(ss.B)[:, 0], np.asarray(ss.C)[0], float(ss.D[0, 0]))
    acc, dt = load_slammer("ImperialValley_1940_ELC-180.txt")
    r = slide_rock_reference(acc[:600], dt, 0.3, 1.2, 0.22, 0.27, floor_system=system)
    e = r["energy"]
    assert r["mode_time"][SLIDE_ROCK] > 0.0 and r["impacts"] > 0
    balance = e["W_floor"] - e["W_friction"] - e["W_impacts"] - e["delta_E"]
    assert abs(balance) <= 1e-9 * e["W_floor"]


def test_impact_rule_conserves_angular_momentum_about_the_new_corner():
    """Every impact loses the kinetic energy the rough impact must lose with Housner's ``r``:
    the sum equals ``W_impacts`` and is positive; with ``r = 1`` an impact at ``V = 0`` loses
    nothing, so a stuck rocker on ``r = 1`` keeps all its energy through its impacts."""
    acc, dt = load_slammer("ImperialValley_1940_ELC-180.txt")
    r = slide_rock_reference(acc[:800], dt, 0.3, 1.2, 100.0, restitution=1.0)
    e = r["energy"]
    assert r["impacts"] > 0
    assert abs(e["W_impacts"]) <= 1e-14 * e["W_floor"]
    assert abs(e["W_floor"] - e["delta_E"]) <= 1e-9 * e["W_floor"]


def test_painleve_and_bad_input_raise():
    with pytest.raises(ValueError, match="mu_k <= mu_s"):
        slide_rock_reference(np.zeros(3), 0.01, 0.3, 1.2, 0.3, 0.2)
    with pytest.raises(RuntimeError, match=r"Painlevé case at t = 0\.0131"):
        # a violent pulse: the rock's friction limit is reached as N falls, and slide-rock
        # with mu_k = 100 is the Painlevé case
        acc = np.r_[-60.0 * G * np.ones(3), 60 * G * np.ones(20)]
        slide_rock_reference(acc, 0.01, 0.2, 1.2, 100.0)
