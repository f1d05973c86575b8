#!/usr/bin/env python3
"""No vouch over a pit the detector could not see.

The 6 cm suite rig (320x240, f = 250 px, B = 60 mm; camera 1.1 m /
25 deg, told 1.2 m / 20 deg) walks at 1.2 m/s up to a hole 1.0 m wide,
0.8 m long and 10 cm deep whose bottom is nearly black (negobs_synth
--lower-shade 0.03): no texture there, no match, no candidate. The walk
vouches up to the pit's edge, then nothing while the pit fills the near
rows; once the pit is below the view every frame vouches the floor
beyond it. Before detect_near.c those frames read CLEAR to 4.5 m with
the walker over the pit. The floor nearer than the view was never
vouched while in view, so nothing may be vouched from the feet until it
has been walked over (docs/DETECTION.md, "The floor under the view").

Checked on every frame: clear_to_mm at most 1.1 x the distance to the
pit's near edge while the pit's far edge is still ahead (0 once the
walker is over it), and no CLEAR frame with the pit within 1.5 m. The
walk must vouch up to the pit on some frame and end with the pit below
the view, or it tests nothing.

usage: test_dark_pit.py NEGOBS_SYNTH NEGOBS_PNG WORKDIR
"""
import math
import sys

import walk_test

HOLE_LENGTH_MM = 800
# The floor distance of the bottom row: 1.1 m / tan(25 deg + atan(119.5 /
# 250)) = 0.91 m; nearer, the pit's edge is below the view.
BOTTOM_OF_VIEW_MM = 1100 / math.tan(math.radians(25) + math.atan(119.5 / 250))


def main():
    args = walk_test.setup(__doc__)
    if args is None:
        return 2
    synth, png, work = args
    rows = walk_test.render_and_run(
        synth, png, work, "pit",
        ["--scene", "hole", "--distractors", "0", "--drop-mm", "100",
         "--edge-mm", "3500", "--hole-width-mm", "1000", "--hole-length-mm",
         str(HOLE_LENGTH_MM), "--lower-shade", "0.03", "--frames", "36",
         "--seed", "4"] + walk_test.SUITE_B6_RIG +
        ["--height-mm", "1100", "--pitch-deg", "25",
         "--texture-kind", "asphalt"],
        walk_test.GENERIC_HINT)
    bad = vouched_before = under_view = 0
    for r in rows:
        edge = r["gt"]["edge_range_mm"]
        ahead = edge is not None and edge + HOLE_LENGTH_MM > 0
        ct = r["clear_to_mm"]
        print("frame %2d: pit at %5s mm, %-7s clear_to %4d mm %s" %
              (r["frame"], edge, r["state"], ct, ",".join(r["reasons"])))
        if not ahead:
            continue
        if r["state"] == "CLEAR" and edge > 1500 and ct >= 1500:
            vouched_before += 1
        if edge < BOTTOM_OF_VIEW_MM:
            under_view += 1
        if ct > 1.1 * max(edge, 0) or (r["state"] == "CLEAR" and
                                       edge <= 1500):
            print("  FAIL: vouched over the pit")
            bad += 1
    print("%d frames, %d vouched up to the pit, %d with it below the view, "
          "%d vouched over it" % (len(rows), vouched_before, under_view, bad))
    if len(rows) != 36 or vouched_before == 0 or under_view == 0:
        print("FAIL: the walk does not test the pit")
        return 1
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
