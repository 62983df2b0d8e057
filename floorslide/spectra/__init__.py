"""Response spectra and floor response spectra, exact at any dt."""

from floorslide.spectra.core import Spectrum, broaden, envelope, period_grid, response_spectrum

__all__ = ["Spectrum", "broaden", "envelope", "period_grid", "response_spectrum"]
