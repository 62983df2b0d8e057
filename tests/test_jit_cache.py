"""floorslide's compiled kernels are cached in a per-user folder, never inside the package (files
left there by numba survive ``pip uninstall`` and shadow a later editable install)."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

from numba.core import config

from floorslide._jit import PACKAGE_DIR, FloorslideCacheLocator, cache_root
from floorslide.contents._kernels import slide_kernel
from tests.conftest import ROOT


def test_cache_root_follows_environment(monkeypatch, tmp_path):
    monkeypatch.setenv("FLOORSLIDE_CACHE_DIR", str(tmp_path / "c"))
    assert cache_root() == tmp_path / "c"
    monkeypatch.delenv("FLOORSLIDE_CACHE_DIR")
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    assert cache_root() == tmp_path / "xdg" / "floorslide" / "numba"


def test_locator_outside_the_package(monkeypatch, tmp_path):
    monkeypatch.setenv("FLOORSLIDE_CACHE_DIR", str(tmp_path))
    monkeypatch.setattr(config, "CACHE_DIR", "")
    func = slide_kernel.py_func
    loc = FloorslideCacheLocator.from_function(func, func.__code__.co_filename)
    path = Path(loc.get_cache_path())
    assert tmp_path in path.parents
    assert PACKAGE_DIR not in path.parents


def test_user_numba_cache_dir_wins(monkeypatch, tmp_path):
    monkeypatch.setattr(config, "CACHE_DIR", str(tmp_path))
    func = slide_kernel.py_func
    assert FloorslideCacheLocator.from_function(func, func.__code__.co_filename) is None


def test_not_for_other_packages(monkeypatch):
    monkeypatch.setattr(config, "CACHE_DIR", "")
    assert FloorslideCacheLocator.from_function(test_not_for_other_packages, __file__) is None


def test_a_kernel_call_writes_nothing_into_the_package(tmp_path):
    code = (
        "import numpy as np\n"
        "from floorslide.building._instep import poly_val\n"
        "print(poly_val(np.array([1.0, 2.0]), 1, 0.5))\n"
    )
    env = dict(os.environ, PYTHONPATH=str(ROOT), FLOORSLIDE_CACHE_DIR=str(tmp_path))
    env.pop("NUMBA_CACHE_DIR", None)
    before = {str(p) for p in PACKAGE_DIR.rglob("*.nb[ic]")}
    out = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, env=env, timeout=900
    )
    assert out.returncode == 0, out.stderr
    assert list(tmp_path.rglob("*.nbi")), "no kernel cached in FLOORSLIDE_CACHE_DIR"
    after = {str(p) for p in PACKAGE_DIR.rglob("*.nb[ic]")}
    assert after == before == set()


def test_a_kernel_is_stale_when_any_kernel_source_changes(tmp_path):
    """numba's own check looks at a kernel's own file only; a kernel compiled against an older
    helper from another file (e.g. numerics/polynomial.py) must not be loaded (issue 20)."""
    from floorslide._jit import FloorslideCacheLocator, kernel_sources_stamp

    root = tmp_path / "pkg"
    (root / "numerics").mkdir(parents=True)
    (root / "kern.py").write_text("from floorslide._jit import njit\\n")
    helper = root / "numerics" / "helper.py"
    helper.write_text("from floorslide._jit import njit\\nX = 1\\n")
    (root / "cli.py").write_text("print('no kernels here')\\n")
    before = kernel_sources_stamp(root)
    (root / "cli.py").write_text("print('still none')\\n")
    kernel_sources_stamp.cache_clear()
    assert kernel_sources_stamp(root) == before  # a file without kernels does not count
    helper.write_text("from floorslide._jit import njit\\nX = 2\\n")  # same size, new content
    kernel_sources_stamp.cache_clear()
    assert kernel_sources_stamp(root) != before
    kernel_sources_stamp.cache_clear()
    func = slide_kernel.py_func
    loc = FloorslideCacheLocator.from_function(func, func.__code__.co_filename)
    if loc is not None:  # not under a user's NUMBA_CACHE_DIR
        assert loc.get_source_stamp() == kernel_sources_stamp()
