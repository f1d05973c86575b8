"""Shared start of the generated-walk tests (test_*.py beside this file):
the command line NEGOBS_SYNTH NEGOBS_PNG WORKDIR and a fresh WORKDIR."""
import json
import os
import shutil
import subprocess
import sys

# The evaluation suite's 6 cm rig (negobs_synth camera arguments) and the
# generic mounting hint its added walks are told (negobs_png arguments).
SUITE_B6_RIG = ["--width", "320", "--height", "240", "--f", "250",
                "--baseline-mm", "60"]
GENERIC_HINT = ["--height-mm", "1200", "--pitch-deg", "20"]


def setup(doc):
    """(synth, png, work) from sys.argv with WORKDIR emptied, or None after
    printing the usage line (the last line of the caller's doc string)."""
    if len(sys.argv) != 4:
        print(doc.strip().splitlines()[-1], file=sys.stderr)
        return None
    synth, png, work = sys.argv[1:]
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    return synth, png, work


def render_and_run(synth, png, work, name, synth_args, png_args):
    """Render a walk with negobs_synth (synth_args after, and overriding,
    the common flat-walk ones: --fps 10 --speed 1.2 --noise 2 --blur 0.5,
    6 distractors), run negobs_png on it (png_args: the mounting hint) and
    return its JSON lines, one dict per frame."""
    seq = os.path.join(work, name)
    jsonl = os.path.join(work, name + ".jsonl")
    subprocess.run([synth, "--scene", "flat", "--drop-mm", "150",
                    "--edge-mm", "8000", "--fps", "10", "--speed", "1.2",
                    "--yaw-deg", "0", "--noise", "2", "--blur", "0.5",
                    "--threads", "1", "--quiet", "--distractors", "6"] +
                   synth_args + ["--out", seq], check=True)
    subprocess.run([png, "--seq", seq, "--out", os.path.join(work, "out"),
                    "--json", jsonl, "--no-overlay", "--quiet"] + png_args,
                   check=True)
    with open(jsonl) as fh:
        return [json.loads(line) for line in fh]


def wearable_flat_walk(synth, png, work, name, frames, seed, height_mm,
                       pitch_deg):
    """Render a flat asphalt walk of the 3 cm wearable rig as
    `negobs_detect_eval --set rigs` draws it (752x480, f = 380 px,
    B = 30 mm, 6 distractors, right camera gain 1.04 and offset -4; seed
    and mounting given), run negobs_png on it without a mounting hint and
    return its JSON lines, one dict per frame."""
    return render_and_run(
        synth, png, work, name,
        ["--frames", str(frames), "--seed", str(seed), "--width", "752",
         "--height", "480", "--f", "380", "--baseline-mm", "30",
         "--height-mm", str(height_mm), "--pitch-deg", str(pitch_deg),
         "--roll-deg", "0", "--texture-kind", "asphalt", "--gain-right",
         "1.04", "--offset-right", "-4"],
        ["--height-mm", "0"])


def generic_flat_walk(synth, png, work, name, frames, seed, mount, camera):
    """Render a flat walk of the 6 cm suite rig as `negobs_detect_eval
    --set generic` draws it (320x240, f = 250 px, B = 60 mm, 6
    distractors, the same shade on both levels, exposure steps of 25 %
    every 8 frames with the right camera one frame late): mount is
    (height_mm, pitch_deg, roll_deg), camera is (texture, gain_right,
    offset_right). Run negobs_png on it with the generic hint the suite
    gives (1.2 m / 20 deg) and return its JSON lines, one dict per
    frame."""
    height_mm, pitch_deg, roll_deg = mount
    texture, gain, offset = camera
    return render_and_run(
        synth, png, work, name,
        ["--frames", str(frames), "--seed", str(seed)] + SUITE_B6_RIG +
        ["--height-mm", str(height_mm), "--pitch-deg", str(pitch_deg),
         "--roll-deg", str(roll_deg), "--texture-kind", texture,
         "--gain-right", str(gain), "--offset-right", str(offset),
         "--lower-shade", "1", "--exposure-pct", "25", "--exposure-every",
         "8", "--exposure-lag-right", "1"],
        GENERIC_HINT)


def check_flat_no_alarm(rows, frames, what):
    """0 when the JSON lines of a flat walk hold `frames` frames, at least
    one raw candidate (else the walk tests nothing; `what` names what
    should raise it) and no frame with a hazard or an alert level; else
    1, after printing why."""
    n = alarms = candidates = 0
    for r in rows:
        n += 1
        candidates += len(r["candidates"])
        if r["hazards"] or r["level"] != "NONE":
            alarms += 1
            print("frame %d: %s %s, hazards %s" %
                  (r["frame"], r["state"], r["level"],
                   [(h["type"], h["range_mm"], h["drop_mm"])
                    for h in r["hazards"]]))
    print("%d frames, %d candidates, %d with a hazard" %
          (n, candidates, alarms))
    if n != frames:
        print("FAIL: %d frames processed" % n)
        return 1
    if candidates == 0:
        print("FAIL: %s raised no candidate; the walk tests nothing" % what)
        return 1
    if alarms:
        print("FAIL: %d frames with a hazard on flat ground" % alarms)
        return 1
    return 0


# The 12 cm rig of the independent renderer's tests (negobs_png arguments:
# told only f, B and the image centre, no mounting hint).
RAYCAST_B12_CAMERA = ["--f", "250", "--baseline-mm", "120", "--cx", "159.5",
                      "--cy", "119.5", "--height-mm", "0"]


def have_numpy():
    """The independent renderer (tools/synth/raycast_walk.py) needs numpy;
    its tests skip (77) without it."""
    try:
        import numpy  # noqa: F401
    except ImportError:
        return False
    return True


def raycast_setup(name, doc):
    """The start of an independent-renderer test: (render, png, work) with
    WORKDIR emptied, or the exit code (77 without numpy, 2 after printing
    the usage line)."""
    if not have_numpy():
        print("%s: numpy is missing; skipped" % name)
        return 77
    args = setup(doc)
    return 2 if args is None else args


def raycast_walk(render, png, work, name, render_args):
    """Render a walk with the independent renderer (render_args: its
    scene, material and mounting), run negobs_png on it told only the 12 cm
    rig's f, B and image centre, and return (the renderer's frames, the
    JSON lines), one dict per frame each."""
    seq = os.path.join(work, name)
    subprocess.run([sys.executable, render, "--out", seq,
                    "--baseline-mm", "120"] + render_args, check=True)
    jsonl = seq + ".jsonl"
    subprocess.run([png, "--seq", seq, "--out", seq + "_out", "--json",
                    jsonl, "--no-overlay", "--quiet"] + RAYCAST_B12_CAMERA,
                   check=True)
    with open(os.path.join(seq, "scene.json")) as fh:
        frames = json.load(fh)["frames"]
    with open(jsonl) as fh:
        rows = [json.loads(line) for line in fh]
    if len(rows) != len(frames):
        raise SystemExit("%s: %d results for %d frames" %
                         (name, len(rows), len(frames)))
    return frames, rows
