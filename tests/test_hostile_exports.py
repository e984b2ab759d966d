"""An export carries everything, or refuses: categorical values written, each parameter as
the plugin reads it, each target's output checked by its own library, text escaped by the
format's rules."""

from __future__ import annotations

import json

import pytest

from roughdiffuse import registry
from roughdiffuse.cli import main
from roughdiffuse.exporters import blender_run
from roughdiffuse.exporters.common import python_comment_lines, rgb_of, xml_comment_text
from roughdiffuse.exporters.mitsuba import bsdf_dict


def run(argv: list[str]) -> int:
    try:
        return main(argv)
    except SystemExit as exc:
        return int(exc.code)


@pytest.fixture(autouse=True)
def no_blender(monkeypatch):
    monkeypatch.delenv(blender_run.ENV, raising=False)
    monkeypatch.setattr(blender_run, "_beside_package", lambda: [])


def test_categorical_values_are_written_and_a_scalar_albedo_is_a_float():
    vc = bsdf_dict(registry.create("v-cavity", bounces="1", measure="angle"))
    assert vc["bounces"] == "1" and vc["measure"] == "angle"
    assert isinstance(vc["albedo"], float)  # the plugin reads a float, not an rgb
    ls = bsdf_dict(registry.create("lambert-sphere", variant="fast"))
    assert ls["variant"] == "fast" and ls["albedo"]["type"] == "rgb"


def test_lambert_sphere_scene_carries_its_variant_and_loads(tmp_path, capsys):
    pytest.importorskip("mitsuba")
    out = tmp_path / "s.xml"
    argv = ["export", "--model", "lambert-sphere", "--param", "variant=fast",
            "--to", "mitsuba", "-o", str(out)]  # fmt: skip
    assert run(argv) == 0
    assert '<string name="variant" value="fast"/>' in out.read_text()
    assert "variant=fast" in capsys.readouterr().out  # the summary says it too


def test_a_scene_mitsuba_cannot_load_is_refused():
    pytest.importorskip("mitsuba")
    from roughdiffuse.exporters.mitsuba import check_scenes, scene_xml

    bad = {"type": "roughdiffuse_v_cavity", "albedo": {"type": "rgb", "value": [0.8] * 3}}
    with pytest.raises(ValueError, match="does not load"):
        check_scenes([scene_xml(bad, [])])


@pytest.mark.parametrize(
    ("model", "says"),
    [("smith-diffuse-ggx", "no Mitsuba plugin"), ("coated", "cannot"), ("mix", "cannot")],
)
def test_models_mitsuba_cannot_hold_are_refused_in_one_line(tmp_path, capsys, model, says):
    out = tmp_path / "s.xml"
    assert run(["export", "--model", model, "--to", "mitsuba", "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert says in err and len(err.strip().splitlines()) == 1 and "Error" not in err
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("channels", [2, 4])
@pytest.mark.parametrize(("target", "suffix"), [("mitsuba", ".xml"), ("materialx", ".mtlx"),
                                                ("blender", ".py"), ("gltf", ".glb"),
                                                ("glsl", ".glsl")])  # fmt: skip
def test_a_four_channel_albedo_is_refused_by_every_target(
    tmp_path, capsys, target, suffix, channels
):
    """GLSL too: it wrote a vec3 of the first three channels of four."""
    record = tmp_path / "fit.json"
    albedo = [0.1, 0.2, 0.3, 0.4][:channels]
    record.write_text(json.dumps({"model": "eon", "params": {"albedo": albedo,
                                                             "roughness": 0.3}}))  # fmt: skip
    out = tmp_path / f"m{suffix}"
    assert run(["export", "--from", str(record), "--to", target, "-o", str(out)]) == 2
    assert f"albedo has {channels} channels" in capsys.readouterr().err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["fit.json"]


def test_rgb_of_takes_one_or_three_values():
    assert rgb_of(0.5) == [0.5] * 3 and rgb_of([0.1, 0.2, 0.3]) == [0.1, 0.2, 0.3]
    for bad in ([0.1, 0.2], [0.1] * 4):
        with pytest.raises(ValueError, match="channels"):
            rgb_of(bad)


@pytest.mark.parametrize("text", ["--->", "a -- b", "x -", "--", "- - -", "<!-- -->"])
def test_xml_comment_text_never_holds_a_double_hyphen_or_ends_in_one(text):
    safe = xml_comment_text(text)
    assert "--" not in safe and not safe.endswith("-")


def test_a_materialx_document_with_hostile_comments_validates():
    pytest.importorskip("MaterialX")
    from roughdiffuse.exporters.materialx import check_document, document

    text = document({"albedo": 0.5, "roughness": 0.3}, True, ["evil ---> <tag/> -", "x\n-->"])
    assert check_document(text) is None


@pytest.mark.parametrize("text", ["Class\nimport os; os.system('x')", "a\rb", "a\u2028b", ""])
def test_python_comment_lines_keep_every_line_a_comment(text):
    lines = python_comment_lines(text)
    assert all(line.startswith("# ") for line in lines)
    compiled = compile("\n".join(lines) + "\n", "t.py", "exec")
    assert compiled.co_names == ()  # nothing but comments


def test_blender_script_with_a_newline_in_a_comment_is_still_only_comments(tmp_path):
    from roughdiffuse.exporters.blender import script

    text = script({"albedo": 0.5, "roughness": 0.2}, ["OrenNayar\nraise SystemExit('pwned')"])
    code = compile(text, "m.py", "exec")
    assert "SystemExit" not in code.co_names


def test_the_solver_never_tries_an_excluded_minimum():
    from roughdiffuse.fit.between_models import _lower_bound

    eta = next(p for p in registry.get("mix").parameters if p.name == "eta")
    assert eta.min_open and _lower_bound(eta) > eta.min
    eta.check(_lower_bound(eta))  # accepted by the declaration
