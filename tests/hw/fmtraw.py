#!/usr/bin/env python3
"""fmtraw: camera-format frames for the run-fmt-* emulated sections.

usage: fmtraw.py SCENE_DIR OUT_DIR [FRAME ...]

SCENE_DIR holds left.y and right.y (png2raw.py: the original 320x240 grey
frames, concatenated).  For the chosen frames (default 0 8 16) OUT_DIR gets
what a camera in each format would deliver, laid out so that negobs_run's
split, crop and 2x2 binning give the original 320x240 pixels back exactly,
and so that a wrong split, crop offset, bin or bit shift does not:

  sbs.raw        GREY 1280x720, both eyes side by side (each eye 640x720):
                 rows 120..599 hold the 2x2-binned eye, the 120 rows above
                 are 0 and the 120 below 255 (negobs_run's centre crop of
                 640x480 out of 640x720 starts at row 120)
  y16-left.raw, y16-right.raw   Y16 640x480, little-endian 16-bit samples
  y10-left.raw, y10-right.raw   Y10 640x480, 10 bits in 16-bit words
  left.md5, right.md5           "MD5 INDEX" of each original frame, INDEX
                                counting the chosen frames from 0

Every 2x2 block of the binned eye averages exactly to the original value
but its samples differ from it (GREY p+1, p-1; Y16 p*256+128+-144; Y10
4p+2+-3), so taking one sample instead of the mean, or the wrong shift
(Y16 >> 2, Y10 >> 8), changes the pixels.  Python 3 standard library only.
"""
import hashlib
import os
import sys

W, H = 320, 240


def blocks(p, fmt):
    """The four samples (top-left, top-right, bottom-left, bottom-right)
    whose mean is exactly the sample value of grey level p."""
    if fmt == "GREY":
        centre, d = p, (1 if 1 <= p <= 254 else 0)
    elif fmt == "Y16":
        centre, d = p * 256 + 128, (144 if 1 <= p <= 254 else 0)
    else:  # Y10
        centre, d = p * 4 + 2, (3 if 1 <= p <= 254 else 0)
    return (centre + d, centre - d, centre - d, centre + d)


def binned_eye(px, fmt):
    """640x480 samples (row-major list) whose 2x2 means are px."""
    out = [0] * (2 * W * 2 * H)
    for y in range(H):
        for x in range(W):
            a, b, c, d = blocks(px[y * W + x], fmt)
            i = (2 * y) * 2 * W + 2 * x
            out[i], out[i + 1] = a, b
            out[i + 2 * W], out[i + 2 * W + 1] = c, d
    return out


def pack16(samples):
    return b"".join(s.to_bytes(2, "little") for s in samples)


def main(argv):
    if len(argv) < 3:
        sys.exit(__doc__)
    src, dst = argv[1], argv[2]
    picks = [int(a) for a in argv[3:]] or [0, 8, 16]
    os.makedirs(dst, exist_ok=True)
    eyes = {}
    for side in ("left", "right"):
        with open(os.path.join(src, side + ".y"), "rb") as f:
            data = f.read()
        n = len(data) // (W * H)
        if n * W * H != len(data) or any(k >= n for k in picks):
            sys.exit(f"fmtraw: {side}.y holds {n} frames of {W}x{H}; "
                     f"frames {picks} wanted")
        eyes[side] = [data[k * W * H:(k + 1) * W * H] for k in picks]
    files = {name: open(os.path.join(dst, name), "wb") for name in
             ("sbs.raw", "y16-left.raw", "y16-right.raw", "y10-left.raw",
              "y10-right.raw", "left.md5", "right.md5")}
    top = bytes(640 * 120)
    bottom = bytes([255]) * (640 * 120)
    for i in range(len(picks)):
        halves = {}
        for side in ("left", "right"):
            px = eyes[side][i]
            files[side + ".md5"].write(
                f"{hashlib.md5(px).hexdigest()} {i}\n".encode())
            halves[side] = top + bytes(binned_eye(px, "GREY")) + bottom
            files["y16-" + side + ".raw"].write(pack16(binned_eye(px, "Y16")))
            files["y10-" + side + ".raw"].write(pack16(binned_eye(px, "Y10")))
        for row in range(720):
            for side in ("left", "right"):
                files["sbs.raw"].write(halves[side][row * 640:(row + 1) * 640])
    for f in files.values():
        f.close()
    # self-check: the 2x2 means of what was written are the originals
    with open(os.path.join(dst, "y10-right.raw"), "rb") as f:
        s = f.read(2 * 640 * 480)
    v = [int.from_bytes(s[2 * j:2 * j + 2], "little") for j in range(640 * 4)]
    for x in range(W):
        m = (v[2 * x] + v[2 * x + 1] + v[640 + 2 * x] + v[641 + 2 * x]) // 4
        assert m >> 2 == eyes["right"][0][x], "Y10 self-check"
    print(f"fmtraw: frames {picks} -> {dst}")


if __name__ == "__main__":
    main(sys.argv)
