"""One BLAS thread for floorslide's dense linear algebra, whoever calls it.

floorslide's matrices are small (a building's states, a batch of oscillators coupled to a
floor: tens to a few hundred rows); a multi-threaded BLAS gains nothing on them and, on a loaded
machine, loses a great deal — two OpenBLAS threads fighting for one core made an uncached
``response_spectrum(..., building=, floor=)`` take 6.6 s instead of 0.10 s, all in SciPy's
``expm``. ``floorslide run`` limits BLAS to one thread for the whole run; the functions here do
the same around each call from the Python API (notebooks, scripts), and restore the caller's
setting afterwards.
"""

from __future__ import annotations

import contextlib

import numpy as np
import scipy.linalg

_controller = None


def single_threaded_blas() -> contextlib.AbstractContextManager:
    """A context in which the BLAS libraries loaded in this process run one thread.

    The :class:`threadpoolctl.ThreadpoolController` (which finds the libraries, ~0.4 ms) is
    made once; entering and leaving the limit then costs ~12 µs.
    """
    global _controller
    if _controller is None:
        from threadpoolctl import ThreadpoolController

        _controller = ThreadpoolController()
    return _controller.limit(limits=1, user_api="blas")


def expm(a: np.ndarray) -> np.ndarray:
    """``scipy.linalg.expm`` (of a matrix or a stack of matrices) on one BLAS thread."""
    with single_threaded_blas():
        return scipy.linalg.expm(a)


def eigh(a: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``scipy.linalg.eigh(a, b)`` (generalised symmetric problem) on one BLAS thread."""
    with single_threaded_blas():
        return scipy.linalg.eigh(a, b)
