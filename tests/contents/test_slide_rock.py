"""Slide–rock (docs/design.md §10g): the two limits that are other solvers (a corner that never
slips is the rocking block, a block too squat to tip is the sliding block) on the ground and on
every kind of building, Shenton's (1996) initiation boundary, the energy balance, mirror
symmetry and bad input."""

from __future__ import annotations

import numpy as np
import pytest

import floorslide as fs
from floorslide.building.plane_isolation import PlaneIsolatedMotion
from floorslide.building.poly_peaks import PolyComponent
from floorslide.building.poly_segments import LinearPolyMotion
from floorslide.errors import ModelError
from tests.conftest import SLAMMER, G


@pytest.fixture(scope="module")
def kobe() -> np.ndarray:
    """Kobe KAK-000 scaled to 0.88 g, 25 s (blocks rock, slide and slide–rock on it)."""
    return np.loadtxt(SLAMMER / "Kobe_1995_KAK-000.txt")[:2500] * G * 3.5


@pytest.fixture(scope="module")
def elc() -> np.ndarray:
    return np.loadtxt(SLAMMER / "ImperialValley_1940_ELC-180.txt") * G


def superstructure():
    return fs.ShearBuilding.from_period(stories=2, period=0.4, damping=0.03)


# (width, height) of blocks that rock: slender, stocky
WIDTHS = np.array([0.3, 0.5, 0.6])
HEIGHTS = np.array([1.5, 1.5, 1.2])


def assert_rocks_as(sr, ro, tol=1e-12):
    """A slide–rock result whose corner never slipped equals the rocking block's."""
    alpha = ro.alpha[:, None]
    np.testing.assert_array_equal(sr.mode_time[:, 1] + sr.mode_time[:, 3], 0.0)
    np.testing.assert_array_equal(sr.peak_slide, 0.0)
    np.testing.assert_array_equal(sr.overturned, ro.overturned)
    np.testing.assert_array_equal(sr.impacts, ro.impacts)
    np.testing.assert_allclose(sr.peak_ratio, ro.peak_ratio, rtol=0, atol=tol)
    np.testing.assert_allclose(sr.theta / alpha, ro.theta / alpha, rtol=0, atol=tol)
    np.testing.assert_allclose(sr.overturn_time, ro.overturn_time, rtol=tol)
    np.testing.assert_allclose(sr.mode_time[:, 2], ro.rocking_time, rtol=1e-9)


def test_a_corner_that_never_slips_rocks_as_the_rocking_block(kobe):
    """mu = 100: the friction always holds the corner — fs.rock's full equation, to rounding,
    overturning included. The two split the steps into different parts, so their rounding
    differs: 3e-21·α on a block that barely rocks, 1.6e-10·α (measured) on one that rocks to
    0.96 α, where rocking amplifies it through hundreds of impacts — hence 1e-9 here."""
    sr = fs.slide_rock(kobe, 0.01, WIDTHS, HEIGHTS, 100.0, histories=True)
    ro = fs.rock(kobe, 0.01, WIDTHS, HEIGHTS, method="nonlinear", histories=True)
    assert ro.overturned.any() and (~ro.overturned).any() and (ro.impacts > 2).all()
    assert_rocks_as(sr, ro, tol=1e-9)
    assert all(m in ("rock", "overturn") for m in sr.mode)


@pytest.mark.parametrize("where", ["fixed", "isolated", "lead-rubber", "pendulum-pair"])
def test_never_slipping_on_buildings(elc, where):
    """The same limit on the roof of a fixed-base, a linearly isolated and a lead-rubber
    building, and on a friction-pendulum building's roof under a pair (a PolyComponent): the
    rocking block reads the same floor polynomials."""
    sup = superstructure()
    W, H = np.array([0.08, 0.12]), np.array([1.0, 1.0])
    if where == "pendulum-pair":
        b = fs.NonlinearIsolatedBuilding(sup, 1.0, fs.FrictionPendulum(mu=0.05, period=3.0))
        motion = PlaneIsolatedMotion(b, elc, 0.6 * elc[::-1].copy(), 0.01)
        pc = PolyComponent(motion, 2, 0)
        sr = fs.slide_rock(pc, None, W, H, 100.0, histories=True)
        ro = fs.rock(pc, None, W, H, method="nonlinear", histories=True)
    else:
        if where == "fixed":
            b = sup
        elif where == "isolated":
            b = fs.IsolatedBuilding(sup, 1.0, 2.5, 0.1)
        else:
            b = fs.NonlinearIsolatedBuilding(
                sup, 1.0, fs.BilinearIsolator(q_ratio=0.05, period=2.5, yield_disp=0.01)
            )
        sr = fs.slide_rock(elc, 0.01, W, H, 100.0, building=b, floor=2, histories=True)
        ro = fs.rock(elc, 0.01, W, H, building=b, floor=2, method="nonlinear", histories=True)
    assert ((ro.impacts > 0) | ro.overturned).all() and (ro.impacts > 0).any()
    assert_rocks_as(sr, ro, tol=1e-9)


def assert_slides_as(sr, sl, tol=1e-12):
    """A slide–rock result of a block too squat to tip equals the sliding block's."""
    np.testing.assert_array_equal(sr.mode_time[:, 2:], 0.0)
    np.testing.assert_array_equal(sr.peak_ratio, 0.0)
    scale = np.max(np.abs(sl.u))
    np.testing.assert_allclose(sr.peak_slide, sl.peak_slide, rtol=0, atol=tol * scale)
    np.testing.assert_allclose(sr.residual_slide, sl.residual_slide, rtol=0, atol=tol * scale)
    np.testing.assert_allclose(sr.slide, sl.u, rtol=0, atol=tol * scale)
    np.testing.assert_allclose(sr.mode_time[:, 1], sl.slide_fraction * sl.duration, rtol=1e-9)


@pytest.mark.parametrize("where", ["ground", "fixed", "lead-rubber"])
def test_a_block_too_squat_to_tip_slides_as_the_sliding_block(kobe, elc, where):
    """b/h > mu_s: the block slides and never tips (mu_k h < b) — fs.slide with its static and
    kinetic friction, to rounding, on the ground and on buildings."""
    mk, ms = np.array([0.15, 0.2, 0.3]), np.array([0.2, 0.2, 0.35])
    W, H = 1.0, 1.0
    if where != "ground":
        mk, ms = mk / 4, ms / 4
    if where == "ground":
        sr = fs.slide_rock(kobe, 0.01, W, H, mk, mu_s=ms, histories=True)
        sl = fs.slide(kobe, 0.01, mk, mu_s=ms, histories=True)
    else:
        sup = superstructure()
        b = (
            sup
            if where == "fixed"
            else fs.NonlinearIsolatedBuilding(
                sup, 1.0, fs.BilinearIsolator(q_ratio=0.05, period=2.5, yield_disp=0.01)
            )
        )
        sr = fs.slide_rock(elc, 0.01, W, H, mk, mu_s=ms, building=b, floor=2, histories=True)
        sl = fs.slide(elc, 0.01, mk, mu_s=ms, building=b, floor=2, histories=True)
    assert (sl.peak_slide > 0).all()
    assert_slides_as(sr, sl)
    assert sr.mode == ("slide",) * 3


def mu_c(a: float, lam: float) -> float:
    """Shenton's (1996) friction that pure rocking needs at its onset from rest under a floor
    acceleration ``a·g``, for ``λ = b/h`` — written from the paper's criterion in (a, λ), not
    from floorslide's forces."""
    return (a * (4 * lam**2 + 1) + 3 * lam) / (lam**2 + 4 + 3 * a * lam)


def initial_mode(a: float, lam: float, mu_s: float, mu_k: float) -> str:
    """The mode a block starts in when the floor jumps to ``−a·g`` (a 2-sample record of
    1e-5 s: it has no time to leave the mode it starts in)."""
    acc = np.array([-a * G, -a * G])
    r = fs.slide_rock(acc, 1e-5, 2 * lam, 2.0, mu_k, mu_s=mu_s)
    return ("rest", "slide", "rock", "slide-rock")[int(np.argmax(r.mode_time[0]))]


@pytest.mark.parametrize("lam", [0.2, 0.4, 0.7])
@pytest.mark.parametrize("ratio", [1.05, 1.5, 2.0, 3.0])
def test_shenton_boundary(lam, ratio):
    """The boundary table of Shenton (1996) at (λ, a/g = ratio·λ): just above μ_c the block
    rocks, just below it slides and rocks (mu_k > λ) or slides (mu_k ≤ λ); below λ it slides,
    and below both levels it rests."""
    a = ratio * lam
    mc = mu_c(a, lam)
    assert mc > lam  # the friction needed grows with the acceleration
    assert initial_mode(a, lam, mc * (1 + 1e-9), mc * (1 + 1e-9)) == "rock"
    below = mc * (1 - 1e-9)
    if below > lam:
        assert initial_mode(a, lam, below, below) == "slide-rock"
        assert initial_mode(a, lam, below, 0.99 * lam) == "slide"
    assert initial_mode(a, lam, 0.9 * lam, 0.9 * lam) == "slide"
    assert initial_mode(0.99 * min(a, lam), lam, lam * 1.5, lam * 1.5) == "rest"


def test_the_mode_at_the_first_sample_is_the_one_the_block_starts_in():
    """A record that starts beyond the rest level starts the mode at t = 0: the mode history's
    first sample says so (θ and the slide are still 0 there)."""
    acc = np.full(50, -0.5 * G)
    r = fs.slide_rock(acc, 0.01, [1.0, 0.3, 0.3], 1.0, [0.2, 0.5, 0.5], mu_s=[0.2, 0.5, 0.5],
                      histories=True)  # fmt: skip
    assert r.mode_history[:, 0].tolist() == [1, 2, 2]  # slide (B/H > mu_s), rock, rock
    assert (r.theta[:, 0] == 0).all() and (r.slide[:, 0] == 0).all()
    still = fs.slide_rock(np.zeros(5), 0.01, 0.3, 1.0, 0.5, histories=True)
    assert still.mode_history[0].tolist() == [0] * 5


def test_shenton_limit_values():
    """μ_c = λ at a = λ (rocking starts with the friction static equilibrium needs) and tends
    to (1 + 4λ²)/(3λ) for a large acceleration (Shenton 1996)."""
    for lam in (0.2, 0.5, 1.0):
        assert mu_c(lam, lam) == pytest.approx(lam, rel=1e-14)
        assert mu_c(1e9, lam) == pytest.approx((1 + 4 * lam**2) / (3 * lam), rel=1e-8)


def test_energy_balance_through_every_mode(kobe):
    """E_end − E_0 = W_floor − W_friction − W_impacts (§10g) to rounding, for blocks that go
    through rest, rock and slide–rock (and overturn): a wrong term of any mode's equations or
    of the impact would break it far above rounding."""
    W = np.array([0.4, 0.3, 0.6, 0.5])
    H = np.array([1.6, 1.5, 1.2, 1.0])
    mk = np.array([0.26, 0.22, 0.45, 0.55])
    ms = np.array([0.3, 0.22, 0.55, 0.6])
    r = fs.slide_rock(kobe, 0.01, W, H, mk, mu_s=ms, energy=True, histories=True)
    assert (r.mode_time[:, 3] > 0).sum() >= 3  # slide–rock happens
    dE, w_floor, w_fric, w_imp = r.energy.T
    assert (w_fric > 0).any() and (w_imp > 0).all()
    np.testing.assert_allclose(dE, w_floor - w_fric - w_imp, rtol=0, atol=1e-12 * w_floor.max())
    # accounting the energy (the contact forces on every part) changes nothing else
    plain = fs.slide_rock(kobe, 0.01, W, H, mk, mu_s=ms, histories=True)
    assert np.isnan(plain.energy).all()
    for name in ("theta", "slide", "mode_time", "peak_slide", "peak_ratio", "impacts"):
        np.testing.assert_array_equal(getattr(plain, name), getattr(r, name))


def test_mirror_symmetry(kobe):
    """The record reversed in sign mirrors the block: θ and U change sign, nothing else."""
    kw = dict(mu_s=np.array([0.3, 0.55]), histories=True)
    a = fs.slide_rock(kobe, 0.01, [0.4, 0.6], [1.6, 1.2], [0.26, 0.45], **kw)
    b = fs.slide_rock(-kobe, 0.01, [0.4, 0.6], [1.6, 1.2], [0.26, 0.45], **kw)
    np.testing.assert_array_equal(a.theta, -b.theta)
    np.testing.assert_array_equal(a.slide, -b.slide)
    np.testing.assert_array_equal(a.mode_time, b.mode_time)
    np.testing.assert_array_equal(a.mode_history, b.mode_history)


def test_results_describe_the_modes(kobe):
    """mode, sequence, entries and histories agree with each other."""
    r = fs.slide_rock(kobe, 0.01, 0.6, 1.2, 0.45, mu_s=0.55, histories=True)
    assert r.mode == ("slide-rock",)
    assert r.sequence[0].startswith("rest 0 → rock ")
    assert "slide-rock" in r.sequence[0]
    assert r.mode_entries[0, 3] >= 1 and r.mode_entries[0, 2] >= r.mode_entries[0, 3]
    codes = set(np.unique(r.mode_history[0]).tolist())
    assert {0, 2} <= codes
    np.testing.assert_allclose(r.mode_time.sum(), r.duration, rtol=1e-12)
    rec = r.to_records()[0]
    assert rec["mode"] == "slide-rock" and rec["time_slide_rock"] > 0


@pytest.mark.parametrize(
    "kwargs, key",
    [
        (dict(mu=0.3, mu_s=0.2), "mu_s"),
        (dict(mu=-0.1), "mu"),
        (dict(mu=None), "mu"),
        (dict(mu=0.3, width=-1.0), "width"),
        (dict(mu=0.3, vertical=np.zeros(10)), "vertical"),
        (dict(mu=0.3, direction="positive"), "direction"),
        (dict(mu=0.3, method="rk2"), "method"),
        (dict(mu=0.3, restitution=1.5), "restitution"),
    ],
)
def test_bad_input_is_one_line_naming_the_key(kwargs, key):
    acc = np.sin(np.linspace(0, 10, 10)) * 3.0
    args = dict(width=0.5, height=1.0)
    args.update(kwargs)
    with pytest.raises(ModelError) as e:
        fs.slide_rock(acc, 0.01, args.pop("width"), args.pop("height"), args.pop("mu"), **args)
    assert e.value.where == key
    assert "\n" not in str(e.value)


def test_a_linear_poly_motion_is_read_as_the_linear_building(elc):
    """A LinearPolyMotion's floor along x (a PolyComponent) gives what building= gives."""
    sup = superstructure()
    pm = LinearPolyMotion(sup, elc, 0.5 * elc, 0.01, floors=[2])
    a = fs.slide_rock(PolyComponent(pm, 2, 0), None, 0.5, 1.2, 0.45, mu_s=0.5)
    b = fs.slide_rock(elc, 0.01, 0.5, 1.2, 0.45, mu_s=0.5, building=sup, floor=2)
    np.testing.assert_array_equal(a.peak_ratio, b.peak_ratio)
    np.testing.assert_array_equal(a.peak_slide, b.peak_slide)
