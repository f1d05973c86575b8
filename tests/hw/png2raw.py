#!/usr/bin/env python3
"""png2raw: negobs_synth's 8-bit grey PNGs -> raw GREY frames for the
emulated-hardware injector (tests/hw/guest/v4l2_loop.c inject -L/-R).

usage: png2raw.py SYNTH_DIR OUT_DIR [--scale K] [--pgm]

Writes OUT_DIR/left.raw and OUT_DIR/right.raw: every left_NNNN.png /
right_NNNN.png (from 0, in order), K x K larger (default 2, laid out for
vivid's scaler), frames concatenated.  K = 2 turns the 320x240 synth frames into 640x480
frames that vivid's HDMI loop accepts (640x480p59.94 timings); vivid's
capture scaler (crop 640x480 -> compose 320x240, which copies pixel PAIRS:
see upscale()) then hands negobs_run the original 320x240 pixels.  --pgm also writes
OUT_DIR/pgm/left_NNNN.pgm + right_NNNN.pgm at the original size (a
replay:DIR for negobs_run on the host).  OUT_DIR/left.y, right.y: the
original frames, raw, concatenated, and OUT_DIR/left.md5, right.md5 (one
"MD5 INDEX" line per original frame) to compare with what the guest got.  Python 3 standard library only.
"""
import hashlib
import os
import struct
import sys
import zlib


def read_png_grey8(path):
    with open(path, "rb") as f:
        data = f.read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise ValueError(f"{path}: not a PNG")
    pos, idat, w = 8, [], None
    while pos < len(data):
        (n,) = struct.unpack(">I", data[pos:pos + 4])
        kind = data[pos + 4:pos + 8]
        body = data[pos + 8:pos + 8 + n]
        pos += 12 + n
        if kind == b"IHDR":
            w, h, depth, ctype, _c, _f, interlace = struct.unpack(">IIBBBBB", body)
            if depth != 8 or ctype != 0 or interlace != 0:
                raise ValueError(f"{path}: want 8-bit grey, non-interlaced "
                                 f"(depth {depth}, colour type {ctype}, interlace {interlace})")
        elif kind == b"IDAT":
            idat.append(body)
        elif kind == b"IEND":
            break
    if w is None:
        raise ValueError(f"{path}: no IHDR")
    raw = zlib.decompress(b"".join(idat))
    out = bytearray(w * h)
    prev = bytearray(w)
    stride = w + 1
    for y in range(h):
        ft = raw[y * stride]
        line = bytearray(raw[y * stride + 1:(y + 1) * stride])
        if ft == 1:
            for x in range(1, w):
                line[x] = (line[x] + line[x - 1]) & 255
        elif ft == 2:
            for x in range(w):
                line[x] = (line[x] + prev[x]) & 255
        elif ft == 3:
            for x in range(w):
                a = line[x - 1] if x else 0
                line[x] = (line[x] + ((a + prev[x]) >> 1)) & 255
        elif ft == 4:
            for x in range(w):
                a = line[x - 1] if x else 0
                b = prev[x]
                c = prev[x - 1] if x else 0
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                pr = a if (pa <= pb and pa <= pc) else (b if pb <= pc else c)
                line[x] = (line[x] + pr) & 255
        elif ft != 0:
            raise ValueError(f"{path}: bad filter {ft} in row {y}")
        out[y * w:(y + 1) * w] = line
        prev = line
    return w, h, bytes(out)


def upscale(w, h, px, k):
    """K x K larger frame that vivid's capture scaler (K:1) turns back into
    px exactly.  vivid's scale_line() (drivers/media/test-drivers/vivid/
    vivid-kthread-cap.c) copies PAIRS of pixels (so packed YUV keeps its
    chroma): output pair j is source pair K*j.  So source pixels
    2*K*j .. 2*K*j+1 must hold the original pair j; the rest of each group
    repeats it.  Rows are picked one in K: every row is repeated K times.
    (Plain pixel repetition would give negobs_run every other column twice
    and ruin the disparity.)"""
    if k == 1:
        return px
    if w % 2:
        raise ValueError("odd width")
    out = bytearray()
    for y in range(h):
        row = px[y * w:(y + 1) * w]
        big = bytearray()
        for j in range(0, w, 2):
            big += row[j:j + 2] * k
        out += bytes(big) * k
    return bytes(out)


def vivid_scale_line(src, dstw, twopix=2):
    """Model of vivid's scale_line() for 8-bit GREY (self-test)."""
    srcw, dstw = len(src) // 2, dstw // 2
    ip, fp, sx, err, out = srcw // dstw, srcw % dstw, 0, 0, bytearray()
    for _ in range(dstw):
        out += src[sx * twopix:sx * twopix + twopix]
        sx += ip
        err += fp
        if err >= dstw:
            err -= dstw
            sx += 1
    return bytes(out)


def main(argv):
    args = [a for a in argv[1:] if not a.startswith("--")]
    k, pgm = 2, "--pgm" in argv
    if "--scale" in argv:
        k = int(argv[argv.index("--scale") + 1])
        args.remove(str(k))
    if len(args) != 2:
        sys.exit(__doc__)
    src, dst = args
    os.makedirs(dst, exist_ok=True)
    if pgm:
        os.makedirs(os.path.join(dst, "pgm"), exist_ok=True)
    n, sums = 0, {"left": [], "right": []}
    with open(os.path.join(dst, "left.raw"), "wb") as fl, \
         open(os.path.join(dst, "right.raw"), "wb") as fr, \
         open(os.path.join(dst, "left.y"), "wb") as yl, \
         open(os.path.join(dst, "right.y"), "wb") as yr:
        while os.path.exists(os.path.join(src, f"left_{n:04d}.png")):
            for eye, f, fy in (("left", fl, yl), ("right", fr, yr)):
                w, h, px = read_png_grey8(os.path.join(src, f"{eye}_{n:04d}.png"))
                big = upscale(w, h, px, k)
                # self-test against the model of vivid's scaler (row 1)
                if k > 1 and vivid_scale_line(big[k * w * k:k * w * k + w * k], w) != px[w:2 * w]:
                    sys.exit("png2raw: vivid scaler model does not give the frame back")
                f.write(big)
                fy.write(px)
                sums[eye].append(hashlib.md5(px).hexdigest())
                if pgm:
                    with open(os.path.join(dst, "pgm", f"{eye}_{n:04d}.pgm"), "wb") as p:
                        p.write(b"P5\n%d %d\n255\n" % (w, h) + px)
            n += 1
    if n == 0:
        sys.exit(f"png2raw: no left_0000.png in {src}")
    for eye in sums:
        with open(os.path.join(dst, f"{eye}.md5"), "w") as f:
            f.write("".join(f"{m} {i}\n" for i, m in enumerate(sums[eye])))
    print(f"png2raw: {n} pairs {w}x{h} -> {w * k}x{h * k} raw in {dst}")


if __name__ == "__main__":
    main(sys.argv)
