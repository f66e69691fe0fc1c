#!/usr/bin/env python3
"""The editor's drag, measured on the server: `fairsurf serve` (release
build) answers `POST /api/solve` with `"quick": true` while a held control
point of `examples/editor_degree10.json` moves a little each step, as the
page sends them during a drag; then one full answer (`"quick": false`).

Prints the median and range of the server's own `seconds` (parse, solve
with the kept factorization, the view for the page) and of the round trip
from this script (with the JSON answer's serialization and transfer).

    cargo build --release -p fairsurf-cli
    python3 bench/editor_drag.py [--steps 60] [--example editor_degree10.json]
        [--mesh-encoding base64|json] [--binary target/release/fairsurf]
"""

import argparse
import json
import statistics
import subprocess
import sys
import time
import urllib.request
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def post(url, body):
    data = json.dumps(body).encode()
    req = urllib.request.Request(
        url + "/api/solve", data=data, headers={"Content-Type": "application/json"}
    )
    t = time.perf_counter()
    with urllib.request.urlopen(req) as r:
        answer = json.loads(r.read())
    return answer, time.perf_counter() - t


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--steps", type=int, default=60)
    ap.add_argument("--example", default="editor_degree10.json")
    ap.add_argument("--binary", default=str(ROOT / "target/release/fairsurf"))
    ap.add_argument("--mesh-encoding", default="base64", choices=["base64", "json"],
                    help="how the answers write the mesh (the page asks for base64)")
    args = ap.parse_args()
    scene = json.loads((ROOT / "examples" / args.example).read_text())
    server = subprocess.Popen(
        [args.binary, "serve", "--port", "0"],
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
    )
    try:
        url = None
        for line in server.stdout:
            if line.startswith("fairsurf editor: "):
                url = line.split(": ", 1)[1].strip().rstrip("/")
                break
        if url is None:
            sys.exit("the server did not start")
        enc = args.mesh_encoding
        first, first_rt = post(url, {"scene": scene, "quick": False, "mesh_encoding": enc})
        # The handle the page would drag: the first held (given) control
        # point inside the net's first row, moved along z.
        net = scene["surface"]["control_points"]
        i, j = 0, len(net[0]) // 2
        base = list(net[i][j])
        server_s, round_trip = [], []
        for k in range(args.steps):
            net[i][j] = [base[0], base[1], base[2] + 0.002 * (k + 1)]
            answer, rt = post(url, {"scene": scene, "quick": True, "mesh_encoding": enc})
            server_s.append(answer["seconds"])
            round_trip.append(rt)
        full, full_rt = post(url, {"scene": scene, "quick": False, "mesh_encoding": enc})

        def ms(xs):
            return f"median {1e3 * statistics.median(xs):.2f} ms " \
                   f"(range {1e3 * min(xs):.2f}–{1e3 * max(xs):.2f})"

        print(f"{args.example}: first request server {1e3 * first['seconds']:.1f} ms, "
              f"round trip {1e3 * first_rt:.1f} ms")
        print(f"quick drag steps ({args.steps}): server {ms(server_s)}; round trip {ms(round_trip)}")
        print(f"full answer after letting go: server {1e3 * full['seconds']:.1f} ms, "
              f"round trip {1e3 * full_rt:.1f} ms")
        reused = [r for r in full.get("table", []) if "reused" in str(r).lower()]
        if reused:
            print("table:", reused)
    finally:
        server.terminate()
        server.wait()


if __name__ == "__main__":
    main()
