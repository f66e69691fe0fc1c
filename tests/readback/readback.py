#!/usr/bin/env python3
"""Read a file written by fairsurf with an independent reader; print JSON.

    readback.py FILE [--uv U,V]... [--mesh-size H]

CAD files (.step .stp .igs .iges) are read by gmsh, i.e. Open CASCADE's STEP
and IGES translators: every surface is listed with its type, its parameter
bounds and its point at each requested (u, v) (gmsh.model.getValue, the
parameters taken as they are, not rescaled to the bounds). With --mesh-size,
gmsh also meshes the surfaces (which needs a usable boundary representation:
edges, vertices, curves on the surface) and reports each one's triangles.

Meshes are read by trimesh (.obj .stl .glb .gltf) or plyfile (.ply): vertex
positions, face count, and what else the file holds (normals, colours,
custom attributes, every PLY vertex property).

Every real is printed as a JSON string holding Python's shortest
round-trip repr ("0.1", "nan"), so that a reader of the JSON gets the exact
double whatever its JSON number parser does (serde_json's default parser is
not correctly rounded).

The fairsurf-io tests run this (crates/fairsurf-io/tests/suite/exports.rs) with the interpreter named
by FAIRSURF_READBACK_PYTHON; `pip install gmsh trimesh plyfile numpy`.
"""

import argparse
import json
import os
import sys


def clean(x):
    """JSON-ready: numpy to lists, reals to their repr strings."""
    if hasattr(x, "tolist"):
        x = x.tolist()
    if isinstance(x, float):
        return repr(x)
    if isinstance(x, (list, tuple)):
        return [clean(y) for y in x]
    if isinstance(x, dict):
        return {str(k): clean(v) for k, v in x.items()}
    return x


def read_cad(path, uvs, mesh_size):
    # Open CASCADE's IGES reader prints to the process's stdout, which must
    # hold nothing but the JSON: send fd 1 to stderr while gmsh runs.
    sys.stdout.flush()
    saved = os.dup(1)
    os.dup2(2, 1)
    try:
        return read_cad_quietly(path, uvs, mesh_size)
    finally:
        sys.stdout.flush()
        os.dup2(saved, 1)
        os.close(saved)


def read_cad_quietly(path, uvs, mesh_size):
    import gmsh

    gmsh.initialize(readConfigFiles=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add("readback")
        imported = gmsh.model.occ.importShapes(path, highestDimOnly=False)
        gmsh.model.occ.synchronize()
        flat = [c for uv in uvs for c in uv]
        surfaces = []
        for _, tag in gmsh.model.getEntities(2):
            lo, hi = gmsh.model.getParametrizationBounds(2, tag)
            values = gmsh.model.getValue(2, tag, flat) if uvs else []
            boundary = gmsh.model.getBoundary([(2, tag)], combined=False, oriented=False)
            surfaces.append(
                {
                    "tag": tag,
                    "type": gmsh.model.getType(2, tag),
                    "bounds": clean([[lo[0], hi[0]], [lo[1], hi[1]]]),
                    "values": clean([list(values[3 * k : 3 * k + 3]) for k in range(len(uvs))]),
                    "boundary_curves": len(boundary),
                }
            )
        if mesh_size:
            gmsh.option.setNumber("Mesh.MeshSizeMax", mesh_size)
            gmsh.model.mesh.generate(2)
            for s in surfaces:
                types, tags, _ = gmsh.model.mesh.getElements(2, s["tag"])
                s["triangles"] = sum(len(t) for e, t in zip(types, tags) if e == 2)
        return {
            "reader": "gmsh %s (Open CASCADE)" % gmsh.__version__,
            "kind": "cad",
            "imported": [list(dt) for dt in imported],
            "surfaces": surfaces,
            "curves": len(gmsh.model.getEntities(1)),
            "points": len(gmsh.model.getEntities(0)),
        }
    finally:
        gmsh.finalize()


def version(package):
    from importlib.metadata import version as v

    return v(package)


def read_ply(path):
    import plyfile

    ply = plyfile.PlyData.read(path)
    vertex = ply["vertex"]
    names = [p.name for p in vertex.properties]
    return {
        "reader": "plyfile %s" % version("plyfile"),
        "kind": "mesh",
        "format": ply.header.splitlines()[1],
        "vertex_properties": {n: clean(vertex[n]) for n in names},
        "property_types": {p.name: str(p.val_dtype) for p in vertex.properties},
        "faces": len(ply["face"]),
        "vertices": clean(
            [[float(vertex["x"][k]), float(vertex["y"][k]), float(vertex["z"][k])]
             for k in range(len(vertex))]
        ),
    }


def column(values):
    """An (N, 1) array as N scalars, anything else as it is."""
    import numpy as np

    a = np.asarray(values)
    return a[:, 0] if a.ndim == 2 and a.shape[1] == 1 else a


def read_trimesh(path):
    import numpy as np
    import trimesh

    scene = trimesh.load(path, force="scene", process=False)
    meshes = list(scene.geometry.values())
    if len(meshes) != 1:
        raise SystemExit("expected one mesh, found %d" % len(meshes))
    mesh = meshes[0]
    # Normals the file held (not ones trimesh would compute on demand).
    cached = mesh._cache.cache
    normals = cached.get("vertex_normals")
    face_normals = cached.get("face_normals")
    colours = None
    visual = mesh.visual
    if getattr(visual, "kind", None) == "vertex":
        colours = np.asarray(visual.vertex_colors)
    elif "color" in getattr(visual, "vertex_attributes", {}):
        colours = np.asarray(visual.vertex_attributes["color"])
    return {
        "reader": "trimesh %s" % trimesh.__version__,
        "kind": "mesh",
        "vertices": clean(np.asarray(mesh.vertices)),
        "faces": len(mesh.faces),
        "face_indices": clean(np.asarray(mesh.faces)),
        "vertex_normals": None if normals is None else clean(np.asarray(normals)),
        "face_normals": None if face_normals is None else clean(np.asarray(face_normals)),
        "colours": None if colours is None else clean(colours),
        "attributes": {k: clean(column(v)) for k, v in mesh.vertex_attributes.items()},
    }


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("file")
    ap.add_argument("--uv", action="append", default=[], help="U,V to evaluate CAD surfaces at")
    ap.add_argument("--mesh-size", type=float, default=0.0, help="mesh CAD surfaces with gmsh")
    a = ap.parse_args()
    uvs = [[float(t) for t in s.split(",")] for s in a.uv]
    ext = os.path.splitext(a.file)[1].lower()
    if ext in (".step", ".stp", ".igs", ".iges"):
        out = read_cad(a.file, uvs, a.mesh_size)
    elif ext == ".ply":
        out = read_ply(a.file)
    elif ext in (".obj", ".stl", ".glb", ".gltf"):
        out = read_trimesh(a.file)
    else:
        raise SystemExit("readback.py: unknown extension %r" % ext)
    json.dump(out, sys.stdout, allow_nan=False)
    sys.stdout.write("\n")


if __name__ == "__main__":
    main()
