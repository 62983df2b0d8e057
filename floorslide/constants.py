"""Physical constants (docs/design.md §2)."""

G = 9.80665
"""Standard gravity, m/s²."""

MAX_LIST = 10_000
"""Longest list a user may give in one go — a sweep, a period grid, damping ratios — alike in
a scene, on the command line and in the Python API (a longer one is almost surely a typo, and
a period grid of 1e8 exhausted memory)."""
