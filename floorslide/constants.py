"""Physical constants (DESIGN §2)."""

G = 9.80665
"""Standard gravity, m/s²."""
