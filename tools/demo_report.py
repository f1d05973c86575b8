#!/usr/bin/env python3
"""Turn negobs_png's JSON lines into one readable line per frame.

usage: demo_report.py FRAMES.jsonl
Each line: frame, detector state, alert pattern, nearest confirmed hazard
(type, range, drop height), and the ground-truth edge range when the
sequence came from negobs_synth.
"""
import json
import sys


def main(path):
    for raw in open(path, encoding="utf-8"):
        raw = raw.strip()
        if not raw:
            continue
        f = json.loads(raw)
        hz = f.get("hazards") or []
        if hz:
            h = min(hz, key=lambda x: x.get("range_mm", 1 << 30))
            what = "%s %d mm drop at %.2f m (%s)" % (
                h["type"].lower(), h.get("drop_mm", 0), h["range_mm"] / 1000.0,
                ",".join(x.lower() for x in h.get("flags", [])))
        elif f.get("state") == "NO_INFO":
            what = "cannot see: " + ",".join(r.lower() for r in f.get("reasons", []))
        else:
            what = "-"
        gt = f.get("gt") or {}
        truth = ""
        if gt.get("edge_range_mm") is not None:
            truth = "   [truth: edge at %.2f m]" % (gt["edge_range_mm"] / 1000.0)
        print("frame %3d  %-7s  motor %-13s %s%s" % (
            f["frame"], f.get("state", "?").lower(),
            f.get("pattern", "?").lower(), what, truth))


if __name__ == "__main__":
    if len(sys.argv) != 2:
        print(__doc__, file=sys.stderr)
        sys.exit(2)
    main(sys.argv[1])
