#!/usr/bin/env python3
"""No alarm from a painted stripe on a narrow rig.

A 3 cm wearable rig (752x480, f = 380 px, B = 30 mm, camera 1.2 m /
20 deg, no mounting hint) walks at 1.2 m/s over flat asphalt with painted
stripes, shadows and dark patches (a walk of the second draw of
`negobs_detect_eval --set rigs`, k7_flat_0_asphalt_s8.0_200122). On this
rig a 5 cm drop at 1.5 m is a 0.28 px deficit, and inside a bright stripe
of flat paint the matcher wanders by 0.2-0.4 px: the stripe read as a
4-7 cm hole, was confirmed and held IMMINENT from frame 6 on. A deficit
read in a box without texture above the sensor noise no longer starts or
confirms a track (detect_texture.c).

Every frame of the flat walk must be free of hazards (no CAUTION, no
IMMINENT).

usage: test_paint_stripe.py NEGOBS_SYNTH NEGOBS_PNG WORKDIR
"""
import sys

import walk_test


def main():
    args = walk_test.setup(__doc__)
    if args is None:
        return 2
    synth, png, work = args
    rows = walk_test.wearable_flat_walk(synth, png, work, "flat", 14, 200122,
                                        1200, 20)
    return walk_test.check_flat_no_alarm(rows, 14, "the stripe")


if __name__ == "__main__":
    sys.exit(main())
