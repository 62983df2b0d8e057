"""The Python API runs its dense linear algebra on one BLAS thread (issue 17): an uncached
floor spectrum called from a script took 6.6 s instead of 0.10 s on a loaded machine, all in
SciPy's ``expm`` with two OpenBLAS threads fighting. Only ``floorslide run`` limited them."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg
from threadpoolctl import threadpool_info, threadpool_limits

import floorslide as fs


def _blas_threads() -> set[int]:
    return {i["num_threads"] for i in threadpool_info() if i["user_api"] == "blas"}


@pytest.fixture
def two_blas_threads():
    """BLAS set to two threads around the test (the caller's own setting), or a skip where
    no BLAS library that threadpoolctl can steer is loaded."""
    if not _blas_threads():
        pytest.skip("no BLAS library visible to threadpoolctl")
    with threadpool_limits(limits=2, user_api="blas"):
        if _blas_threads() != {2}:
            pytest.skip(f"BLAS here does not take two threads ({_blas_threads()})")
        yield


@pytest.fixture
def expm_spy(monkeypatch):
    """Record the BLAS thread counts in effect at every call of ``scipy.linalg.expm``."""
    seen: list[set[int]] = []
    real = scipy.linalg.expm

    def spy(a, *args, **kwargs):
        seen.append(_blas_threads())
        return real(a, *args, **kwargs)

    monkeypatch.setattr(scipy.linalg, "expm", spy)
    return seen


def _record() -> tuple[np.ndarray, float]:
    t = np.arange(600) * 0.01
    return 2.0 * np.sin(2 * np.pi * 1.3 * t) * np.exp(-0.2 * t), 0.01


def test_floor_spectrum_runs_expm_on_one_blas_thread(two_blas_threads, expm_spy):
    acc, dt = _record()
    rng = np.random.default_rng()  # fresh periods and building: nothing cached
    b = fs.ShearBuilding.from_period(stories=2, period=0.4 + 0.1 * rng.random(), damping=0.05)
    periods = np.sort(0.05 + 2.0 * rng.random(12))
    fs.response_spectrum(acc, dt, periods, [0.05], building=b, floor=2)
    assert expm_spy, "the uncached floor spectrum called no expm: the spy sees nothing"
    assert all(s == {1} for s in expm_spy), expm_spy
    assert _blas_threads() == {2}, "the caller's BLAS setting is restored"


def test_building_motion_runs_expm_on_one_blas_thread(two_blas_threads, expm_spy):
    acc, dt = _record()
    rng = np.random.default_rng()
    fixed = fs.ShearBuilding.from_period(stories=3, period=0.5 + 0.1 * rng.random(), damping=0.03)
    b = fs.IsolatedBuilding(fixed, 1.0, 2.0 + rng.random(), 0.1)
    fs.building_motion(b, acc, dt).peaks([3])
    assert expm_spy
    assert all(s == {1} for s in expm_spy), expm_spy
    assert _blas_threads() == {2}
