"""Results cross process boundaries: they pickle, and a Dask cluster of
worker processes solves a sweep to the same arrays as one process."""

from __future__ import annotations

import functools
import json
import pickle
from pathlib import Path

import numpy as np
import pytest
from distributed import Client, LocalCluster

import fairsurf

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


@pytest.mark.parametrize("scene", ["wu_yang_fig4_l500.json", "vw_pentagon_hole.json",
                                   "bspline_hole_guided.json"])
def test_results_pickle_exactly(scene: str, tmp_path: Path) -> None:
    r = fairsurf.solve(EXAMPLES / scene)
    back = pickle.loads(pickle.dumps(r))
    assert isinstance(back, fairsurf.Result)
    np.testing.assert_array_equal(back.control_points, r.control_points)
    assert back.report == r.report and back.to_json() == r.to_json()
    back.write(tmp_path / "r.json")
    assert json.loads((tmp_path / "r.json").read_text()) == json.loads(r.to_json())
    # The surface alone pickles as the scene that gives it, of every kind.
    alone = pickle.loads(pickle.dumps(r.surface))
    assert type(alone) is fairsurf.Surface and alone.degree == r.degree
    np.testing.assert_array_equal(alone.control_points, r.control_points)
    if r.surface_type == "triangular":
        np.testing.assert_array_equal(alone.patch_indices, r.patch_indices)
        mine, theirs = alone.mesh(4), r.mesh(4)
        np.testing.assert_array_equal(mine.vertices, theirs.vertices)
    else:
        np.testing.assert_array_equal(alone.evaluate(0.3, 0.7), r.evaluate(0.3, 0.7))
    e = pickle.loads(pickle.dumps(_scene_error()))
    assert isinstance(e, fairsurf.SceneError) and e.path == "surface.type"


def _scene_error() -> fairsurf.SceneError:
    try:
        fairsurf.solve({"surface": {"type": "nurbs"}})
    except fairsurf.SceneError as e:
        return e
    raise AssertionError("no error")


def sweep() -> list:
    """Wu & Yang Fig. 4's hole, λ from 0 to 1000."""
    base = json.loads((EXAMPLES / "wu_yang_fig4_l500.json").read_text())
    out = []
    for lam in [0, 10, 100, 500, 1000, 2000]:
        s = json.loads(json.dumps(base))
        if lam:
            s["energy"]["normal_field"]["weight"] = lam
        else:
            del s["energy"]["normal_field"]
        out.append(s)
    return out


def test_a_dask_cluster_solves_a_sweep_like_one_process() -> None:
    """Two worker processes (dask.distributed's LocalCluster) solve a λ
    sweep, one chunk of scenes per task with solve_many's threads, and one
    scene per task with solve; the gathered control points equal
    solve_many's in this process bit for bit, and a bad scene's
    SceneError comes back with its JSON path."""
    scenes = sweep()
    local = fairsurf.solve_many(scenes, threads=2)
    chunks = [scenes[k:k + 3] for k in range(0, len(scenes), 3)]
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                      dashboard_address=None) as cluster, Client(cluster) as client:
        solve_chunk = functools.partial(fairsurf.solve_many, threads=2)
        chunked = [r for part in client.gather(client.map(solve_chunk, chunks)) for r in part]
        futures = client.map(fairsurf.solve, scenes)
        remote = client.gather(futures)
        pids = set(client.run(lambda: __import__("os").getpid()).values())
        bad = client.submit(fairsurf.solve, {"surface": {"type": "nurbs"}})
        with pytest.raises(fairsurf.SceneError) as e:
            bad.result()
    assert len(pids) == 2
    assert e.value.path == "surface.type"
    assert len(chunked) == len(local)
    for a, c, b in zip(remote, chunked, local):
        np.testing.assert_array_equal(a.control_points, b.control_points)
        np.testing.assert_array_equal(c.control_points, b.control_points)
        assert a.report["energy"] == b.report["energy"]
    energies = [r.report["energy"] for r in remote]
    assert energies == sorted(energies)  # a larger λ never lowers the minimum
