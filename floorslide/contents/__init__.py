"""Contents: freestanding equipment sliding on floors (rigid blocks, 2-DOF sliding oscillator)
and the rocking-or-sliding check."""

from floorslide.contents.oscillator import OscillatorResult, slide_oscillator
from floorslide.contents.rocking import response_mode
from floorslide.contents.sliding import SlideResult, slide

__all__ = ["OscillatorResult", "SlideResult", "response_mode", "slide", "slide_oscillator"]
