"""Scene values that are valid but almost surely a mistake are warned about by key path;
scene conveniences a user expects (docs/design.md §4)."""

from __future__ import annotations

from floorslide.scene.schema import parse_scene
from tests.conftest import ROOT
from tests.scene.test_schema import GOOD


def test_friction_given_as_a_percentage_warns_by_key_path():
    text = GOOD.replace("mu = [0.1, 0.2]\nmu_s = 0.25", "mu = [10, 0.2]\nmu_s = 20")
    sc = parse_scene(text, ROOT / "x.toml")
    assert sc.contents[0].mu == (10.0, 0.2)  # valid: warned, not refused
    assert sc.warnings == (
        "contents[0].mu[0]: friction coefficient 10 is implausible (dry friction is below "
        "about 1); did you mean 0.10?",
        "contents[0].mu_s: friction coefficient 20 is implausible (dry friction is below "
        "about 1); did you mean 0.20?",
    )


def test_allowable_in_cm_warns_that_it_is_in_metres():
    text = GOOD.replace("mu = 0.2\n", "mu = 0.2\nallowable = [0.05, 10]\n", 1)
    sc = parse_scene(text, ROOT / "x.toml")
    assert sc.warnings == (
        "contents[1].allowable[1]: allowable displacement 10 m is implausible (the value is in "
        "m); did you mean 0.1 (10 cm) or 0.01 (10 mm)?",
    )
    ok = parse_scene(GOOD.replace("mu = 0.2\n", "mu = 0.2\nallowable = 0.1\n", 1), ROOT / "x.toml")
    assert ok.warnings == ()


def test_floor_lists_mix_numbers_and_roof():
    text = GOOD.replace(
        "floors = [1, 2]\nmu = [0.1, 0.2]", 'floors = [0, 1, "roof"]\nmu = [0.1, 0.2]'
    )
    sc = parse_scene(text.replace('floors = "all"', 'floors = [0, "roof"]'), ROOT / "x.toml")
    assert sc.contents[0].floors_of(2) == (0, 1, 2) and sc.contents[0].floors_of(5) == (0, 1, 5)
    assert sc.spectra.floors_of(3) == (0, 3)
    twice = parse_scene(text.replace('[0, 1, "roof"]', '[2, "roof"]'), ROOT / "x.toml")
    assert twice.contents[0].floors_of(2) == (2,)  # the roof named twice is one floor


def test_a_floor_name_other_than_roof_is_one_error_by_key_path():
    import pytest

    from floorslide.errors import SceneError

    text = GOOD.replace("floors = [1, 2]\nmu = [0.1, 0.2]", 'floors = [1, "top"]\nmu = [0.1, 0.2]')
    with pytest.raises(SceneError, match=r"contents\[0\]\.floors\[1\]: must be a floor number, "
                       r"'roof' or 'all', got 'top'"):  # fmt: skip
        parse_scene(text, ROOT / "x.toml")


PENDULUM = """
[[buildings]]
id = "fps"
kind = "isolated"
superstructure = "fb1"
{period}
isolator = {{ model = "friction_pendulum", mu = 0.05, {radius} }}
"""


def _pendulum_scene(period: str, radius: str) -> str:
    return GOOD.replace("\n[[contents]]", PENDULUM.format(period=period, radius=radius)
                        + "\n[[contents]]", 1)  # fmt: skip


def test_a_pendulum_by_its_radius_has_the_period_two_pi_root_r_over_g():
    import math

    sc = parse_scene(_pendulum_scene("", "radius = 2.0"), ROOT / "x.toml")
    (fps,) = [b for b in sc.buildings if b.base == "fps"]
    assert fps.period == 2 * math.pi * math.sqrt(2.0 / 9.80665)  # 2.8375 s
    assert fps.build().isolator.R == __import__("pytest").approx(2.0, rel=1e-12)
    both = parse_scene(_pendulum_scene("period = 2.8375", "radius = 2.0"), ROOT / "x.toml")
    assert [b.period for b in both.buildings if b.base == "fps"] == [2.8375]


def test_a_pendulum_radius_that_contradicts_its_period_is_refused():
    import pytest

    from floorslide.errors import SceneError

    with pytest.raises(SceneError, match=r"buildings\[3\]\.isolator\.radius: R = 2 m gives the "
                       r"pendulum period 2π√\(R/g\) = 2\.837 s, but period = 3 s; give one of "
                       r"radius and period"):  # fmt: skip
        parse_scene(_pendulum_scene("period = 3.0", "radius = 2.0"), ROOT / "x.toml")


def test_storey_heights_one_per_storey_or_one_for_all():
    import pytest

    from floorslide.errors import SceneError

    text = GOOD.replace('id = "fb1"\nkind = "fixed"\nstories = 2', 'id = "fb1"\nkind = "fixed"\n'
                        'stories = 2\nstorey_heights = [4.5, 3.0]')  # fmt: skip
    sc = parse_scene(text, ROOT / "x.toml")
    fb1 = next(b for b in sc.buildings if b.id == "fb1")
    assert fb1.storey_heights == (4.5, 3.0)
    assert next(b for b in sc.buildings if b.base == "iso").storey_heights == (4.5, 3.0)
    with pytest.raises(SceneError, match=r"buildings\[1\]\.storey_heights: 3 heights \(one per "
                       r"storey\) for 2 storeys"):  # fmt: skip
        parse_scene(text.replace("[4.5, 3.0]", "[4.5, 3.0, 3.0]"), ROOT / "x.toml")


def test_the_rocking_key_is_warned_about_and_ignored():
    """Rocking objects are slide–rock blocks with the full equations (docs/design.md §10g): a
    scene that still chooses the rocking equation is told, by key path, and runs."""
    text = GOOD.replace("mu = 0.2\n", 'mu = 0.2\nwidth = 0.4\nheight = 1.6\nrocking = "exact"\n', 1)
    sc = parse_scene(text, ROOT / "x.toml")
    assert sc.warnings == (
        "contents[1].rocking: no longer applies in a study: rocking objects are simulated as "
        "slide–rock blocks with the full equations (docs/design.md §10g); the key is ignored",
    )
    plain = GOOD.replace("mu = 0.2\n", "mu = 0.2\nwidth = 0.4\nheight = 1.6\n", 1)
    assert parse_scene(plain, ROOT / "x.toml").warnings == ()
