"""Rocking or sliding: which motion a freestanding rigid block starts (Shenton 1996).

A rigid block of base width ``B`` and height ``H`` (centre of mass at mid-height) on a floor with
static friction ``mu_s``, under a horizontal floor acceleration of peak ``a``:

- it rests while ``a ≤ mu_s·g`` and ``a ≤ g·B/H``;
- with ``mu_s < B/H`` it slides once ``a > mu_s·g`` (it would need ``g·B/H`` to tip);
- with ``mu_s > B/H`` it rocks once ``a > g·B/H`` (friction holds it up to ``mu_s·g``);
- with ``mu_s = B/H`` both start together (slide-rock).

References
----------
Shenton, H. W. (1996). Criteria for initiation of slide, rock, and slide-rock rigid-body modes.
*J. Eng. Mech.* 122(7), 690–693, Table 1 (pseudo-static criteria).
"""

from __future__ import annotations

import numpy as np

from floorslide.constants import G
from floorslide.errors import ModelError

MODES = ("rest", "slide", "rock", "slide-rock")


def response_mode(width: float, height: float, mu_s: float, peak_acc: float) -> str:
    """``"rest"``, ``"slide"``, ``"rock"`` or ``"slide-rock"`` for a block of `width` × `height`
    (m) with static friction `mu_s` under a floor whose peak absolute acceleration is `peak_acc`
    (m/s²).

    The ratio ``B/H`` is compared with ``mu_s`` to 1e-12 relative (equality means slide-rock).
    """
    for name, value in (("width", width), ("height", height)):
        if not (np.isfinite(value) and value > 0):
            raise ModelError(f"{name} must be > 0 m, got {value}", name)
    if not (np.isfinite(mu_s) and mu_s >= 0):
        raise ModelError(f"mu_s must be ≥ 0, got {mu_s}", "mu_s")
    if not (np.isfinite(peak_acc) and peak_acc >= 0):
        raise ModelError(f"peak_acc must be ≥ 0 m/s², got {peak_acc}", "peak_acc")
    slender = width / height
    slide_at, rock_at = mu_s * G, slender * G
    if abs(mu_s - slender) <= 1e-12 * slender:
        return "slide-rock" if peak_acc > slide_at else "rest"
    if mu_s < slender:
        return "slide" if peak_acc > slide_at else "rest"
    return "rock" if peak_acc > rock_at else "rest"
