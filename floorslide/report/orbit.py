"""The bearing orbit figure: the path of a bearing in the plane under two components
(:func:`floorslide.building.plane_isolation.plane_isolator_response`), with its peak and, when
given, its displacement capacity as a circle — optionally beside the uncoupled model's path
(:func:`floorslide.building.plane_isolation_approx.uncoupled_plane_isolator_response`)."""

from __future__ import annotations

import numpy as np


def plot_bearing_orbit(response, *, uncoupled=None, capacity: float | None = None,
                       title: str = "", path=None):  # fmt: skip
    """Draw the bearing's orbit (mm; x along ``h1``, y along ``h2``) with its peak marked and
    the capacity circle (red when exceeded).

    Parameters
    ----------
    response
        A :class:`~floorslide.building.plane_isolation.PlaneIsolatorResponse` (or any object
        with ``displacement`` ``(npts, 2)``, ``peak_displacement`` and ``peak_direction``).
    uncoupled
        The per-direction model's response, drawn dashed beside it.
    capacity
        The bearing's displacement capacity, m (default: none drawn).
    title
        The figure's title.
    path
        Where to save the PNG (default: not saved).

    Returns
    -------
    matplotlib.figure.Figure
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    u = 1000.0 * np.asarray(response.displacement)
    fig, ax = plt.subplots(figsize=(5.2, 5.2))
    ax.plot(u[:, 0], u[:, 1], lw=0.9, color="C0", label="coupled (friction circle)")
    if uncoupled is not None:
        w = 1000.0 * np.asarray(uncoupled.displacement)
        ax.plot(w[:, 0], w[:, 1], lw=0.8, ls="--", color="C1", label="uncoupled (per direction)")
    peak = 1000.0 * response.peak_displacement
    th = np.radians(response.peak_direction)
    ax.plot([peak * np.cos(th)], [peak * np.sin(th)], "o", color="C0", ms=5,
            label=f"peak {peak:.0f} mm at {response.peak_direction:.0f}°")  # fmt: skip
    reach = max(peak, np.abs(u).max())
    if capacity is not None:
        c = 1000.0 * capacity
        phi = np.linspace(0.0, 2.0 * np.pi, 361)
        over = peak > c
        ax.plot(c * np.cos(phi), c * np.sin(phi), color="C3" if over else "0.4", lw=1.0,
                label=f"capacity {c:.0f} mm" + (" — exceeded" if over else ""))  # fmt: skip
        reach = max(reach, c)
    lim = 1.08 * reach if reach > 0 else 1.0
    ax.set_xlim(-lim, lim)
    ax.set_ylim(-lim, lim)
    ax.set_aspect("equal")
    ax.axhline(0.0, color="0.85", lw=0.6, zorder=0)
    ax.axvline(0.0, color="0.85", lw=0.6, zorder=0)
    ax.set_xlabel("bearing displacement along h1 (mm)")
    ax.set_ylabel("along h2 (mm)")
    if title:
        ax.set_title(title, fontsize=10)
    ax.legend(loc="lower left", fontsize=8, frameon=False)
    fig.tight_layout()
    if path is not None:
        fig.savefig(path, dpi=110)
    return fig
