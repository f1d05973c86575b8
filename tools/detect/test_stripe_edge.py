#!/usr/bin/env python3
"""No alarm from the long edges of a painted stripe across the path.

A flat worn-asphalt walk of the 6 cm suite rig as the fifth draw of
`negobs_detect_eval --set generic` renders it
(g1_flat_0_worn_s8.0_H1442_p28_r6_500364: 1.44 m / 28 deg, roll 5.8
deg, right camera gain 1.1, detector told 1.2 m / 20 deg). A 213 mm
white stripe across the path saturates both images; the 5x5 windows on
its long edges hold plenty of variance, all of it vertical, so every
disparity along the row matches about as well and the matcher returns
disparities 1-3 px low with high confidence: a 0.8 m "hole". The box
test now asks each window for horizontal structure too
(detect_texture.c); without it, and with the scan reading past one or
two rows above the model, the walk was IMMINENT on 6 frames.

Every frame of the flat walk must be free of hazards (no CAUTION, no
IMMINENT), and the stripe must still raise a raw candidate (else the
walk tests nothing).

usage: test_stripe_edge.py NEGOBS_SYNTH NEGOBS_PNG WORKDIR
"""
import sys

import walk_test


def main():
    args = walk_test.setup(__doc__)
    if args is None:
        return 2
    synth, png, work = args
    rows = walk_test.generic_flat_walk(synth, png, work, "flat", 30, 500364,
                                       (1442, 28.0, 5.8), ("worn", 1.1, -3))
    return walk_test.check_flat_no_alarm(rows, 30, "the stripe")


if __name__ == "__main__":
    sys.exit(main())
