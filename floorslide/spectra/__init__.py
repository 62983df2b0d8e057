"""Response spectra and floor response spectra, exact at any dt; RotD spectra of two horizontal
components."""

from floorslide.spectra.core import Spectrum, broaden, envelope, period_grid, response_spectrum
from floorslide.spectra.rotd import RotDSpectrum, rotd_spectrum

__all__ = [
    "RotDSpectrum",
    "Spectrum",
    "broaden",
    "envelope",
    "period_grid",
    "response_spectrum",
    "rotd_spectrum",
]
