"""numba's ``njit`` for floorslide's kernels, with their disk cache kept out of the package.

Compiled kernels are cached on disk (``@njit(cache=True)``) so that a command-line call loads
them instead of compiling. numba's default is to write the cache into ``__pycache__`` folders
beside the sources — for an installed package, inside ``site-packages/floorslide/``. Those files
are not part of the installed distribution: ``pip uninstall`` leaves them behind, and the
orphaned ``floorslide/<package>/`` folders then act as namespace packages that shadow a later
editable install (``ModuleNotFoundError: floorslide.contents.sliding``).

floorslide's kernels are therefore cached in a per-user folder instead:

1. ``$FLOORSLIDE_CACHE_DIR`` if set;
2. else ``$XDG_CACHE_HOME/floorslide/numba`` (``~/.cache/floorslide/numba`` by default);
3. else, when that folder cannot be written, ``<tmp>/floorslide-numba-<user>``.

Under it, each source folder gets its own subfolder (named after the folder and a hash of its
absolute path), so an installed copy and a source tree never share cache files. A cached kernel
is stale when *any* of floorslide's kernel sources changed, not only its own file (numba's own
check): a kernel compiles the helpers it calls from other files into itself, so after an edit
of, say, ``numerics/polynomial.py`` numba would otherwise go on loading kernels that run the old
helper. The stamp is a SHA-256 of the contents of every source file that defines compiled
functions (:func:`kernel_sources_stamp`). A ``NUMBA_CACHE_DIR`` set by the user
takes precedence (numba's own locator is used then), as the benchmark's fresh-compile
measurement relies on. Only functions defined in floorslide's own source files are affected.
"""

from __future__ import annotations

import functools
import getpass
import hashlib
import os
import sys
import tempfile
from pathlib import Path

from numba import njit
from numba.core import caching, config

__all__ = ["cache_root", "kernel_sources_stamp", "njit"]

PACKAGE_DIR = Path(__file__).resolve().parent
"""The folder of the floorslide package whose functions are cached by this locator."""

# numba < 0.60 spells these with a leading underscore
_CacheImpl = getattr(caching, "CacheImpl", None) or caching._CacheImpl
_CacheLocator = caching._CacheLocator
_SourceBacked = getattr(caching, "_SourceFileBackedLocatorMixin", None)


def cache_root() -> Path:
    """The per-user folder of floorslide's compiled kernels (see the module docstring)."""
    given = os.environ.get("FLOORSLIDE_CACHE_DIR")
    if given:
        return Path(given).expanduser()
    xdg = os.environ.get("XDG_CACHE_HOME")
    base = Path(xdg).expanduser() if xdg else Path.home() / ".cache"
    return base / "floorslide" / "numba"


@functools.lru_cache(maxsize=4)
def kernel_sources_stamp(root: Path = PACKAGE_DIR) -> str:
    """SHA-256 of the contents of every source file under `root` that defines compiled kernels
    (imports ``floorslide._jit``), names included: the staleness stamp of every cached kernel."""
    digest = hashlib.sha256()
    for path in sorted(Path(root).rglob("*.py")):
        try:
            text = path.read_bytes()
        except OSError:  # pragma: no cover - unreadable: not part of the stamp
            continue
        if b"floorslide._jit import" in text or path.name == "_jit.py":
            digest.update(path.relative_to(root).as_posix().encode() + b"\0")
            digest.update(hashlib.sha256(text).digest())
    return digest.hexdigest()


def _fallback_root() -> Path:
    try:
        user = getpass.getuser()
    except (KeyError, OSError):  # pragma: no cover - no user name
        user = str(os.getuid()) if hasattr(os, "getuid") else "user"
    return Path(tempfile.gettempdir()) / f"floorslide-numba-{user}"


def _inside_package(py_file: str) -> bool:
    try:
        Path(py_file).resolve().relative_to(PACKAGE_DIR)
    except (ValueError, OSError):
        return False
    return True


class FloorslideCacheLocator(_SourceBacked, _CacheLocator):
    """numba cache locator for functions defined in floorslide's source files: a per-user
    folder, never the package's own folders."""

    def __init__(self, py_func, py_file, root: Path | None = None):
        self._py_file = py_file
        self._lineno = py_func.__code__.co_firstlineno
        tag = f"py{sys.version_info[0]}{sys.version_info[1]}"
        root = cache_root() if root is None else root
        self._cache_path = str(root / tag / self.get_suitable_cache_subpath(py_file))

    def get_cache_path(self) -> str:
        return self._cache_path

    def get_source_stamp(self) -> str:
        """Every kernel source, not only this function's file (see the module docstring)."""
        return kernel_sources_stamp()

    @classmethod
    def from_function(cls, py_func, py_file):
        if config.CACHE_DIR or not _inside_package(py_file) or not os.path.exists(py_file):
            return None  # the user's NUMBA_CACHE_DIR, or not ours: numba's own locators
        for root in (cache_root(), _fallback_root()):
            locator = cls(py_func, py_file, root)
            try:
                locator.ensure_cache_path()
            except OSError:
                continue
            return locator
        return None  # pragma: no cover - nothing writable: numba decides


def _register() -> None:
    classes = _CacheImpl._locator_classes
    if FloorslideCacheLocator not in classes:
        classes.insert(0, FloorslideCacheLocator)


_register()
