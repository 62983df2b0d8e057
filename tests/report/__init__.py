"""Tests of the design tables and figures (floorslide.report)."""
