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

Checked: every frame processed, candidates raised, and no frame with a
hazard or an alert.

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
    return walk_test.check_flat_no_alarm(rows, 60,
                                         "the matcher's sub-pixel ripple")


if __name__ == "__main__":
    sys.exit(main())
