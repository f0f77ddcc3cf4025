"""The Python front end against the library's options table
(crates/penumbra/src/scene/options.rs): every list of render options here,
the keyword arguments, their signatures and stubs, and the flags of
`python -m penumbra`, must be the table's."""

from __future__ import annotations

import ast
import inspect
import re
import subprocess
import sys
from pathlib import Path

import pytest

import penumbra
from penumbra import _penumbra

FLAGS = _penumbra._OPTION_FLAGS
STUB = Path(_penumbra.__file__).with_name("_penumbra.pyi")
ANNOTATIONS = {
    "int": "int | None",
    "float": "float | None",
    "bool": "bool | None",
    "distribution": "DistributionName | None",
    "filter": "FilterName | None",
    "stop_rule": "StopRuleName | None",
    "integrator": "IntegratorName | None",
    "path_sampler": "PathSamplerName | None",
    "light_sampler": "LightSamplerName | None",
    "path": "PointSets | None",
}
VALID = {
    "int": 2,
    "float": 0.5,
    "bool": True,
    "distribution": "poisson",
    "filter": "tent",
    "stop_rule": "cycles",
    "integrator": "whitted",
    "path_sampler": "sobol",
    "light_sampler": "power",
    "path": "points.json",
}


def test_render_options_are_the_tables_and_progress():
    assert [f["name"] for f in FLAGS] + ["progress"] == list(penumbra.RENDER_OPTIONS)


#: The arguments of a progressive render, after the render options.
PROGRESSIVE = ["time_limit", "checkpoint", "checkpoint_interval", "resume", "on_pass"]


@pytest.mark.parametrize("func", [penumbra.render, penumbra.render_region])
def test_signatures_list_every_option(func):
    params = inspect.signature(func).parameters.values()
    keywords = [p.name for p in params if p.kind is p.KEYWORD_ONLY]
    assert keywords == list(penumbra.RENDER_OPTIONS) + PROGRESSIVE


def _stub(name: str) -> ast.FunctionDef:
    cls, _, func = name.rpartition(".")
    body = ast.parse(STUB.read_text()).body
    if cls:
        body = next(n for n in body if isinstance(n, ast.ClassDef) and n.name == cls).body
    return next(n for n in body if isinstance(n, ast.FunctionDef) and n.name == func)


@pytest.mark.parametrize("name", ["render", "render_region", "Scene.settings"])
def test_stubs_type_every_option(name):
    stub = {a.arg: ast.unparse(a.annotation) for a in _stub(name).args.kwonlyargs}
    progressive = PROGRESSIVE if name != "Scene.settings" else []
    assert list(stub) == list(penumbra.RENDER_OPTIONS) + progressive
    for f in FLAGS:
        assert stub[f["name"]] == ANNOTATIONS[f["kind"]], f["name"]


@pytest.mark.parametrize("flag", FLAGS, ids=lambda f: f["name"])
def test_every_option_is_accepted_and_checked(flag):
    _penumbra._check_options(**{flag["name"]: VALID[flag["kind"]]})
    with pytest.raises(TypeError, match=flag["name"]):
        _penumbra._check_options(**{flag["name"]: object()})


def _flags(help_text: str) -> set[str]:
    return set(re.findall(r"(?<![\w-])--[a-z][a-z-]*", help_text))


def test_the_binary_and_python_m_penumbra_have_the_tables_flags(cli: Path):
    expected = {f["flag"] for f in FLAGS} | {f["off_flag"] for f in FLAGS if f["off_flag"]}
    binary = subprocess.run([str(cli), "render", "--help"], capture_output=True, text=True, check=True)
    # --max-file-size and --simd are the binary's global flags, not render options
    # (python -m penumbra takes $PENUMBRA_MAX_FILE_SIZE and $PENUMBRA_SIMD, as its workers do);
    # --define, --search, --sensor and --lenient set how a Mitsuba XML scene is read, which only the
    # binary reads.
    # --time-limit, --checkpoint, --checkpoint-interval and --resume are both's (checked below).
    progressive = {"--time-limit", "--checkpoint", "--checkpoint-interval", "--resume"}
    binary_others = {"--output", "--stats", "--bunny", "--quiet", "--help", "--max-file-size", "--simd", "--define",
                     "--search", "--sensor", "--lenient", *progressive}
    # --preview and --bind serve the binary's live view in a browser;
    # --display-server streams it to tev.
    binary_others |= {"--preview", "--bind", "--display-server"}
    assert _flags(binary.stdout) - binary_others == expected
    module = subprocess.run(
        [sys.executable, "-m", "penumbra", "render", "--help"], capture_output=True, text=True, check=True
    )
    others = {"--output", "--scheduler", "--local-workers", "--tile", "--retries", "--stats", "--bunny",
              "--quiet", "--help", "--tiles-dir", *progressive}
    assert _flags(module.stdout) - others == expected
    assert progressive <= _flags(binary.stdout) and progressive <= _flags(module.stdout)
