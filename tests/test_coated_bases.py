"""The registry's ``coated`` over each base it offers (``base``, one declaration).

Independent references: at η = 1 a smooth coat is no interface at all, so the coat is its
base, whose own formula (the base class) is the reference; a smooth coat over Lambert is the
exact sum of the internal reflections, ρ (1 − F_i)(1 − F_o) / (π η² (1 − ρ F_dr)), F_dr by
SciPy's adaptive quadrature (Mitsuba 3's ``plastic`` with ``nonlinear=true``).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad

import roughdiffuse as rd
from mitsuba_setup import mitsuba_variant, random_geometries
from roughdiffuse import cli, registry
from roughdiffuse.models.coated import COAT_BASES
from roughdiffuse.models.microfacet import fresnel_dielectric

BASES = {  # registry's base id and its own parameter -> the base built by its own class
    "lambert": ({}, rd.Lambert(0.7)),
    "oren-nayar": ({"sigma": 0.4}, rd.OrenNayar(0.7, 0.4, "qualitative")),
    "oren-nayar-full": ({"sigma": 0.4}, rd.OrenNayar(0.7, 0.4, "full")),
    "fujii": ({"base_roughness": 0.6}, rd.Fujii(0.7, 0.6)),
    "eon": ({"base_roughness": 0.6}, rd.EON(0.7, 0.6)),
}
CHOICES = "'lambert', 'oren-nayar', 'oren-nayar-full', 'fujii', 'eon'"


def _dirs(ti, tr, dp):
    return rd.spherical_to_vector(ti, 0.0), rd.spherical_to_vector(tr, dp)


def test_every_offered_base_is_tested() -> None:
    assert set(BASES) == set(COAT_BASES)


@pytest.mark.parametrize("base", sorted(BASES))
def test_invisible_coat_is_the_base(base: str) -> None:
    own, ref = BASES[base]
    model = registry.create("coated", base=base, albedo=0.7, eta=1.0, **own)
    assert model.base == ref
    w = _dirs(*random_geometries(12, 3))
    np.testing.assert_allclose(model.brdf(*w), ref.brdf(*w), rtol=1e-12)


def test_smooth_coat_over_lambert_by_id_is_the_exact_sum() -> None:
    rho, eta = 0.7, 1.5
    fdr = quad(lambda m: 2 * m * fresnel_dielectric(np, np.array(m), 1 / eta), 0, 1,
               points=[math.sqrt(1 - 1 / eta**2)], limit=200, epsabs=1e-12)[0]
    ti, tr, dp = random_geometries(10, 2)
    ref = (1 - fresnel_dielectric(np, np.cos(ti), eta)) * (
        1 - fresnel_dielectric(np, np.cos(tr), eta)) * rho / (math.pi * eta**2 * (1 - rho * fdr))
    model = registry.create("coated", base="lambert", albedo=rho, eta=eta)
    np.testing.assert_allclose(model.brdf(*_dirs(ti, tr, dp)), ref, rtol=1e-6)


def test_the_declaration_says_which_parameter_each_base_takes() -> None:
    entry = registry.get("coated")
    assert entry.param("base").choices == COAT_BASES
    taken = {b: [p.name for p in entry.applicable({"base": b})] for b in COAT_BASES}
    assert taken["lambert"] == ["base", "albedo", "eta", "roughness", "distribution",
                                "absorption"]
    assert "sigma" in taken["oren-nayar-full"] and "base_roughness" not in taken["oren-nayar"]
    assert "base_roughness" in taken["eon"] and "sigma" not in taken["fujii"]
    # the base's own range, unit and fit box (one declaration: copied from the base class)
    on, eon = rd.OrenNayar.params[1], rd.EON.params[1]
    for mine, theirs in ((entry.param("sigma"), on), (entry.param("base_roughness"), eon)):
        assert (mine.min, mine.max, mine.unit, mine.bounds) == (
            theirs.min, theirs.max, theirs.unit, theirs.bounds)
    record = {r["id"]: r for r in registry.to_json()}["coated"]  # /api/models
    when = {p["name"]: p["when"] for p in record["parameters"]}
    assert when["sigma"] == {"base": ["oren-nayar", "oren-nayar-full"]}
    assert when["base_roughness"] == {"base": ["fujii", "eon"]} and when["eta"] is None


@pytest.mark.parametrize(
    ("params", "message"),
    [
        ({"base": "coated"}, f"'coated' is a coat: a coat on a coat .*; choose one of {CHOICES}"),
        ({"base": "smith-diffuse-ggx"}, f"'smith-diffuse-ggx' is a simulation.*{CHOICES}"),
        ({"base": "burley"}, f"'burley' is not a base the registry's coated offers.*{CHOICES}"),
        ({"base": "no-such"}, f"'no-such' is not a model id; choose one of {CHOICES}"),
        ({"base": "eon", "sigma": 0.2}, "sigma applies only with base in {'oren-nayar', "),
        ({"base": "lambert", "base_roughness": 0.2}, "base_roughness applies only with base"),
    ],
)
def test_bad_base_named(params: dict, message: str) -> None:
    with pytest.raises(ValueError, match=message):
        registry.create("coated", **params)


def test_cli_evaluates_the_coat_over_eon(capsys) -> None:
    args = ["eval", "--model", "coated", "--param", "base=eon", "--param", "base_roughness=0.6",
            "--param", "albedo=0.7", "--param", "eta=1.4", "--theta-i", "40", "--theta-r", "20",
            "--delta-phi", "30"]
    assert cli.main(args) == 0
    out = capsys.readouterr().out
    value = float(next(line for line in out.splitlines() if line.startswith("brdf")).split()[-1])
    ref = rd.Coated(rd.EON(0.7, 0.6), 1.4).brdf(
        rd.spherical_to_vector(math.radians(40), 0.0),
        rd.spherical_to_vector(math.radians(20), math.radians(30)))
    assert value == pytest.approx(float(ref), rel=1e-5)  # printed with 6 digits
    assert "defaults used for: eta" not in out and "sigma" not in out.split("defaults used")[1]


@pytest.mark.parametrize(("param", "message"), [
    ("base=coated", "base 'coated' is a coat"), ("sigma=20", "sigma applies only with base")])
def test_cli_refuses_a_bad_base_in_one_line(capsys, param: str, message: str) -> None:
    base = [] if param.startswith("base") else ["--param", "base=eon"]
    assert cli.main(["eval", "--model", "coated", *base, "--param", param]) == 2
    err = capsys.readouterr().err.strip()
    assert message in err and "\n" not in err and "Traceback" not in err


def test_fit_takes_the_base_as_a_fixed_choice(capsys) -> None:
    from roughdiffuse.fit.compare import candidate

    c = candidate("coated", {"base": "eon"})
    assert c.fixed == {"base": "eon"}
    assert c.params == ("albedo", "base_roughness", "eta", "roughness", "absorption")
    with pytest.raises(ValueError, match="only a choice can be fixed"):
        candidate("coated", {"eta": "1.5"})
    with pytest.raises(ValueError, match="base must be one of 'lambert'"):
        candidate("coated", {"base": "coated"})


@pytest.mark.slow  # JAX compiles the residuals and Jacobian of the coat over EON
def test_fit_recovers_the_coat_over_eon() -> None:
    from roughdiffuse.fit import Measurements, fit
    from roughdiffuse.fit.compare import candidate

    truth = {"albedo": 0.7, "base_roughness": 0.6, "eta": 1.6, "roughness": 0.25}
    ti, tr, dp = random_geometries(300, 6)
    f = np.asarray(registry.create("coated", base="eon", **truth).brdf(*_dirs(ti, tr, dp)))
    rng = np.random.default_rng(7)
    data = Measurements.from_angles(ti, tr, dp, f * (1 + 0.01 * rng.standard_normal(f.shape)))
    c = candidate("coated", {"base": "eon"})
    names = [n for n in c.params if n != "absorption"]
    r = fit(c.model, data, names, fixed={**c.fixed, "absorption": 0.0}, noise="relative")
    values = dict(zip(r.names, r.values, strict=True))
    errors = dict(zip(r.names, r.errors, strict=True))
    for name in names:
        assert abs(values[name] - truth[name]) <= 4 * errors[name], (name, values, errors)


def test_mitsuba_plugin_coats_the_chosen_base() -> None:
    import drjit as dr

    mi = mitsuba_variant("llvm_ad_rgb")
    colour = [0.8, 0.55, 0.3]
    bsdf = mi.load_dict({"type": "roughdiffuse_coated", "base": "eon", "base_roughness": 0.6,
                         "albedo": {"type": "rgb", "value": colour}, "eta": 1.4,
                         "roughness": 0.3})
    model = rd.Coated(rd.EON(np.array(colour), 0.6), 1.4, 0.3)
    rng = np.random.default_rng(1)
    v = rng.normal(size=(2, 200, 3))
    v /= np.linalg.norm(v, axis=-1, keepdims=True)
    v[..., 2] = np.abs(v[..., 2])
    light, view = v
    si = dr.zeros(mi.SurfaceInteraction3f, len(light))
    si.wi = mi.Vector3f(*(view.T.astype(np.float32)))
    value = bsdf.eval(mi.BSDFContext(), si, mi.Vector3f(*(light.T.astype(np.float32))))
    value = np.array(value).reshape(3, -1).T
    ref = np.asarray(model.brdf(light, view)) * light[:, 2:3]
    np.testing.assert_allclose(value, ref, rtol=5e-4, atol=5e-6)  # float32 (the plugin tests')
    with pytest.raises(Exception, match="sigma applies only with base"):
        mi.load_dict({"type": "roughdiffuse_coated", "base": "eon", "sigma": 0.3})
