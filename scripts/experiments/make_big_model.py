#!/usr/bin/python3
"""Writes a large model for measuring the loaders (the loader's time for a 1M-triangle model).

A wavy UV sphere of LON x LAT quads, two triangles each (default 1000 x 500 = 1,000,000 triangles), as
  OUT.glb  one indexed glTF 2.0 mesh (float32 positions and normals, uint32 indices) in a GLB container, and
  OUT.obj  the same triangles as OBJ text (v / vn / f v//n),
so that `omnishadow run --scene OUT.glb ...` prints the load time in its summary ("Scenes loaded ...") and in
results.json (phases.scene_loads). Generated, not committed (the .glb is ~24 MB, the .obj ~70 MB).

  /usr/bin/python3 scripts/experiments/make_big_model.py /tmp/big [--lon 1000 --lat 500]
"""
import argparse
import json
import struct

import numpy as np


def sphere(lon, lat):
    # Rows j = 0..lat from the north pole; the radius ripples so that the model casts shadows on itself.
    theta = np.linspace(0.0, np.pi, lat + 1)
    phi = np.linspace(0.0, 2.0 * np.pi, lon, endpoint=False)
    t, p = np.meshgrid(theta, phi, indexing="ij")
    r = 1.0 + 0.05 * np.sin(12 * p) * np.sin(8 * t)
    pos = np.stack([r * np.sin(t) * np.cos(p), r * np.cos(t), -r * np.sin(t) * np.sin(p)], axis=-1)
    nrm = pos / np.linalg.norm(pos, axis=-1, keepdims=True)  # the smooth sphere's normal: good enough for lighting
    pos = pos.reshape(-1, 3).astype(np.float32)
    nrm = nrm.reshape(-1, 3).astype(np.float32)
    j, i = np.meshgrid(np.arange(lat), np.arange(lon), indexing="ij")
    a = j * lon + i
    b = j * lon + (i + 1) % lon
    c = (j + 1) * lon + i
    d = (j + 1) * lon + (i + 1) % lon
    # Counter-clockwise seen from outside.
    tris = np.concatenate([np.stack([a, c, b], -1).reshape(-1, 3), np.stack([b, c, d], -1).reshape(-1, 3)])
    return pos, nrm, tris.astype(np.uint32)


def write_glb(path, pos, nrm, tris):
    blobs = [pos.tobytes(), nrm.tobytes(), tris.tobytes()]
    offsets = np.cumsum([0] + [len(b) for b in blobs])
    gltf = {
        "asset": {"version": "2.0", "generator": "omnishadow make_big_model.py"},
        "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2}]}],
        "buffers": [{"byteLength": int(offsets[-1])}],
        "bufferViews": [{"buffer": 0, "byteOffset": int(offsets[k]), "byteLength": len(blobs[k])} for k in range(3)],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": len(pos), "type": "VEC3",
             "min": pos.min(0).tolist(), "max": pos.max(0).tolist()},
            {"bufferView": 1, "componentType": 5126, "count": len(nrm), "type": "VEC3"},
            {"bufferView": 2, "componentType": 5125, "count": tris.size, "type": "SCALAR"},
        ],
    }
    text = json.dumps(gltf).encode()
    text += b" " * (-len(text) % 4)
    binary = b"".join(blobs)
    binary += b"\0" * (-len(binary) % 4)
    with open(path, "wb") as f:
        f.write(struct.pack("<III", 0x46546C67, 2, 12 + 8 + len(text) + 8 + len(binary)))
        f.write(struct.pack("<II", len(text), 0x4E4F534A) + text)
        f.write(struct.pack("<II", len(binary), 0x004E4942) + binary)


def write_obj(path, pos, nrm, tris):
    with open(path, "w") as f:
        f.write("# omnishadow make_big_model.py\n")
        np.savetxt(f, pos, fmt="v %.6f %.6f %.6f")
        np.savetxt(f, nrm, fmt="vn %.6f %.6f %.6f")
        t = tris + 1
        np.savetxt(f, np.repeat(t, 2, axis=1), fmt="f %d//%d %d//%d %d//%d")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("out", help="path without extension: OUT.glb and OUT.obj are written")
    ap.add_argument("--lon", type=int, default=1000)
    ap.add_argument("--lat", type=int, default=500)
    a = ap.parse_args()
    pos, nrm, tris = sphere(a.lon, a.lat)
    write_glb(a.out + ".glb", pos, nrm, tris)
    write_obj(a.out + ".obj", pos, nrm, tris)
    print(f"{a.out}.glb, {a.out}.obj: {len(tris)} triangles, {len(pos)} vertices")


if __name__ == "__main__":
    main()
