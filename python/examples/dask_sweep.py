"""A design study on a Dask cluster: Wu & Yang's Fig. 4 hole filled for a
sweep of normal-field weights λ, solved by worker processes, gathered as
numpy arrays.

    python python/examples/dask_sweep.py [SCHEDULER_ADDRESS]

With no address it starts a local cluster of two worker processes; give a
scheduler's address (tcp://host:8786) to use a real one, whose workers have
fairsurf installed. Each task solves a chunk of the sweep with
``fairsurf.solve_many`` on the worker's threads (the GIL is released during
solves); results pickle as their result files' text, so they travel between
processes and machines whole.
"""

import functools
import json
import sys
from pathlib import Path

import numpy as np
from distributed import Client, LocalCluster

import fairsurf

def main() -> None:
    examples = Path(__file__).resolve().parents[2] / "examples"
    base = json.loads((examples / "wu_yang_fig4_l500.json").read_text())
    weights = [10, 30, 100, 300, 1000, 3000]
    scenes = []
    for lam in weights:
        s = json.loads(json.dumps(base))
        s["energy"]["normal_field"]["weight"] = lam
        scenes.append(s)

    chunks = [scenes[k:k + 3] for k in range(0, len(scenes), 3)]
    solve_chunk = functools.partial(fairsurf.solve_many, threads=2)

    def solve(client: Client) -> list:
        parts = client.gather(client.map(solve_chunk, chunks))
        return [r for part in parts for r in part]

    if len(sys.argv) > 1:
        with Client(sys.argv[1]) as client:
            results = solve(client)
    else:
        with LocalCluster(n_workers=2, threads_per_worker=1, dashboard_address=None) as cluster, \
                Client(cluster) as client:
            results = solve(client)

    nets = np.stack([r.control_points for r in results])  # (weights, n+1, m+1, 3)
    print("nets", nets.shape, nets.dtype)
    for lam, r in zip(weights, results):
        rep = r.report
        print(f"λ = {lam:>5}: energy {rep['energy']:.6g}, normal deviation "
              f"{rep['normal_deviation_deg']['max']:.3f}° max, checked {rep['check']['excess']:.1e}")


if __name__ == "__main__":  # worker processes import this file again
    main()
