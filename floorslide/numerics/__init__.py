"""Shared numerics of the exact solvers: polynomials inside a step (rigorous roots, extrema,
first crossings) and exact stepping of linear systems under piecewise-linear input."""
