#!/usr/bin/env python3
"""No vouch past a curb when a generic hint agrees with the lower floor.

The 12 cm rig (320x240, f = 250 px) at 1.09 m / 12 deg walks at 1.2 m/s
towards a 5 cm curb on smooth concrete, the same shade on both levels,
told the generic hint 1.2 m / 20 deg (generic draw 35 of
negobs_detect_eval). The floor it walks on fits 0.97-1.11 m, so the start
stays unverified; once the lower floor beyond the curb fills the fit
rows with the curb at the bottom of the view, the fit reads the camera
about 5 cm higher, 1.15 m, which agrees with the hint. Taken as the
ground under the feet, that frame vouched 4.57 m with the curb 1.44 m
ahead. The hint verifies only when the floor seen since the start agrees
with it too (detect_cue.c, hint_agrees; docs/DETECTION.md 6.1, "The
hint").

Checked on every frame: clear_to_mm at most 1.1 x the curb's distance
while it is ahead, and no CLEAR frame with it within 1.5 m. The walk
must reach a fit that agrees with the hint while the curb is within
1.6 m, or it tests nothing.

usage: test_high_hint.py NEGOBS_SYNTH NEGOBS_PNG WORKDIR
"""
import sys

import walk_test

HINT_MM = 1200
VERIFY_MM = 50  # ground_verify_mm


def main():
    args = walk_test.setup(__doc__)
    if args is None:
        return 2
    synth, png, work = args
    rows = walk_test.render_and_run(
        synth, png, work, "curb",
        ["--scene", "curb", "--drop-mm", "50", "--edge-mm", "3000",
         "--frames", "20", "--seed", "3500337", "--distractors", "0",
         "--texture-kind", "concrete", "--lower-shade", "1"] +
        walk_test.SUITE_B6_RIG[:-2] + ["--baseline-mm", "120",
                                       "--height-mm", "1091",
                                       "--pitch-deg", "12.1",
                                       "--roll-deg", "-6",
                                       "--gain-right", "0.965",
                                       "--offset-right", "-3"],
        walk_test.GENERIC_HINT)
    fails = 0
    agrees = 0
    for r in rows:
        edge = r["gt"]["edge_range_mm"]
        if edge <= 0:
            continue
        if edge <= 1600 and abs(r["mount"]["height_mm"] - HINT_MM) < VERIFY_MM:
            agrees += 1
        vouched = r["clear_to_mm"]
        if r["state"] == "CLEAR":
            vouched = max(vouched, 1500 if r["short_sight"] else 4000)
        if vouched > 1.1 * edge or (r["state"] == "CLEAR" and edge <= 1500):
            print("FAIL: frame %d: %s, vouched %d mm, curb %d mm ahead "
                  "(ground ref by %s)" % (r["frame"], r["state"], vouched,
                                          edge, r["ground_ref"]["by"]))
            fails += 1
    print("%d frames, %d with the fit agreeing with the hint and the curb "
          "within 1.6 m" % (len(rows), agrees))
    if agrees == 0:
        print("FAIL: no fit agreed with the hint near the curb; the walk "
              "tests nothing")
        return 1
    return 1 if fails else 0


if __name__ == "__main__":
    sys.exit(main())
