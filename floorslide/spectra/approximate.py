"""Approximate response spectra, kept for the accuracy-versus-cost study (docs/design.md §6).

- ``samples``: the exact recurrence, but peaks read at the samples only;
- ``newmark``: Newmark average acceleration (γ = 1/2, β = 1/4) at ``dt/substeps``;
- ``fft``: the oscillator's frequency response applied to the FFT of the zero-padded record;
- ``reinterpolated``: the exact solver applied to floor samples joined by straight lines.

On a floor, all but ``reinterpolated`` start from exact samples of the floor motion.
"""

from __future__ import annotations

import numpy as np

from floorslide._jit import njit
from floorslide.building.exact_motion import single_use_motion
from floorslide.spectra.core import _exact, _sdof_recurrence, floor_samples


def spectra(a, dt, T, Z, building, floor, method, substeps):
    """sd, sv, sa of shape (len(Z), len(T)) by an approximate method."""
    if method == "reinterpolated":
        af = floor_samples(a, dt, building, floor)
        return _exact(single_use_motion(None, af, dt, None), T, Z)
    k = substeps if method == "newmark" else 1
    af = floor_samples(a, dt, building, floor, oversample=k)
    h = dt / k
    pos = T > 0
    TT, ZZ = np.meshgrid(T[pos], Z)
    w = 2 * np.pi / TT.ravel()
    xi = ZZ.ravel()
    out = np.zeros((w.size, 3))
    if method == "samples":
        E = _sdof_recurrence(w, xi, h)
        _recurrence_peaks(af, *E, w, xi, out)
    elif method == "newmark":
        _newmark_peaks(af, h, w, xi, out)
    elif method == "fft":
        _fft_peaks(af, h, w, xi, out)
    sd = np.zeros((Z.size, T.size))
    sv = np.zeros_like(sd)
    sa = np.zeros_like(sd)
    sd[:, pos] = out[:, 0].reshape(Z.size, -1)
    sv[:, pos] = out[:, 1].reshape(Z.size, -1)
    sa[:, pos] = out[:, 2].reshape(Z.size, -1)
    sa[:, ~pos] = np.abs(af).max()
    return sd, sv, sa


@njit(cache=True)
def _recurrence_peaks(af, P, p, q, w, xi, out):
    for o in range(w.size):
        x0 = 0.0
        x1 = 0.0
        pd = pv = pa = 0.0
        for k in range(af.size - 1):
            y0 = P[o, 0, 0] * x0 + P[o, 0, 1] * x1 + p[o, 0] * af[k] + q[o, 0] * af[k + 1]
            y1 = P[o, 1, 0] * x0 + P[o, 1, 1] * x1 + p[o, 1] * af[k] + q[o, 1] * af[k + 1]
            x0, x1 = y0, y1
            pd = max(pd, abs(x0))
            pv = max(pv, abs(x1))
            pa = max(pa, abs(w[o] * w[o] * x0 + 2 * xi[o] * w[o] * x1))
        out[o, 0], out[o, 1], out[o, 2] = pd, pv, pa


@njit(cache=True)
def _newmark_peaks(af, h, w, xi, out):
    """Newmark average acceleration, incremental form (Chopra 2012, Table 5.4.2)."""
    for o in range(w.size):
        k = w[o] * w[o]
        c = 2 * xi[o] * w[o]
        kh = k + 2.0 / h * c + 4.0 / (h * h)
        u = 0.0
        v = 0.0
        acc = -af[0]
        pd = pv = pa = 0.0
        for i in range(af.size - 1):
            dp = -(af[i + 1] - af[i]) + (4.0 / h + 2.0 * c) * v + 2.0 * acc
            du = dp / kh
            dv = 2.0 / h * du - 2.0 * v
            u += du
            v += dv
            acc = -af[i + 1] - c * v - k * u
            pd = max(pd, abs(u))
            pv = max(pv, abs(v))
            pa = max(pa, abs(k * u + c * v))
        out[o, 0], out[o, 1], out[o, 2] = pd, pv, pa


def _fft_peaks(af, h, w, xi, out):
    n = af.size
    nfft = 1 << int(np.ceil(np.log2(n + int(4 * (2 * np.pi / w.min()) / h) + 1)))
    nfft = min(nfft, 1 << 24)
    F = np.fft.rfft(af, nfft)
    om = 2 * np.pi * np.fft.rfftfreq(nfft, h)
    for o in range(w.size):
        H = -1.0 / (w[o] ** 2 - om**2 + 2j * xi[o] * w[o] * om)
        u = np.fft.irfft(F * H, nfft)[:n]
        v = np.fft.irfft(F * H * 1j * om, nfft)[:n]
        out[o, 0] = np.abs(u).max()
        out[o, 1] = np.abs(v).max()
        out[o, 2] = np.abs(w[o] ** 2 * u + 2 * xi[o] * w[o] * v).max()
