"""The bearing orbit figure (floorslide/report/orbit.py): it draws the orbit it is given, in mm,
and the capacity circle, red when the peak exceeds it."""

from __future__ import annotations

import numpy as np
from matplotlib.colors import to_rgb

from floorslide.report.orbit import plot_bearing_orbit


class _Response:
    def __init__(self, u):
        self.displacement = u
        r = np.hypot(u[:, 0], u[:, 1])
        i = int(np.argmax(r))
        self.peak_displacement = float(r[i])
        self.peak_direction = float(np.degrees(np.arctan2(u[i, 1], u[i, 0])))


def test_the_orbit_and_the_capacity_are_drawn(tmp_path):
    t = np.linspace(0.0, 6.0, 601)
    u = np.stack([0.3 * np.sin(t), 0.1 * np.sin(2 * t)], axis=1)
    r = _Response(u)
    fig = plot_bearing_orbit(r, uncoupled=_Response(0.9 * u), capacity=0.25,
                             path=tmp_path / "o.png")  # fmt: skip
    ax = fig.axes[0]
    orbit, other, peak, circle = ax.lines[:4]
    np.testing.assert_allclose(orbit.get_xdata(), 1000 * u[:, 0])
    np.testing.assert_allclose(orbit.get_ydata(), 1000 * u[:, 1])
    np.testing.assert_allclose(other.get_xdata(), 900 * u[:, 0])
    np.testing.assert_allclose(np.hypot(circle.get_xdata(), circle.get_ydata()), 250.0)
    assert to_rgb(circle.get_color()) == to_rgb("C3")  # 300 mm > 250 mm: exceeded
    assert "exceeded" in circle.get_label()
    at = np.hypot(peak.get_xdata()[0], peak.get_ydata()[0])
    assert abs(at - 1000 * r.peak_displacement) < 1e-9
    assert (tmp_path / "o.png").stat().st_size > 0
    fig2 = plot_bearing_orbit(r, capacity=1.0)
    assert to_rgb(fig2.axes[0].lines[-1].get_color()) != to_rgb("C3")
