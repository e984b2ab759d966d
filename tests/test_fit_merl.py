"""The MERL binary format: byte layout, index convention, errors, model -> file -> fit."""

from __future__ import annotations

import math

import numpy as np
import pytest

import roughdiffuse as rd
from roughdiffuse.fit import (
    MERLBRDF,
    directions_from_half_diff,
    fit,
    half_diff_from_directions,
    merl_cell_index,
    read_merl,
    write_merl,
)

N = 90 * 90 * 180
# MERL's BRDFRead.cpp RED_SCALE, GREEN_SCALE, BLUE_SCALE, typed again
SCALE = (1.0 / 1500.0, 1.15 / 1500.0, 1.66 / 1500.0)


def _file(path, raw: np.ndarray, dims=(90, 90, 180)) -> None:  # noqa: ANN001
    """A MERL file written by hand: int32 header, then red, green, blue float64 blocks."""
    path.write_bytes(np.asarray(dims, "<i4").tobytes() + np.asarray(raw, "<f8").tobytes())


def _random_directions(n: int, seed: int) -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    ti, tr = rng.uniform(0, 1.5, n), rng.uniform(0, 1.5, n)
    pi, pr = rng.uniform(-np.pi, np.pi, n), rng.uniform(-np.pi, np.pi, n)
    return rd.spherical_to_vector(ti, pi), rd.spherical_to_vector(tr, pr)


def test_lambertian_file_gives_rho_over_pi(tmp_path) -> None:  # noqa: ANN001
    rho = np.array([0.2, 0.5, 0.9])
    raw = np.concatenate([np.full(N, rho[c] / math.pi / SCALE[c]) for c in range(3)])
    path = tmp_path / "lambert.binary"
    _file(path, raw)
    merl = read_merl(path)
    wi, wo = _random_directions(500, 0)
    np.testing.assert_allclose(merl.lookup(wi, wo), np.tile(rho / math.pi, (500, 1)), rtol=1e-14)
    r = fit(rd.Lambert, merl.to_measurements(max_samples=5000))
    np.testing.assert_allclose(r.values, rho, rtol=1e-10)


def test_model_tabulated_as_lambert_equals_hand_file() -> None:
    merl = MERLBRDF.from_model(rd.Lambert(0.5))
    brdf = merl.brdf
    present = merl.valid
    np.testing.assert_allclose(brdf[present], 0.5 / math.pi, rtol=1e-14)
    # missing exactly where a direction of the cell centre is below the horizon
    assert 0.3 < present.mean() < 0.95


def test_round_trip_is_byte_exact(tmp_path) -> None:  # noqa: ANN001
    rng = np.random.default_rng(1)
    raw = rng.uniform(0, 500, 3 * N)
    raw[rng.choice(3 * N, 1000, replace=False)] = -1.0  # missing samples
    a = tmp_path / "a.binary"
    b = tmp_path / "b.binary"
    _file(a, raw)
    merl = read_merl(a)
    np.testing.assert_array_equal(merl.raw.ravel(), raw)
    assert int((~merl.valid).sum()) == 1000
    assert np.isnan(merl.brdf[~merl.valid]).all()
    write_merl(b, merl)
    assert a.read_bytes() == b.read_bytes()
    again = MERLBRDF.from_brdf(merl.brdf)
    np.testing.assert_allclose(again.raw, merl.raw, rtol=1e-14)


def test_truncated_file(tmp_path) -> None:  # noqa: ANN001
    path = tmp_path / "t.binary"
    _file(path, np.zeros(3 * N))
    blob = path.read_bytes()
    path.write_bytes(blob[:-8])
    with pytest.raises(ValueError, match="truncated MERL file"):
        read_merl(path)
    path.write_bytes(blob[:6])
    with pytest.raises(ValueError, match="truncated"):
        read_merl(path)
    path.write_bytes(blob + b"\0" * 8)
    with pytest.raises(ValueError, match="too long"):
        read_merl(path)


def test_wrong_dimensions(tmp_path) -> None:  # noqa: ANN001
    path = tmp_path / "d.binary"
    _file(path, np.zeros(3 * 90 * 90 * 360), dims=(90, 90, 360))
    with pytest.raises(ValueError, match="dimensions must be 90 x 90 x 180.*90 x 90 x 360"):
        read_merl(path)


def test_nan_entries(tmp_path) -> None:  # noqa: ANN001
    raw = np.zeros(3 * N)
    raw[N + 180 * 90 * 3 + 180 * 4 + 5] = np.nan  # green, θh 3, θd 4, φd 5
    path = tmp_path / "n.binary"
    _file(path, raw)
    with pytest.raises(
        ValueError, match="1 entries are NaN.*channel G, θh index 3, θd index 4, φd index 5"
    ):
        read_merl(path)


def _index_by_hand(th: float, td: float, pd: float) -> tuple[int, int, int]:
    """MERL's BRDFRead.cpp index rules (theta_half_index, theta_diff_index, phi_diff_index),
    one scalar at a time."""
    ih = 0 if th <= 0 else min(89, int(math.sqrt(th / (math.pi / 2)) * 90))
    idd = min(89, max(0, int(td / (math.pi / 2) * 90)))
    if pd < 0:
        pd += math.pi
    ip = min(179, max(0, int(pd / math.pi * 180)))
    return ih, idd, ip


def test_cell_index_convention() -> None:
    rng = np.random.default_rng(2)
    th = rng.uniform(0, math.pi / 2, 300)
    td = rng.uniform(0, math.pi / 2, 300)
    pd = rng.uniform(-math.pi, math.pi, 300)
    got = np.stack(merl_cell_index(th, td, pd), axis=-1)
    want = np.array([_index_by_hand(*g) for g in zip(th, td, pd, strict=True)])
    np.testing.assert_array_equal(got, want)
    assert [int(v) for v in merl_cell_index(0.0, 0.0, 0.0)] == [0, 0, 0]
    # θh index is √(θh/(π/2))·90: θh = (π/2)/4 is index 45
    assert int(merl_cell_index(math.pi / 8 + 1e-9, 0.0, 0.0)[0]) == 45


def test_half_diff_angles_of_known_geometries() -> None:
    a = 0.4
    wi = np.array([math.sin(a), 0.0, math.cos(a)])
    wo = np.array([-math.sin(a), 0.0, math.cos(a)])  # mirror direction: h = normal
    th, td, _ = half_diff_from_directions(wi, wo)
    assert float(th) == pytest.approx(0.0, abs=1e-12)
    assert float(td) == pytest.approx(a)
    th, td, _ = half_diff_from_directions(wi, wi)  # retro-reflection: d = normal
    assert float(th) == pytest.approx(a)
    assert float(td) == pytest.approx(0.0, abs=1e-7)
    # inverse, and reciprocity: swapping wi and wo lands in the same cell
    wi, wo = _random_directions(200, 3)
    back_i, back_o = directions_from_half_diff(
        *half_diff_from_directions(wi, wo), np.arctan2(*(wi + wo)[:, 1::-1].T)
    )
    np.testing.assert_allclose(back_i, wi, atol=1e-9)
    np.testing.assert_allclose(back_o, wo, atol=1e-9)
    cells = np.stack(merl_cell_index(*half_diff_from_directions(wi, wo)))
    swapped = np.stack(merl_cell_index(*half_diff_from_directions(wo, wi)))
    assert (cells == swapped).mean() > 0.99  # exact up to samples on a cell border


def test_model_to_merl_to_fit(tmp_path) -> None:  # noqa: ANN001
    model = rd.OrenNayar(np.array([0.3, 0.55, 0.8]), 0.45, "full")
    path = tmp_path / "on.binary"
    write_merl(path, MERLBRDF.from_model(model))
    merl = read_merl(path)
    r = fit(rd.OrenNayar, merl.to_measurements(max_samples=20_000), fixed={"variant": "full"})
    np.testing.assert_allclose(r.values, [0.3, 0.55, 0.8, 0.45], atol=1e-8)
    # nearest-cell lookup at arbitrary directions is close to the model (cells are small)
    wi, wo = _random_directions(2000, 4)
    look = merl.lookup(wi, wo)
    f = np.asarray(model.brdf(wi, wo))
    ok = np.all(np.isfinite(look), axis=-1) & (wi[:, 2] > 0.2) & (wo[:, 2] > 0.2)
    assert np.median(np.abs(look[ok] / f[ok] - 1)) < 0.02
