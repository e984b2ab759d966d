"""Ground-truth tables: file round trip, resumable chunks, refusal to mix, Dask on loopback."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

import roughdiffuse.simulate.table as table_mod
from roughdiffuse.cli import main
from roughdiffuse.simulate import GroundTruth, Settings, brdf, compute_table, load_table

TI = np.radians([0.0, 30.0, 60.0])
TR = np.radians([10.0, 50.0])
DP = np.radians([0.0, 180.0])
SIG = np.array([0.2, 0.4])


def _table(path, **kw):
    return compute_table(path, TI, TR, DP, SIG, 0.8, 1, rows_per_chunk=1, progress=False, **kw)


def test_round_trip_and_values(tmp_path):
    t = _table(tmp_path / "gt.npz")
    u = load_table(tmp_path / "gt.npz")
    np.testing.assert_array_equal(t.values, u.values)
    assert u.settings == Settings() and u.bounces == 1 and u.albedo == 0.8
    # each entry equals a direct evaluation at that grid point
    ref = brdf(TI[2], TR[1], DP[1], SIG[1], 0.8, 1)
    assert u.values[2, 1, 1, 1] == pytest.approx(float(ref), rel=1e-12)
    assert not (tmp_path / "gt.npz.chunks").exists()


def test_resume_recomputes_nothing_finished(tmp_path, monkeypatch):
    path = tmp_path / "gt.npz"
    calls = []
    real = table_mod.compute_chunk

    def flaky(spec):
        calls.append(spec["name"])
        if len(calls) == 4:
            raise KeyboardInterrupt  # interrupted in the middle of the run
        return real(spec)

    monkeypatch.setattr(table_mod, "compute_chunk", flaky)
    with pytest.raises(KeyboardInterrupt):
        _table(path)
    done = sorted(p.name for p in (tmp_path / "gt.npz.chunks").glob("s*.npz"))
    assert len(done) == 3 and not path.exists()
    assert not list((tmp_path / "gt.npz.chunks").glob("*.tmp"))  # nothing half-written
    calls.clear()
    monkeypatch.setattr(
        table_mod, "compute_chunk", lambda spec: (calls.append(spec["name"]), real(spec))[1]
    )
    t = _table(path)
    assert len(calls) == 6 - 3 and not set(calls) & set(done)
    np.testing.assert_allclose(t.values, _table(tmp_path / "fresh.npz").values, rtol=0, atol=0)


def test_resume_refuses_other_settings(tmp_path, monkeypatch):
    path = tmp_path / "gt.npz"
    real = table_mod.compute_chunk
    n = []

    def stop(spec):
        n.append(1)
        if len(n) > 1:
            raise KeyboardInterrupt
        return real(spec)

    monkeypatch.setattr(table_mod, "compute_chunk", stop)
    with pytest.raises(KeyboardInterrupt):
        _table(path)
    monkeypatch.setattr(table_mod, "compute_chunk", real)
    with pytest.raises(ValueError, match="refusing to mix"):
        _table(path, settings=Settings(measure="angle"))


def test_bad_files(tmp_path):
    bad = tmp_path / "bad.npz"
    bad.write_bytes(b"not a zip file")
    with pytest.raises(ValueError, match="not a readable"):
        load_table(bad)
    t = _table(tmp_path / "gt.npz")
    meta = dict(t.meta)
    old = GroundTruth(
        t.theta_i, t.theta_r, t.delta_phi, t.sigma, t.values, t.k_difference, 0.8, 1, t.settings
    )
    old.save(tmp_path / "old.npz")
    with np.load(tmp_path / "old.npz") as z:
        arrays = {k: z[k] for k in z.files}
    meta = json.loads(str(arrays["meta"]))
    meta["format_version"] = 99
    arrays["meta"] = np.array(json.dumps(meta))
    np.savez(tmp_path / "v99.npz", **arrays)
    with pytest.raises(ValueError, match="version"):
        load_table(tmp_path / "v99.npz")
    arrays["values"] = arrays["values"][:1]
    meta["format_version"] = 1
    arrays["meta"] = np.array(json.dumps(meta))
    np.savez(tmp_path / "short.npz", **arrays)
    with pytest.raises(ValueError, match="corrupt"):
        load_table(tmp_path / "short.npz")


def test_bad_grid(tmp_path):
    with pytest.raises(ValueError, match="theta_i"):
        compute_table(tmp_path / "x.npz", [2.0], TR, DP, SIG, progress=False)
    with pytest.raises(ValueError, match="sigma"):
        compute_table(tmp_path / "x.npz", TI, TR, DP, [-0.1], progress=False)
    with pytest.raises(ValueError, match="workers"):
        compute_table(tmp_path / "x.npz", TI, TR, DP, SIG, workers=0, progress=False)


def test_dask_local_cluster_and_scheduler_address(tmp_path):
    from distributed import LocalCluster

    ref = _table(tmp_path / "ref.npz", backend="numpy")  # as "auto" picks for workers
    t2 = _table(tmp_path / "w2.npz", workers=2)
    np.testing.assert_array_equal(t2.values, ref.values)
    with LocalCluster(
        n_workers=1, threads_per_worker=1, processes=True, host="127.0.0.1", dashboard_address=None
    ) as cluster:
        t3 = _table(tmp_path / "sched.npz", scheduler=cluster.scheduler_address)
    np.testing.assert_array_equal(t3.values, ref.values)


def test_local_workers_settings_are_dask_settings():
    """The keys of LOCAL_WORKER_CONFIG are Dask's own (a renamed key would silently do
    nothing): the nanny's environment of its workers (a None value is left unset, Dask's
    distributed.yaml) and the worker's profiler switch."""
    import dask
    import distributed  # noqa: F401  (loads the distributed.* defaults)

    for key in table_mod.LOCAL_WORKER_CONFIG:
        parent, _, leaf = key.rpartition(".")
        assert leaf in dask.config.get(parent), key
    with dask.config.set(table_mod.LOCAL_WORKER_CONFIG):
        environ = dask.config.get("distributed.nanny.pre-spawn-environ")
        assert environ["MALLOC_TRIM_THRESHOLD_"] is None
        assert dask.config.get("distributed.worker.profile.enabled") is False


def test_cli(tmp_path, capsys):
    assert (
        main(["simulate", "--theta-i", "30", "--theta-r", "0", "--sigma", "0", "--albedo", "0.5"])
        == 0
    )
    out = capsys.readouterr().out
    assert f"{0.5 / math.pi:.8g}" in out
    path = tmp_path / "t.npz"
    args = ["simulate", "--table", str(path), "--step", "45", "--delta-phi-step", "180"]
    assert main([*args, "--sigma", "10,20", "--bounces", "1", "--no-progress"]) == 0
    assert load_table(path).values.shape == (3, 3, 2, 2)
    assert main(["simulate", "--bounces", "0"]) == 2
    assert main(["simulate", "--sigma", "100"]) == 2
    assert main(["simulate", "--table", str(path), "--step", "0"]) == 2
    err = capsys.readouterr().err
    assert "Traceback" not in err and "--step" in err


@pytest.mark.slow
def test_report_quick(tmp_path):
    assert main(["simulate", "--report", "--quick", "-o", str(tmp_path), "--no-progress"]) == 0
    text = (tmp_path / "index.md").read_text()
    assert "reading fits better" in text and "Oren–Nayar full" in text
    for truth in ("V-cavity", "Smith-Beckmann", "Smith-GGX"):  # the scoreboard's three truths
        assert f"### Against the {truth} surface" in text
    assert "White furnace" in text and "Which model for which surface" in text
    for png in ("plane_of_incidence.png", "error_maps.png"):
        assert (tmp_path / png).stat().st_size > 10_000
    # the scoreboard as JSON (the site's model pages read it) holds the tables' numbers
    import json

    scores = json.loads((tmp_path / "model_scores.json").read_text())
    rows = scores["models"]["oren-nayar-full"]["V-cavity"]
    assert {r["mapping"] for r in rows} == {"best fit", "published"}
    table = text.split("### Against the V-cavity surface", 1)[1].split("###", 1)[0]
    line = next(x for x in table.splitlines() if x.startswith("| Oren–Nayar full | sigma: best"))
    for r in (r for r in rows if r["mapping"] == "best fit"):
        assert f"{r['rms']:.3f} (max {r['max']:.2f}) [{r['value']:.2f}]" in line


def test_backends_agree_and_bad_backend(tmp_path):
    # the compiled JAX chunks and the NumPy chunks hold the same values
    jx = compute_table(tmp_path / "j.npz", TI, TR, DP, SIG, 0.8, 2, progress=False, backend="jax")
    ref = brdf(TI[:, None, None], TR[None, :, None], DP[None, None, :], SIG[1], 0.8, 2)
    np.testing.assert_allclose(jx.values[..., 1], ref, rtol=1e-9)
    with pytest.raises(ValueError, match="backend"):
        compute_table(tmp_path / "x.npz", TI, TR, DP, SIG, progress=False, backend="cuda")
