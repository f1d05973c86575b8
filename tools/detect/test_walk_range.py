#!/usr/bin/env python3
"""Floor nearer than the matcher's disparity range (docs/DETECTION.md
section 4, "Beyond the matcher's range").

A chest camera with a long focal length and a wide baseline (640x360,
f = 700 px, B = 120 mm, 0.9 m / 35 deg, the last camera of
`negobs_detect_eval --set rigs`) sees the floor at the bottom row at about
73 px, and negobs_png searches 0-63 px (its default). Two generated walks
at 1.2 m/s, told the generic 1.2 m / 20 deg:

1. Flat asphalt, 3 s. The rows beyond the range read the range's top and
   then whatever the matcher carries there; fitted and scanned with the
   rest they made the fit 1.04-1.07 m / 43-45 deg and a "drop" at the
   feet: IMMINENT on 28 of 30 frames. Now: no hazard and no alert on any
   frame, the mounting measured within 60 mm and 2 deg of the truth
   (0.9 m / 35 deg; the walk bobs 25 mm and sways 1 deg), and the walk
   verifies its start, so the last 10 frames are CLEAR.
2. A 15 cm curb 4 m ahead: it is confirmed while it is 1.5-2.2 m away,
   within 10 % of its true distance, as with a range of 95 px.

usage: test_walk_range.py NEGOBS_SYNTH NEGOBS_PNG WORKDIR
"""
import json
import os
import subprocess
import sys

import walk_test

H_MM, PITCH = 900, 35


def walk(synth, png, work, name, scene):
    seq = os.path.join(work, name)
    jsonl = os.path.join(work, name + ".jsonl")
    subprocess.run([synth, "--scene", scene, "--drop-mm", "150",
                    "--edge-mm", "4000", "--frames", "30", "--speed", "1.2",
                    "--fps", "10", "--width", "640", "--height", "360",
                    "--f", "700", "--baseline-mm", "120",
                    "--height-mm", str(H_MM), "--pitch-deg", str(PITCH),
                    "--noise", "2", "--seed", "5", "--texture-kind",
                    "asphalt", "--threads", "1", "--quiet", "--out", seq],
                   check=True)
    subprocess.run([png, "--seq", seq, "--out", os.path.join(work, "out"),
                    "--json", jsonl, "--no-overlay", "--quiet",
                    "--height-mm", "1200", "--pitch-deg", "20"], check=True)
    with open(jsonl) as fh:
        return [json.loads(line) for line in fh]


def verdicts(rows):
    return " ".join("%s%s" % (r["state"][0], r["level"][0]) for r in rows)


def check_flat(synth, png, work):
    """1 when the flat walk alerts, mismeasures or stays unverified."""
    rows = walk(synth, png, work, "flat", "flat")
    print("flat:", verdicts(rows))
    if len(rows) != 30:
        print("FAIL: %d frames processed" % len(rows))
        return 1
    if rows[0]["stereo"]["range"][1] > 63:
        print("FAIL: the walk was searched to %d px, not 63"
              % rows[0]["stereo"]["range"][1])
        return 1
    failed = 0
    alarms = [r["frame"] for r in rows if r["hazards"] or r["level"] != "NONE"]
    if alarms:
        print("FAIL: hazard or alert on frames %s" % alarms)
        failed = 1
    for r in rows:
        m = r["mount"]
        if m["source"] != "estimated" or abs(m["height_mm"] - H_MM) > 60 or \
                abs(m["pitch_mdeg"] / 1000.0 - PITCH) > 2.0:
            print("FAIL: frame %d measured %s" % (r["frame"], m))
            failed = 1
            break
    if any(r["state"] != "CLEAR" for r in rows[20:]):
        print("FAIL: not CLEAR on the last 10 frames")
        failed = 1
    return failed


def check_curb(synth, png, work):
    """1 when the curb is not confirmed at 1.5-2.2 m within 10 %."""
    rows = walk(synth, png, work, "curb", "curb")
    print("curb:", verdicts(rows))
    confirmed = [r for r in rows if r["hazards"] and
                 1500 <= r["gt"]["edge_range_mm"] <= 2200]
    failed = 0
    if len(confirmed) < 4:
        print("FAIL: the curb was confirmed on %d frames at 1.5-2.2 m"
              % len(confirmed))
        failed = 1
    for r in confirmed:
        got = min(h["range_mm"] for h in r["hazards"])
        true = r["gt"]["edge_range_mm"]
        if abs(got - true) > 0.1 * true:
            print("FAIL: frame %d read %d mm for %d mm" % (r["frame"], got, true))
            failed = 1
    return failed


def main():
    args = walk_test.setup(__doc__)
    if args is None:
        return 2
    failed = check_flat(*args) | check_curb(*args)
    print("FAIL" if failed else "PASS")
    return failed


if __name__ == "__main__":
    sys.exit(main())
