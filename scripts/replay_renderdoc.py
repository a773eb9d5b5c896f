#!/usr/bin/python3
"""Replays a RenderDoc capture (`omnishadow run --capture`, a GL case's check frame: OUT/captures/<case>.rdc) with
RenderDoc's own replay, headless, and writes the colour target of the frame's last draw as a PNG: the lit image as
the replayed commands made it on this machine's driver, to hold to the harness's own (the timed variant's lighting
pass comes last in a check frame, and equals the checked one bit for bit).

The PNG reads top row first, as the harness's own PNGs do. RenderDoc writes a GL texture's rows top first (it turns
GL's bottom-left origin over) but a Vulkan image's rows as they lie in memory, where the harness's lit frame has
row 0 at the bottom on both APIs (GL's window convention, backends/backend.h): a Vulkan capture's image is turned
over here (python3-pil), so that either API's replay compares with the harness's lit.png as it is.

Runs with Debian's python3-renderdoc (RenderDoc 1.24). RenderDoc replays a GL capture in a context it makes through
EGL: on a machine without a display set EGL_PLATFORM=surfaceless (Mesa).

With --rounds N the whole frame is then replayed N more times, each round timed from the replay's start until one
texel of its last colour target is read back (the read waits for the replayed commands; wall and this process's CPU
time, in ms), and, where the driver offers RenderDoc's EventGPUDuration counter, the frame's GPU time (the sum of
every event's duration, in ms) from a replay of its own; --json writes these with the image's SHA-256 (of its
RGBA pixels, top row first: the PNG's encoding left out), so that the image of a trace replayed on another driver
or commit compares as a checksum, as Mesa's trace CI compares its replays (scripts/replay_trace.py reads it).

Usage: EGL_PLATFORM=surfaceless scripts/replay_renderdoc.py CAPTURE.rdc --out IMAGE.png [--rounds N --json FILE]
Exit: 0, 1 when the capture does not replay, 2 on bad input (one line).
"""
import argparse
import hashlib
import json
import os
import sys
import time


def fail(message, code=2):
    print(f"replay_renderdoc: error: {message}", file=sys.stderr)
    sys.exit(code)


def last_draw(actions):
    """The last action that drew (depth-first, in submission order), or None."""
    found = None
    for a in actions:
        below = last_draw(a.children)
        if below is not None:
            found = below
        elif a.outputs and any(int(o) != 0 for o in a.outputs):
            found = a
    return found


def last_event(actions):
    """The frame's last event id (the largest in the action tree)."""
    return max((max(a.eventId, last_event(a.children)) for a in actions), default=0)


def image_sha256(png):
    from PIL import Image
    return hashlib.sha256(Image.open(png).convert("RGBA").tobytes()).hexdigest()


def timed_rounds(rd, controller, rounds, target):
    """(wall ms per round, CPU ms per round, GPU ms per round or [] where the driver has no duration counter)."""
    end = last_event(controller.GetRootActions())
    walls, cpus, gpus = [], [], []
    for _ in range(rounds):
        wall, cpu = time.perf_counter(), time.process_time()
        controller.SetFrameEvent(end, True)
        controller.PickPixel(target, 0, 0, rd.Subresource(), rd.CompType.Typeless)
        walls.append((time.perf_counter() - wall) * 1e3)
        cpus.append((time.process_time() - cpu) * 1e3)
    if rd.GPUCounter.EventGPUDuration in controller.EnumerateCounters():
        for _ in range(rounds):
            found = controller.FetchCounters([rd.GPUCounter.EventGPUDuration])
            gpus.append(sum(r.value.d for r in found) * 1e3)  # seconds per event
    return walls, cpus, gpus


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("capture")
    parser.add_argument("--out", required=True, help="PNG of the last draw's first colour target")
    parser.add_argument("--rounds", type=int, default=0, help="timed replays of the whole frame (default 0)")
    parser.add_argument("--json", help="the timings and the image's checksum, as JSON")
    args = parser.parse_args()
    if not os.path.isfile(args.capture):
        fail(f"{args.capture}: no such file")
    if args.rounds < 0:
        fail(f"--rounds {args.rounds}: at least 0")
    if args.rounds and not args.json:
        fail("--rounds needs --json (the file the timings go to)")
    try:
        import renderdoc as rd
    except ImportError:
        fail("the renderdoc module is missing (Debian package python3-renderdoc)")
    rd.InitialiseReplay(rd.GlobalEnvironment(), [])
    cap = rd.OpenCaptureFile()
    try:
        result = cap.OpenFile(args.capture, "", None)
        if result != rd.ResultCode.Succeeded:
            fail(f"{args.capture}: not a capture RenderDoc opens: {result}")
        result, controller = cap.OpenCapture(rd.ReplayOptions(), None)
        if result != rd.ResultCode.Succeeded:
            fail(f"{args.capture}: does not replay here: {result}", 1)
        try:
            action = last_draw(controller.GetRootActions())
            if action is None:
                fail(f"{args.capture}: no draw to read back", 1)
            controller.SetFrameEvent(action.eventId, True)
            save = rd.TextureSave()
            save.resourceId = next(o for o in action.outputs if int(o) != 0)
            save.destType = rd.FileType.PNG
            save.alpha = rd.AlphaMapping.Preserve
            result = controller.SaveTexture(save, args.out)
            if result != rd.ResultCode.Succeeded:
                fail(f"{args.capture}: the replayed image cannot be saved: {result}", 1)
            if cap.DriverName() == "Vulkan":
                from PIL import Image, ImageOps
                ImageOps.flip(Image.open(args.out)).save(args.out)
            print(f"{args.capture}: replayed to event {action.eventId}; its colour target in {args.out}")
            if args.json:
                walls, cpus, gpus = timed_rounds(rd, controller, args.rounds, save.resourceId)
                doc = {"driver": cap.DriverName(), "events": last_event(controller.GetRootActions()),
                       "image_sha256": image_sha256(args.out), "wall_ms": walls, "cpu_ms": cpus, "gpu_ms": gpus}
                with open(args.json + ".tmp", "w") as f:
                    json.dump(doc, f, indent=1)
                os.replace(args.json + ".tmp", args.json)
        finally:
            controller.Shutdown()
    finally:
        cap.Shutdown()
        rd.ShutdownReplay()


if __name__ == "__main__":
    main()
