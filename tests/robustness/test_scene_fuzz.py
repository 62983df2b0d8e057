"""Random edits of a valid scene: a valid scene or a SceneError with key paths, never a crash."""

from __future__ import annotations

import tomllib

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from floorslide.errors import SceneError
from floorslide.scene.schema import parse_scene
from tests.conftest import ROOT

CATALOG = (ROOT / "data" / "records" / "slammer" / "index.csv").as_posix()
BASE = tomllib.loads(
    (ROOT / "data" / "scenes" / "demo.toml")
    .read_text()
    .replace("../records/slammer/index.csv", CATALOG)
)
ODD_TEXT = st.one_of(
    st.sampled_from(["/", "a/b", ".", "..", "a\x00b", "\x01", "a\nb", " a", "a ", "a@b", "a:b"]),
    st.sampled_from(["\u200b", "\u00a0", "\u202e", "é", "機器", "x" * 64, "x" * 65]),
    st.text(alphabet=st.characters(codec="utf-8"), min_size=1, max_size=6),
)
"""Strings with the characters an id must not hold (separators, dots, control and invisible
characters) and ones it may (any script)."""
WEIRD = st.one_of(
    st.integers(-5, 5),
    st.floats(allow_nan=True, allow_infinity=True),
    st.text(max_size=8),
    ODD_TEXT,
    st.booleans(),
    st.lists(st.floats(-2, 10), max_size=3),
    st.just([]),
    st.dictionaries(st.text(max_size=3), st.integers(), max_size=2),
    st.sampled_from([10**7, 1e9, "all", "roof", ["a"], {"min": 1, "max": 2, "n": 10**9}]),
)


def paths(doc, prefix=()):
    if isinstance(doc, dict):
        for k, v in doc.items():
            yield (*prefix, k)
            yield from paths(v, (*prefix, k))
    elif isinstance(doc, list):
        for i, v in enumerate(doc):
            yield from paths(v, (*prefix, i))


ALL = list(paths(BASE))


def toml_value(v):
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, float):
        if v != v:
            return "nan"
        if v in (float("inf"), float("-inf")):
            return "inf" if v > 0 else "-inf"
        return repr(v)
    if isinstance(v, int):
        return str(v)
    if isinstance(v, str):
        return '"' + v.replace("\\", "\\\\").replace('"', '\\"').replace("\n", "\\n") + '"'
    if isinstance(v, list):
        return "[" + ", ".join(toml_value(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{" + ", ".join(f'"{k}" = {toml_value(x)}' for k, x in v.items()) + "}"
    raise TypeError(v)


def dump(doc) -> str:
    out = []
    for key, value in doc.items():
        if isinstance(value, list) and value and all(isinstance(x, dict) for x in value):
            for item in value:
                out.append(f"[[{key}]]")
                out += [f'"{k}" = {toml_value(v)}' for k, v in item.items()]
        elif isinstance(value, dict):
            out.append(f"[{key}]")
            out += [f'"{k}" = {toml_value(v)}' for k, v in value.items()]
        else:
            out.insert(0, f'"{key}" = {toml_value(value)}')
    return "\n".join(out) + "\n"


def edit(doc, path, value, delete):
    import copy

    doc = copy.deepcopy(doc)
    node = doc
    for p in path[:-1]:
        node = node[p]
    if delete:
        del node[path[-1]]
    else:
        node[path[-1]] = value
    return doc


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    which=st.lists(st.integers(0, len(ALL) - 1), min_size=1, max_size=3),
    values=st.lists(WEIRD, min_size=3, max_size=3),
    delete=st.lists(st.booleans(), min_size=3, max_size=3),
)
def test_random_edits_validate_cleanly(which, values, delete):
    doc = BASE
    for i, idx in enumerate(which):
        path = ALL[idx]
        try:
            doc = edit(doc, path, values[i], delete[i])
        except (KeyError, IndexError, TypeError):
            continue  # an earlier edit removed or replaced this path
    try:
        text = dump(doc)
    except TypeError:
        return
    try:
        scene = parse_scene(text, ROOT / "data" / "scenes" / "fuzz.toml")
    except SceneError as exc:
        assert exc.problems
        for p in exc.problems:
            assert ": " in p and "\n" not in p
        return
    assert scene.buildings  # a valid scene is a usable one


def test_a_list_as_the_isolator_model_is_a_key_path_error():
    """Found by the fuzz above (``model = []`` crashed with TypeError: a list is not a key)."""
    import pytest

    text = (
        (ROOT / "data" / "scenes" / "demo.toml")
        .read_text()
        .replace("../records/slammer/index.csv", CATALOG)
    )
    text = text.replace('model = "friction_pendulum"', "model = []")
    with pytest.raises(SceneError, match=r"buildings\[2\]\.isolator\.model: must be one of"):
        parse_scene(text, ROOT / "data" / "scenes" / "fuzz.toml")


IDS = [p for p in ALL if p[-1] in ("id", "set", "superstructure") and len(p) == 3]
"""Paths of the ids (and the references to them) of the base scene."""


def _usable_name(name: str) -> bool:
    """Whether `name` comes back unchanged as the only group of a fresh HDF5 group, and
    reads as an id: no separator of variants (``@``) or comparisons (``:``), no spaces at
    either end, printable."""
    import h5py

    if "@" in name or ":" in name or name != name.strip() or not name.isprintable():
        return False
    try:
        with h5py.File("ids.h5", "w", driver="core", backing_store=False) as f:
            f.create_group("g").create_group(name)
            return list(f["g"].keys()) == [name]
    except (ValueError, KeyError, TypeError):
        return False


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    which=st.lists(st.sampled_from(IDS), min_size=1, max_size=2),
    names=st.lists(ODD_TEXT, min_size=2, max_size=2),
)
def test_odd_ids_are_refused_or_name_result_groups(which, names):
    """An id with odd characters (``/``, ``.``, NUL, control, reserved separators) is a key-path
    error; an id the scene accepts is a usable group name of the result file."""
    doc = BASE
    for path, name in zip(which, names, strict=False):
        doc = edit(doc, path, name, False)
    try:
        scene = parse_scene(dump(doc), ROOT / "data" / "scenes" / "fuzz.toml")
    except SceneError as exc:
        for p in exc.problems:
            assert ": " in p and "\n" not in p
        return
    ids = [r.set for r in scene.records] + [b.base for b in scene.buildings]
    for name in ids + [c.id for c in scene.contents]:
        assert _usable_name(name), name
