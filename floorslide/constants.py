"""Physical constants (docs/design.md §2)."""

G = 9.80665
"""Standard gravity, m/s²."""

MAX_LIST = 10_000
"""Longest list a user may give in one go — a sweep, a period grid, damping ratios — alike in
a scene, on the command line and in the Python API (a longer one is almost surely a typo, and
a period grid of 1e8 exhausted memory)."""

MAX_ACCELERATION = 1e5 * G
"""Largest acceleration (m/s²; 100 000 g) a solver takes as a sample of a record (scaled or
not). The strongest ground motions recorded are a few g; far beyond, the solvers' arithmetic
(powers of rates times accelerations in the in-step Taylor polynomials, their products in the
event searches) overflows float64 and a response comes out as NaN or, worse, as "no slide".
Readers and ``inspect`` still take such a record (its measures say what overflows)."""
