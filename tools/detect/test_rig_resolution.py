#!/usr/bin/env python3
"""No alert on flat ground from deficits finer than the matcher resolves.

The 3 cm head-worn rig of `negobs_detect_eval --set rigs` (752x480,
f = 380 px, B = 30 mm, 1.7 m / 15 deg, no hint) walks 6 s over flat
asphalt (the walk k8_flat_0_asphalt_s8.0_2400128 of rigs draw 24). Its
floor 2 m ahead has a disparity of about 4.4 px, where the rule's 40 mm
near threshold is a deficit of 1.6/16 px, rounded down to one sixteenth:
the sub-pixel ripple along a row (pixel locking) passes it, and 21-48 mm
"holes" at 1.8-2.1 m confirmed and were held IMMINENT for 34 frames. No
row counts a deficit below 2/16 px now (detect_internal.h,
DEFICIT_MIN_Q4; docs/DETECTION.md 5, "The rig's resolution").

Checked: no frame raises an alert.

usage: test_rig_resolution.py NEGOBS_SYNTH NEGOBS_PNG WORKDIR
"""
import sys

import walk_test


def main():
    args = walk_test.setup(__doc__)
    if args is None:
        return 2
    synth, png, work = args
    rows = walk_test.wearable_flat_walk(synth, png, work, "head", 60, 2400128,
                                        1700, 15)
    alerts = [r for r in rows if r["level"] != "NONE"]
    for r in alerts:
        print("FAIL: frame %d: %s %s, hazards %s" %
              (r["frame"], r["state"], r["level"],
               [(h["type"], h["range_mm"], h["drop_mm"])
                for h in r["hazards"]]))
    print("%d frames, %d with an alert" % (len(rows), len(alerts)))
    return 1 if alerts else 0


if __name__ == "__main__":
    sys.exit(main())
