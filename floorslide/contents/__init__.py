"""Contents: freestanding equipment sliding on floors (rigid blocks, 2-DOF sliding oscillator)
and the rocking-or-sliding check."""

from floorslide.contents.coupled import CoupledSlideResult, slide_coupled
from floorslide.contents.oscillator import OscillatorResult, slide_oscillator
from floorslide.contents.plane import PlaneSlideResult, slide_plane
from floorslide.contents.plane_oscillator import PlaneOscillatorResult, slide_oscillator_plane
from floorslide.contents.rocking import response_mode
from floorslide.contents.rocking_block import RockResult, rock
from floorslide.contents.slide_rock import SlideRockResult, slide_rock
from floorslide.contents.sliding import SlideResult, slide

__all__ = [
    "CoupledSlideResult",
    "OscillatorResult",
    "PlaneOscillatorResult",
    "PlaneSlideResult",
    "RockResult",
    "SlideResult",
    "SlideRockResult",
    "response_mode",
    "rock",
    "slide",
    "slide_coupled",
    "slide_oscillator",
    "slide_oscillator_plane",
    "slide_plane",
    "slide_rock",
]
