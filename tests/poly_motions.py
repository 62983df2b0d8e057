"""Poly motions for testing consumers (docs/design.md §16): closed-form harmonic motions as exact
degree-23 segments, and any motion recut into pieces as short as a building's events make."""

from __future__ import annotations

import math

import numpy as np

from floorslide.building.poly_segments import DEGREE, PolySegments, shift_rows


class Harmonic:
    """``a_x = A cos(Ωt + φ_x)``, ``a_y = A cos(Ωt + φ_y)`` (floor 0; a phase None: that
    component 0) as exact degree-23 Taylor segments of length `dt` (the terms beyond are below
    1e-28 of A for ``Ω·dt ≤ 0.63``)."""

    def __init__(self, A, om, dt, npts, phase_x=0.0, phase_y=-np.pi / 2):
        self.A, self.om, self.dt, self.npts = A, om, dt, npts
        self.phases = (phase_x, phase_y)
        self.floors = (0,)
        self.notes = ()

    def poly_chunks(self):
        k = np.arange(self.npts - 1, dtype=np.int64)
        th = self.om * k * self.dt
        j = np.arange(DEGREE)
        w = self.A * self.om**j / np.array([math.factorial(i) for i in j], dtype=float)
        coef = np.zeros((k.size, 1, 2, DEGREE))
        for d, ph in enumerate(self.phases):
            if ph is not None:
                coef[:, 0, d] = np.cos(th[:, None] + ph + j * np.pi / 2) * w
        ones = np.ones(k.size, dtype=bool)
        yield PolySegments(k * self.dt, np.full(k.size, self.dt), k, ones, coef, (0,), 0, k.size)


class Recut:
    """`motion` with every segment cut at the fractions `cuts` of its length, each polynomial
    re-expanded about its piece's start."""

    def __init__(self, motion, cuts):
        self.motion, self.cuts = motion, np.asarray(cuts, dtype=float)
        self.dt, self.npts = motion.dt, motion.npts
        self.floors, self.notes = motion.floors, motion.notes

    def poly_chunks(self):
        f = np.concatenate([[0.0], self.cuts])
        nxt = np.append(self.cuts, 1.0)
        for s in self.motion.poly_chunks():
            i = np.repeat(np.arange(s.nseg), f.size)
            off = np.tile(f, s.nseg) * s.length[i]
            end = np.tile(nxt, s.nseg) * s.length[i]
            last = np.tile(np.arange(f.size) == f.size - 1, s.nseg)
            yield PolySegments(s.t0[i] + off, end - off, s.step[i], s.ends[i] & last,
                               shift_rows(s.coef[i], off), s.floors, s.k0, s.k1)  # fmt: skip


class OneSegment:
    """A record of one step of length `L` whose ``x`` acceleration is the polynomial `coef`
    (``y``: `coef_y`, or 0): the polynomials as given, whatever their terms."""

    def __init__(self, coef, L, coef_y=None):
        self.coef = np.zeros((2, DEGREE))
        self.coef[0, : len(coef)] = coef
        if coef_y is not None:
            self.coef[1, : len(coef_y)] = coef_y
        self.dt, self.npts = float(L), 2
        self.floors = (0,)
        self.notes = ()

    def poly_chunks(self):
        coef = np.zeros((1, 1, 2, DEGREE))
        coef[0, 0] = self.coef
        one = np.array([0], dtype=np.int64)
        yield PolySegments(np.zeros(1), np.array([self.dt]), one, np.ones(1, dtype=bool), coef,
                           (0,), 0, 1)  # fmt: skip


class Counted:
    """`motion`, counting the passes consumers make over it (``poly_chunks()`` calls)."""

    def __init__(self, motion):
        self.motion, self.passes = motion, 0
        self.dt, self.npts = motion.dt, motion.npts
        self.floors, self.notes = motion.floors, motion.notes

    def poly_chunks(self):
        self.passes += 1
        yield from self.motion.poly_chunks()
