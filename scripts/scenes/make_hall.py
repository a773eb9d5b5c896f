#!/usr/bin/python3
"""Writes scenes/hall.json: 64 lamps over a long hall of pillars, crates and balls (the many-light scene).

The lamps form a 16 x 4 grid under the ceiling, 4 units apart, each with a range (far) of 12 units, so every
point of the floor is within reach of several lamps and their cubes overlap. They are listed in bit-reversed
order of their grid index, so that the first K of them (`--light-count K`) spread along the whole hall for
K = 1, 2, 4, ..., 64 rather than crowding one end. Every fourth lamp sways along the hall, out of step with the
others (its own phase), so frames differ, and reaches 10 units only (lights of one case differ in range, as a
renderer's do); the rest stand still. Casters move too: four rollers sweep 6 units either way along the hall
and three carts 2 units across it, each group in step (their paths are functions of the frame index like a
lamp's), so that the faces they reach must be rendered again while the rest of a still lamp's cube keeps.
With --still the rollers and carts stand where they start (no paths, the same file otherwise): a hall whose
still lamps a static cache keeps whole, where what an atlas re-plan moves is a whole lamp's render again
(docs/many-lights.md, "Holding a size between re-plans").
Usage: scripts/scenes/make_hall.py [--still] [OUT]
"""
import json
import sys

GRID_X, GRID_Z = 16, 4
LAMP_Y, RANGE, SWAYING_RANGE, NEAR = 5.5, 12.0, 10.0, 0.1  # 2.5 below the ceiling: the tutorial's bias holds at cube 512
WARM, COOL = [0.06, 0.05, 0.035], [0.035, 0.045, 0.06]  # 64 unattenuated lamps: dim each one


def bit_reversed(n, bits):
    return int(format(n, f"0{bits}b")[::-1], 2)


def lamp(order):
    grid = bit_reversed(order, 6)  # 6 bits: 64 lamps, the low 2 bits pick the row across the hall
    i, j = grid >> 2, grid & 3
    light = {"type": "point", "position": [-30 + 4 * i, LAMP_Y, -4.5 + 3 * j], "near": NEAR, "far": RANGE,
             "color": WARM if (i + j) % 2 == 0 else COOL}
    if order % 4 == 3:
        light["far"] = SWAYING_RANGE
        light["path"] = {"amplitude": [1.0, 0, 0], "frequency": 0.5, "seconds_per_frame": 0.0166666667,
                         "phase": round(0.7 * order, 4)}
    return light


def hall(still=False):
    doc = {
        "format": "omnishadow-scene/1",
        "description": "Many shadowed point lights: 64 lamps (16 x 4, every fourth swaying) under the ceiling of "
                       "a 64 x 8 x 12 hall of pillars, crates and balls, with rollers and carts moving; written "
                       "by scripts/scenes/make_hall.py.",
        "camera": {"position": [-31, 4.5, 0], "target": [0, 1, 0], "fov_y_degrees": 50, "near": 0.1,
                   "far": 100, "size": [800, 600]},
        "lights": [lamp(k) for k in range(GRID_X * GRID_Z)],
        "objects": [
            {"name": "hall", "type": "box", "translate": [0, 4, 0], "scale": [32, 4, 6], "inside": True,
             "color": [0.76, 0.70, 0.62]},
            {"name": "pillar", "type": "box", "translate": [-28, 4, -3.5], "scale": [0.3, 4, 0.3],
             "color": [0.8, 0.78, 0.74], "array": {"count": [8, 1, 2], "spacing": [8, 0, 7]}},
            {"name": "crate", "type": "box", "translate": [-30, 0.5, 0], "scale": 0.5, "color": [0.9, 0.9, 0.9],
             "rotate": {"degrees": 30, "axis": [0, 1, 0]},
             "array": {"count": [16, 1, 1], "spacing": [4, 0, 0]}},
            {"name": "ball", "type": "sphere", "segments": [24, 12], "translate": [-26, 1.2, -1.8], "scale": 0.6,
             "color": [0.6, 0.7, 0.9], "array": {"count": [7, 1, 2], "spacing": [8, 0, 3.6]}},
            {"name": "roller", "type": "sphere", "segments": [16, 8], "translate": [-24, 0.5, 4.8], "scale": 0.5,
             "color": [0.9, 0.5, 0.3], "array": {"count": [4, 1, 1], "spacing": [16, 0, 0]},
             "path": {"amplitude": [6, 0, 0], "frequency": 0.5, "seconds_per_frame": 0.0166666667, "phase": 0.3}},
            {"name": "cart", "type": "box", "translate": [-20, 0.4, 0], "scale": [0.6, 0.4, 0.4],
             "color": [0.5, 0.8, 0.5], "array": {"count": [3, 1, 1], "spacing": [20, 0, 0]},
             "path": {"amplitude": [0, 0, 2], "frequency": 0.8, "seconds_per_frame": 0.0166666667, "phase": 1.1}},
        ],
    }
    if still:
        for o in doc["objects"]:
            o.pop("path", None)
        doc["description"] = doc["description"].replace("with rollers and carts moving", "its rollers and carts still")
    return doc


def main():
    args = sys.argv[1:]
    still = "--still" in args
    args = [a for a in args if a != "--still"]
    if any(a.startswith("-") for a in args) or len(args) > 1:
        sys.exit("make_hall.py: usage: make_hall.py [--still] [OUT]")
    out = args[0] if args else "scenes/hall.json"
    doc = hall(still)
    # One lamp a line: the file stays readable at 64 lights.
    lines = ["{", '  "format": "omnishadow-scene/1",', f'  "description": {json.dumps(doc["description"])},',
             f'  "camera": {json.dumps(doc["camera"])},', '  "lights": [']
    lines += [f"    {json.dumps(l)}," for l in doc["lights"]]
    lines[-1] = lines[-1].rstrip(",")
    lines += ["  ],", '  "objects": [']
    lines += [f"    {json.dumps(o)}," for o in doc["objects"]]
    lines[-1] = lines[-1].rstrip(",")
    lines += ["  ]", "}"]
    text = "\n".join(lines) + "\n"
    assert json.loads(text) == doc
    with open(out, "w") as f:
        f.write(text)


if __name__ == "__main__":
    main()
