#!/usr/bin/env python3
"""No alert on flat paving from the matcher's sub-pixel ripple.

A flat paving walk of generic draw 41 (`g1_flat_0_paving_s8.0_H1566_p28_r1`:
the suite's 6 cm rig at 1.57 m / 27.7 deg, told 1.2 m / 20 deg). Over the
tiles' smooth interiors the strips' medians run -0.15 px and +0.1 px in
turn as the floor disparity runs through each whole pixel (pixel
locking; OpenCV's SGBM reads the same wave at the same rows), and the
negative half passed the rule as 40-70 mm "drops" 1.4-2.2 m ahead on most
frames: held IMMINENT on 26 of the 30 frames. Over one whole pixel of floor
disparity past each such edge the ripple averages out, which a lower
surface does not: those candidates carry UNIT_SHALLOW and confirm nothing
(docs/DETECTION.md 5, "One pixel of floor").

Checked: every frame processed, candidates raised, all of them
UNIT_SHALLOW, and no frame with a hazard or an alert.

usage: test_paving_ripple.py NEGOBS_SYNTH NEGOBS_PNG WORKDIR
"""
import sys

import walk_test


def main():
    args = walk_test.setup(__doc__)
    if args is None:
        return 2
    synth, png, work = args
    rows = walk_test.render_and_run(
        synth, png, work, "paving",
        walk_test.SUITE_B6_RIG +
        ["--frames", "30", "--seed", "4100354", "--height-mm", "1566",
         "--pitch-deg", "27.7", "--roll-deg", "1.4", "--texture-kind",
         "paving", "--gain-right", "0.966", "--offset-right", "5",
         "--exposure-pct", "25", "--exposure-every", "8",
         "--exposure-lag-right", "0"],
        walk_test.GENERIC_HINT)
    if walk_test.check_flat_no_alarm(rows, 30,
                                     "the matcher's sub-pixel ripple"):
        return 1
    flagged = sum(1 for r in rows for c in r["candidates"]
                  if "UNIT_SHALLOW" in c["flags"])
    total = sum(len(r["candidates"]) for r in rows)
    print("%d of %d candidates UNIT_SHALLOW" % (flagged, total))
    if flagged != total:
        print("FAIL: a candidate of the ripple is not UNIT_SHALLOW")
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
