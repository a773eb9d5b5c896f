#!/usr/bin/python3
"""Writes scenes/extremes/: the scenes of the numerical-stability suite, each with its purpose in `description`.

All are the point-shadow tutorial's room (a 10-unit room, five cubes, a point light) pushed to one extreme at a time, so that an
error can be attributed to that extreme: near/far ratios from 1:25 to 1:1e6, the whole scene translated far from
the origin, the light on a surface and inside a caster, receivers at grazing angles, casters on cube-face seams and
corners, zero-area triangles, and a light moving by tiny steps (for flicker); and two for the moments filters'
hazards: light bleeding between two occluders, and nearly singular moments (the light at a sphere's centre). Regenerate after changing this
script: scripts/experiments/make_extreme_scenes.py (the files are committed so the suite needs no generation step).
"""
import copy
import json
import os

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
OUT = os.path.join(ROOT, "scenes", "extremes")

CUBES = [
    {"name": "cube1", "type": "box", "translate": [4, -3.5, 0], "scale": 0.5},
    {"name": "cube2", "type": "box", "translate": [2, 3, 1], "scale": 0.75},
    {"name": "cube3", "type": "box", "translate": [-3, -1, 0], "scale": 0.5},
    {"name": "cube4", "type": "box", "translate": [-1.5, 1, 1.5], "scale": 0.5},
    {"name": "cube5", "type": "box", "translate": [-1.5, 2, -3], "rotate": {"degrees": 60, "axis": [1, 0, 1]},
     "scale": 0.75},
]


BLEEDING_DESCRIPTION = ("light bleeding: a small box near the light casts its shadow across the foot of a thin wall; behind "
                        "the wall's foot the receiver is barely beyond the wall, so wherever the filter's footprint spans "
                        "both occluders' depths the moments' variance dwarfs that gap and the Chebyshev / Hamburger bounds "
                        "let light through (bleed reduction lbr<a> trades it for darker penumbrae)")
FLAT_DESCRIPTION = ("the light at the centre of a sphere of radius 4: every cube texel holds nearly one distance, so the "
                    "moments' variance (vsm) and Hankel matrix (msm) are singular up to rounding; with the lookup bias "
                    "off (bias0) only the variance floor and moment bias (floor<s>) keep the sphere from shadowing "
                    "itself; one box casts a shadow")


def room(description, light, objects=None, camera=None):
    return {
        "format": "omnishadow-scene/1",
        "description": description,
        "camera": camera or {"position": [0, 0, 3], "target": [0, 0, 2], "fov_y_degrees": 45, "near": 0.1,
                             "far": 100, "size": [400, 300]},
        "light": light,
        "objects": [{"name": "room", "type": "box", "scale": 5, "inside": True}] + (objects or copy.deepcopy(CUBES)),
    }


def point(position=(0, 0, 0), near=1.0, far=25.0, path=None):
    light = {"type": "point", "position": list(position), "near": near, "far": far, "color": [0.3, 0.3, 0.3]}
    if path:
        light["path"] = path
    return light


def translated(scene, offset):
    s = copy.deepcopy(scene)
    for o in s["objects"]:
        o["translate"] = [a + offset for a in o.get("translate", [0, 0, 0])]
    s["light"]["position"] = [a + offset for a in s["light"]["position"]]
    for key in ("position", "target"):
        s["camera"][key] = [a + offset for a in s["camera"][key]]
    return s


def main():
    os.makedirs(OUT, exist_ok=True)
    scenes = {}
    for name, near, far in [("nf_25", 1.0, 25.0), ("nf_1e3", 0.1, 100.0), ("nf_1e4", 0.01, 100.0),
                            ("nf_1e5", 1.0, 1e5), ("nf_1e6", 1e-4, 100.0)]:
        scenes[name] = room(f"near/far {near:g}:{far:g} (ratio 1:{far / near:g}): how far linear depth, each depth "
                            "format and R32F distance hold when the range is stretched", point(near=near, far=far))
    base = room("the room at the origin, for the far-from-origin family", point())
    for exp in (3, 5, 6):
        s = translated(base, 10.0 ** exp)
        s["description"] = (f"the room, light and camera translated by 1e{exp} on every axis: float cancellation in "
                            "world-space distances (ulp at 1e6 is 0.06)")
        scenes[f"offset_1e{exp}"] = s
    scenes["light_on_floor"] = room("the light exactly on the floor (y = -5): distances of 0 and surfaces through "
                                    "the light", point(position=(0, -5, 0), near=0.01))
    scenes["light_in_caster"] = room("the light inside cube1: every direction is blocked at distance < 1",
                                     point(position=(4, -3.5, 0), near=0.01))
    scenes["grazing"] = room("the light 0.05 above the floor: the floor is lit at grazing angles, where bias and "
                             "texel size decide acne", point(position=(0, -4.95, 0), near=0.01))
    # Casters on the diagonals from the light: their shadows fall across cube-face seams and corners, where the
    # face selection ties.
    seams = [{"name": f"seam{i}", "type": "box", "translate": t, "scale": 0.3} for i, t in enumerate(
        [[2, 2, 2], [-2, 2, -2], [2, -2, 0], [0, 2, -2], [-2.5, -2.5, 2.5], [2, 0, 2]])]
    scenes["seams"] = room("casters on the light's diagonals: shadows across face seams (|x| = |y|) and corners "
                           "(|x| = |y| = |z|), where the face selection ties", point(), objects=seams,
                           camera={"position": [-4, -4, -4], "target": [5, 5, 5], "fov_y_degrees": 70, "near": 0.1,
                                   "far": 100, "size": [400, 300]})
    # The tetrahedral layout's own seams (backends/common/tetrahedron.h): its cells' corners lie along the axes'
    # antipodes ((1, 1, -1) and the like), the midpoints of their edges along the coordinate axes, and each edge in a
    # plane where two faces tie (y + z = 0 between the faces along (1, 1, 1) and (1, -1, -1)); there the face's
    # frustum box is at its widest past the cell, where a layer's texels are most stretched. Boxes on corners and
    # midpoints, and two bars lying in tie planes, whose shadows run along the edges.
    tetra = [{"name": f"corner{i}", "type": "box", "translate": t, "scale": 0.3} for i, t in enumerate(
        [[2, 2, -2], [2, -2, 2], [-2, 2, 2]])]
    tetra += [{"name": f"midpoint{i}", "type": "box", "translate": t, "scale": 0.3} for i, t in enumerate(
        [[0, 0, 2.5], [0, -2.5, 0]])]
    tetra += [{"name": "bar_y_plus_z", "type": "box", "translate": [2.5, 0, 0], "scale": [0.1, 1.2, 0.1],
               "rotate": {"degrees": -45, "axis": [1, 0, 0]}},
              {"name": "bar_x_plus_z", "type": "box", "translate": [0, 2.5, 0], "scale": [1.2, 0.1, 0.1],
               "rotate": {"degrees": 45, "axis": [0, 1, 0]}}]
    scenes["tetra_seams"] = room("casters where the tetrahedral layout's faces meet: on its cells' corners (the "
                                 "axes' antipodes), on its edges' midpoints (the coordinate axes), and two bars in the "
                                 "planes where two faces tie, whose shadows run along the edges", point(),
                                 objects=tetra,
                                 camera={"position": [-4, -4, -4], "target": [5, 5, 5], "fov_y_degrees": 70,
                                         "near": 0.1, "far": 100, "size": [400, 300]})
    scenes["degenerate"] = room("zero-area triangles (repeated and collinear vertices) mixed with real ones: they must "
                                "rasterise to nothing and change no value", point(),
                                objects=copy.deepcopy(CUBES) + [{"name": "degenerate", "type": "obj",
                                                                 "file": "degenerate.obj", "translate": [0, -2, -2]}])
    scenes["stability_tiny_steps"] = room(
        "the light moving by about 1e-5 units per frame (amplitude 1e-3): shadows must not flicker between frames",
        point(path={"amplitude": [0.001, 0.0007, 0.0013], "frequency": 0.5, "seconds_per_frame": 0.0166666667}))
    # The moments filters' hazards (run_extremes.sh's moments runs). Bleeding: a small box near the light casts across
    # the foot of a thin wall, where the receiver is barely beyond the wall.
    scenes["bleeding"] = room(BLEEDING_DESCRIPTION, point(position=(0, 1, 0), near=0.5, far=12.0), objects=[
        {"name": "near_occluder", "type": "box", "translate": [0.65, -0.5, 0.3], "scale": 0.2},
        {"name": "thin_wall", "type": "box", "translate": [2.2, -3, 0], "scale": [0.05, 2, 1.5]}],
        camera={"position": [4.5, 0.5, -4.0], "target": [2.4, -5, 0.3], "fov_y_degrees": 70, "near": 0.05,
                "far": 100, "size": [400, 300]})
    # Singular moments: the light at the centre of a sphere (no room), one box casting.
    flat = room(FLAT_DESCRIPTION, point(near=0.5, far=6.0), camera={
        "position": [0, 0, 0.5], "target": [0, -1, -3], "fov_y_degrees": 70, "near": 0.05, "far": 100,
        "size": [400, 300]})
    flat["objects"] = [{"name": "shell", "type": "sphere", "segments": [192, 96], "scale": 4, "inside": True},
                       {"name": "box", "type": "box", "translate": [0.6, -1.2, -2], "scale": 0.3}]
    scenes["flat_moments"] = flat
    for name, scene in scenes.items():
        with open(os.path.join(OUT, name + ".json"), "w") as f:
            json.dump(scene, f, indent=1)
            f.write("\n")
    with open(os.path.join(OUT, "degenerate.obj"), "w") as f:
        f.write("# zero-area triangles: repeated vertices, collinear vertices; and one real triangle\n"
                "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nv 1 1 0\n"
                "f 1 1 1\nf 1 2 3\nf 2 2 4\nf 1 2 5\n")
    print(f"wrote {len(scenes)} scenes to {OUT}")


if __name__ == "__main__":
    main()
