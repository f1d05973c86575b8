#!/usr/bin/env python3
"""No alert from a fit that rises while the start is being checked.

The 6 cm rig (320x240, f = 250 px) at 1.42 m, pitched only 5 deg (its
view starts 2.4 m ahead), walks at 1.2 m/s towards a 15 cm up-step 4 m
ahead on asphalt, told the generic hint 1.2 m / 20 deg, so the start is
unverified (generic draw 36 of negobs_detect_eval). As the riser and the
upper level fill the fit rows, the fit tilts: 1.44 m / 6.6 deg on the
first frame, 1.72 m / 10 deg four frames later. Against that plane the
floor 2.5-2.8 m ahead read as a 73 mm hole, the track confirmed on the
unverified frames and was held IMMINENT for 17 frames. A fit standing
100 mm or more above the lowest fit of the last 5 s (ground_risen) is
no floor to measure deficits against while the start is checked: its
candidates are not trusted (docs/DETECTION.md 6.1, "A fit that rose").

Checked: no frame raises an alert (an up-step is no negative obstacle),
and the fit did rise by 100 mm on some frame, or the walk tests nothing.

usage: test_upstep_fit_rise.py NEGOBS_SYNTH NEGOBS_PNG WORKDIR
"""
import sys

import walk_test

RISE_MM = 100  # ground_drop_mm


def main():
    args = walk_test.setup(__doc__)
    if args is None:
        return 2
    synth, png, work = args
    rows = walk_test.render_and_run(
        synth, png, work, "upstep",
        ["--scene", "upstep", "--drop-mm", "150", "--edge-mm", "4000",
         "--frames", "24", "--seed", "3600367", "--distractors", "0",
         "--texture-kind", "asphalt"] + walk_test.SUITE_B6_RIG +
        ["--height-mm", "1421", "--pitch-deg", "5.1", "--roll-deg", "-4.5",
         "--gain-right", "0.912", "--offset-right", "4"],
        walk_test.GENERIC_HINT)
    fails = 0
    low = min(r["mount"]["height_mm"] for r in rows)
    rose = max(r["mount"]["height_mm"] for r in rows) - low
    for r in rows:
        if r["level"] != "NONE":
            print("FAIL: frame %d: %s %s (fit %d mm / %.1f deg, ground ref "
                  "by %s)" % (r["frame"], r["state"], r["level"],
                              r["mount"]["height_mm"],
                              r["mount"]["pitch_mdeg"] / 1000.0,
                              r["ground_ref"]["by"]))
            fails += 1
    print("%d frames, the fit rose by up to %d mm" % (len(rows), rose))
    if rose < RISE_MM:
        print("FAIL: the fit did not rise by %d mm; the walk tests nothing" %
              RISE_MM)
        return 1
    return 1 if fails else 0


if __name__ == "__main__":
    sys.exit(main())
