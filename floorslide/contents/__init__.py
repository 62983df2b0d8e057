"""Contents: freestanding equipment sliding on floors (rigid blocks, 2-DOF sliding oscillator)
and the rocking-or-sliding check."""

from floorslide.contents.sliding import SlideResult, slide

__all__ = ["SlideResult", "slide"]
