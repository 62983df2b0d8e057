"""Scenes: schema, loading, validation, the planner."""
