#!/usr/bin/env python3
"""Chessboard pairs for negobs_calib from a session recorded on the device.

    negobs_run --record DIR ... (on the board, the board moved in view)
    tools/calib/session_pairs.py DIR OUT [--every N] [--first K] [--count M]
    negobs_calib --list OUT/stereo_calib.xml --board 9x6 --square-mm 24.5 ...

Writes OUT/left_NNNN.pgm and OUT/right_NNNN.pgm (8-bit PGM, the recorded
luma as it came from the cameras: raw, unrectified, which is what a
calibration needs) for every N-th complete pair, and OUT/stereo_calib.xml
listing them left, right, left, right in OpenCV's format. The session
format is documented in docs/RUNNING.md ("Replay folders and the
recorded-session format"). Exit 0 ok, 1 bad session, 2 bad command line.
"""
import argparse
import os
import sys


def read_size(path):
    words = []
    with open(path) as f:
        for line in f:
            line = line.split("#", 1)[0].split()
            words += line
    if words[:2] != ["negobs-session", "1"]:
        raise ValueError(path + ": not a negobs-session 1 header")
    kv = dict(zip(words[2::2], words[3::2]))
    w, h = int(kv.get("width", 0)), int(kv.get("height", 0))
    if not (16 <= w <= 4096 and 16 <= h <= 4096):
        raise ValueError(path + ": bad width/height")
    return w, h


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("session")
    ap.add_argument("out")
    ap.add_argument("--every", type=int, default=1,
                    help="keep every N-th pair (default 1)")
    ap.add_argument("--first", type=int, default=0)
    ap.add_argument("--count", type=int, default=0,
                    help="at most this many pairs (0: all)")
    a = ap.parse_args()
    if a.every < 1 or a.first < 0 or a.count < 0:
        ap.error("--every >= 1, --first >= 0, --count >= 0")
    try:
        w, h = read_size(os.path.join(a.session, "session.txt"))
        fb = w * h
        n = min(os.path.getsize(os.path.join(a.session, s + ".y"))
                for s in ("left", "right")) // fb
    except (OSError, ValueError) as e:
        print("session_pairs: %s" % e, file=sys.stderr)
        return 1
    if n == 0:
        print("session_pairs: no complete pair in " + a.session, file=sys.stderr)
        return 1
    os.makedirs(a.out, exist_ok=True)
    names = []
    files = {s: open(os.path.join(a.session, s + ".y"), "rb")
             for s in ("left", "right")}
    for k in range(a.first, n, a.every):
        if a.count and len(names) // 2 >= a.count:
            break
        for side in ("left", "right"):
            files[side].seek(k * fb)
            px = files[side].read(fb)
            name = "%s_%04d.pgm" % (side, k)
            with open(os.path.join(a.out, name), "wb") as o:
                o.write(b"P5\n%d %d\n255\n" % (w, h) + px)
            names.append(name)
    with open(os.path.join(a.out, "stereo_calib.xml"), "w") as x:
        x.write('<?xml version="1.0"?>\n<opencv_storage>\n<imagelist>\n')
        x.writelines('"%s"\n' % nm for nm in names)
        x.write("</imagelist>\n</opencv_storage>\n")
    print("session_pairs: %d pairs (%dx%d) -> %s/stereo_calib.xml"
          % (len(names) // 2, w, h, a.out))
    return 0


if __name__ == "__main__":
    sys.exit(main())
