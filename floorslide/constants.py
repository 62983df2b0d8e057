"""Physical constants (docs/design.md §2)."""

G = 9.80665
"""Standard gravity, m/s²."""
