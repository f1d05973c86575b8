"""Shared start of the generated-walk tests (test_*.py beside this file):
the command line NEGOBS_SYNTH NEGOBS_PNG WORKDIR and a fresh WORKDIR."""
import json
import os
import shutil
import subprocess
import sys


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


def wearable_flat_walk(synth, png, work, name, frames, seed, height_mm,
                       pitch_deg):
    """Render a flat asphalt walk of the 3 cm wearable rig as
    `negobs_detect_eval --set rigs` draws it (752x480, f = 380 px,
    B = 30 mm, 6 distractors, right camera gain 1.04 and offset -4; seed
    and mounting given), run negobs_png on it without a mounting hint and
    return its JSON lines, one dict per frame."""
    seq = os.path.join(work, name)
    jsonl = os.path.join(work, name + ".jsonl")
    subprocess.run([synth, "--scene", "flat", "--drop-mm", "150",
                    "--edge-mm", "8000", "--frames", str(frames), "--fps",
                    "10", "--speed", "1.2", "--yaw-deg", "0", "--seed",
                    str(seed), "--noise", "2", "--blur", "0.5", "--width",
                    "752", "--height", "480", "--f", "380", "--baseline-mm",
                    "30", "--height-mm", str(height_mm), "--pitch-deg",
                    str(pitch_deg), "--threads", "1", "--quiet",
                    "--distractors", "6", "--roll-deg", "0",
                    "--texture-kind", "asphalt", "--gain-right", "1.04",
                    "--offset-right", "-4", "--out", seq], check=True)
    subprocess.run([png, "--seq", seq, "--out", os.path.join(work, "out"),
                    "--json", jsonl, "--no-overlay", "--quiet",
                    "--height-mm", "0"], check=True)
    with open(jsonl) as fh:
        return [json.loads(line) for line in fh]


def generic_flat_walk(synth, png, work, name, frames, seed, mount, camera):
    """Render a flat walk of the 6 cm suite rig as `negobs_detect_eval
    --set generic` draws it (320x240, f = 250 px, B = 60 mm, 6
    distractors, the same shade on both levels, exposure steps of 25 %
    every 8 frames with the right camera one frame late): mount is
    (height_mm, pitch_deg, roll_deg), camera is (texture, gain_right,
    offset_right). Run negobs_png on it with the generic hint the suite
    gives (1.2 m / 20 deg) and return its JSON lines, one dict per
    frame."""
    seq = os.path.join(work, name)
    jsonl = os.path.join(work, name + ".jsonl")
    height_mm, pitch_deg, roll_deg = mount
    texture, gain, offset = camera
    subprocess.run([synth, "--scene", "flat", "--drop-mm", "150",
                    "--edge-mm", "8000", "--frames", str(frames), "--fps",
                    "10", "--speed", "1.2", "--yaw-deg", "0", "--seed",
                    str(seed), "--noise", "2", "--blur", "0.5", "--width",
                    "320", "--height", "240", "--f", "250", "--baseline-mm",
                    "60", "--height-mm", str(height_mm), "--pitch-deg",
                    str(pitch_deg), "--threads", "1", "--quiet",
                    "--distractors", "6", "--roll-deg", str(roll_deg),
                    "--texture-kind", texture, "--gain-right", str(gain),
                    "--offset-right", str(offset), "--lower-shade", "1",
                    "--exposure-pct", "25", "--exposure-every", "8",
                    "--exposure-lag-right", "1", "--out", seq], check=True)
    subprocess.run([png, "--seq", seq, "--out", os.path.join(work, "out"),
                    "--json", jsonl, "--no-overlay", "--quiet",
                    "--height-mm", "1200", "--pitch-deg", "20"], check=True)
    with open(jsonl) as fh:
        return [json.loads(line) for line in fh]
