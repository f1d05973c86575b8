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
    frames = alarms = candidates = 0
    for r in rows:
        frames += 1
        candidates += len(r["candidates"])
        if r["hazards"] or r["level"] != "NONE":
            alarms += 1
            print("frame %d: %s %s, hazards %s" %
                  (r["frame"], r["state"], r["level"],
                   [(h["type"], h["range_mm"], h["drop_mm"])
                    for h in r["hazards"]]))
    print("%d frames, %d candidates, %d with a hazard" %
          (frames, candidates, alarms))
    if frames != 14:
        print("FAIL: %d frames processed" % frames)
        return 1
    if candidates == 0:
        print("FAIL: the stripe raised no candidate; the walk tests nothing")
        return 1
    if alarms:
        print("FAIL: %d frames with a hazard on flat ground" % alarms)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
