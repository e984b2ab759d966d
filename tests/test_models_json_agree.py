"""`roughdiffuse models --json`, the Python classes' defaults and the explorer's /api/models
say the same thing (issue 13: one declaration per model)."""

from __future__ import annotations

import dataclasses
import json
import urllib.request

import pytest

from conftest import all_models
from roughdiffuse import registry
from roughdiffuse.cli import main
from roughdiffuse.explorer import make_server, serve_in_thread


@pytest.fixture(scope="module")
def api_models() -> list[dict]:
    server = make_server()
    serve_in_thread(server)
    try:
        host, port = server.server_address[:2]
        with urllib.request.urlopen(f"http://{host}:{port}/api/models", timeout=30) as r:
            assert r.headers["Content-Type"] == "application/json"
            return json.loads(r.read())
    finally:
        server.shutdown()
        server.server_close()


def test_cli_json_equals_the_explorer_api(api_models, capsys):
    assert main(["models", "--json"]) == 0
    # the explorer adds its own fields: the printed shader and the page's state keys
    explorer_only = {"shader", "state_keys"}
    assert all(explorer_only <= set(r) for r in api_models)
    api = [{k: v for k, v in r.items() if k not in explorer_only} for r in api_models]
    assert json.loads(capsys.readouterr().out) == api


@pytest.mark.parametrize("model_id", registry.ids())
def test_json_defaults_are_the_python_defaults(api_models, model_id):
    """Each JSON default is the value the class itself takes when the parameter is omitted."""
    rec = {r["id"]: r for r in api_models}[model_id]
    entry = registry.get(model_id)
    built = entry.create()  # nothing given: the class's own defaults
    if dataclasses.is_dataclass(built) and not hasattr(entry.cls, "from_params"):
        fields = {f.name: f.default for f in dataclasses.fields(entry.cls)}
        for p in rec["parameters"]:
            value = getattr(built, p["name"])
            assert value == pytest.approx(p["default"]), p["name"]
            if fields[p["name"]] is not None:  # a conditional field is None until resolved
                assert fields[p["name"]] == pytest.approx(p["default"]), p["name"]
    else:  # Mix: the factory's keyword defaults
        import inspect

        sig = inspect.signature(entry.cls.from_params)
        for p in rec["parameters"]:  # one that exists only for some choices: None (unset)
            assert sig.parameters[p["name"]].default == (None if p["when"] else p["default"])


def test_every_package_model_is_in_the_test_matrix():
    """The test matrix (tests/conftest.all_models) is built from the registry: every
    closed-form model of the package is in it."""
    tested = {type(m) for m in all_models()}
    for e in registry.entries():
        if e.source == "roughdiffuse" and e.cls.closed_form:
            # SmithDiffuse (Monte Carlo) and VCavity (tabulated: closed_form =
            # False, no differentiable parameters, not for the fast path) have their own tests
            # (test_smith_diffuse_model.py, test_models_vcavity.py) instead of the matrix,
            # which differentiates parameters and compiles every model
            assert e.cls in tested, e.id
