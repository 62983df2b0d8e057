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
WEIRD = st.one_of(
    st.integers(-5, 5),
    st.floats(allow_nan=True, allow_infinity=True),
    st.text(max_size=8),
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
