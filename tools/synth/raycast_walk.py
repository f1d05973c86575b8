#!/usr/bin/env python3
"""An independent renderer of stereo walks, for cross-checking the detector.

negobs_synth and the evaluation suite built on it were written with the
detector; a renderer written against the same ideas can share their blind
spots. This one shares no code with it and models the images differently:

* the scene is a height profile along the walking direction (floor, a
  drop-off, stairs down, an up-step), intersected ray by ray, the visible
  riser of an up-step included, a textured wall 30 m ahead above it;
* textures are hashed value noise in world millimetres, several octaves
  per material (smooth concrete, worn asphalt, asphalt, square tiles with
  grout lines, whose period invites false matches);
* light: a directional sun plus sky on horizontal and vertical faces,
  vignetting, each camera its own exposure drifting through the walk,
  the right camera its own gain and offset, shot and read noise, a lens
  blur, 2 x 2 supersampling;
* the walk: forward speed, head bob, pitch and roll sway at the gait
  frequency.

It writes left_NNNN.png / right_NNNN.png (8-bit grey) and scene.json (the
camera and, per frame, the pose and the edge's floor distance). It does
not write gt.json: negobs_png is told only f, B and the image centre.

usage: raycast_walk.py --out DIR [--scene flat|drop|stairs|upstep]
       [--drop-mm H] [--edge-mm E] [--material M] [--height-mm H]
       [--pitch-deg P] [--roll-deg R] [--baseline-mm B] [--seed S] ...
"""
import argparse
import json
import math
import os
import struct
import sys
import zlib

import numpy as np

MATERIALS = {
    # (scale mm, amplitude in grey levels) per octave, and the mean level;
    # the amplitude is that of a point sample: a pixel averages an octave
    # finer than its footprint down (albedo())
    "concrete": ([(2.5, 30.0), (9.0, 8.0), (40.0, 6.0), (220.0, 10.0)], 150.0),
    "worn": ([(3.0, 50.0), (12.0, 20.0), (60.0, 10.0), (300.0, 12.0)], 110.0),
    "asphalt": ([(3.0, 100.0), (8.0, 60.0), (50.0, 15.0), (400.0, 10.0)],
                95.0),
    "tiles": ([(2.5, 20.0), (15.0, 10.0), (120.0, 5.0)], 170.0),
}
TILE_MM = 300.0
GROUT_MM = 8.0


def hash01(ix, iy, seed):
    """Deterministic pseudo-random values in [0, 1) at integer lattice
    points (arrays of int64)."""
    h = (ix * np.int64(73856093)) ^ (iy * np.int64(19349663)) ^ np.int64(
        seed * 83492791 + 1)
    h = (h ^ (h >> 13)) * np.int64(0x5bd1e995)
    h = h ^ (h >> 15)
    return (h & np.int64(0xFFFFFF)).astype(np.float64) / float(1 << 24)


def value_noise(s, t, scale, seed):
    """Smooth value noise of lattice step `scale` mm, mean 0, about +-0.5."""
    x = s / scale
    y = t / scale
    x0 = np.floor(x)
    y0 = np.floor(y)
    fx = x - x0
    fy = y - y0
    fx = fx * fx * (3 - 2 * fx)
    fy = fy * fy * (3 - 2 * fy)
    ix = x0.astype(np.int64)
    iy = y0.astype(np.int64)
    v00 = hash01(ix, iy, seed)
    v10 = hash01(ix + 1, iy, seed)
    v01 = hash01(ix, iy + 1, seed)
    v11 = hash01(ix + 1, iy + 1, seed)
    a = v00 + (v10 - v00) * fx
    b = v01 + (v11 - v01) * fx
    return a + (b - a) * fy - 0.5


def albedo(material, s, t, seed, fp):
    """Grey level of the material at surface coordinates (s, t) in mm, as
    a sample of footprint fp mm sees it: an octave of cell `scale` finer
    than the footprint averages about (fp / scale)^2 independent cells, so
    its contrast falls as scale / fp (and a grout line's as its width)."""
    octaves, mean = MATERIALS[material]
    g = np.full(s.shape, mean)
    for k, (scale, amp) in enumerate(octaves):
        att = np.minimum(1.0, scale / fp)
        g += 2.0 * amp * att * value_noise(s, t, scale, seed * 7 + k)
    if material == "tiles":
        ms = np.mod(s, TILE_MM)
        mt = np.mod(t, TILE_MM)
        grout = (ms < GROUT_MM) | (mt < GROUT_MM)
        g = np.where(grout, g - 45.0 * np.minimum(1.0, GROUT_MM / fp), g)
    return g


def footprint(t, dx, dy, dz, cos_in, f, ss):
    """A sample's footprint on the surface (mm): its angular size times
    the distance, stretched by the incidence (geometric mean of the two
    axes)."""
    dist = t * np.sqrt(dx * dx + dy * dy + dz * dz)
    return dist / (f * ss) / np.sqrt(np.maximum(cos_in, 0.05))


class Scene:
    """Levels along Y (forward, mm): segment k starts at starts[k] (the
    first at -inf) and lies at height levels[k] (mm, up)."""

    def __init__(self, kind, edge_mm, drop_mm, steps=3, run_mm=300.0):
        self.starts = [-1e9]
        self.levels = [0.0]
        if kind == "drop":
            self.starts.append(edge_mm)
            self.levels.append(-drop_mm)
        elif kind == "stairs":
            for k in range(steps):
                self.starts.append(edge_mm + k * run_mm)
                self.levels.append(-drop_mm * (k + 1))
        elif kind == "upstep":
            self.starts.append(edge_mm)
            self.levels.append(drop_mm)


def render_view(scene, cam, origin, axes, material, seed, light):
    """Radiance (grey levels, float) of one camera, 2 x 2 supersampled."""
    w, h, f, cx, cy = cam["width"], cam["height"], cam["f"], cam["cx"], cam[
        "cy"]
    xr, yd, zf = axes
    ss = 2
    us = (np.arange(w * ss) + 0.5) / ss - 0.5
    vs = (np.arange(h * ss) + 0.5) / ss - 0.5
    uu, vv = np.meshgrid(us, vs)
    a = (uu - cx) / f
    b = (vv - cy) / f
    dx = a * xr[0] + b * yd[0] + zf[0]
    dy = a * xr[1] + b * yd[1] + zf[1]
    dz = a * xr[2] + b * yd[2] + zf[2]
    ox, oy, oz = origin
    out = np.zeros(uu.shape)
    hit = np.zeros(uu.shape, dtype=bool)
    n = len(scene.starts)
    sun_h, sun_v, sky = light
    for k in range(n):
        y0 = scene.starts[k]
        y1 = scene.starts[k + 1] if k + 1 < n else 1e9
        zk = scene.levels[k]
        if k > 0 and zk > scene.levels[k - 1]:
            # the riser of a step up faces the walker
            with np.errstate(divide="ignore", invalid="ignore"):
                t = (y0 - oy) / dy
            zr = oz + t * dz
            m = (~hit) & (dy > 0) & (t > 0) & (zr >= scene.levels[k - 1]) & (
                zr <= zk)
            if m.any():
                xs = ox + t[m] * dx[m]
                fp = footprint(t[m], dx[m], dy[m], dz[m],
                               dy[m] / np.sqrt(dx[m]**2 + dy[m]**2 + dz[m]**2),
                               f, ss)
                out[m] = albedo(material, xs, zr[m] + 5000.0, seed,
                                fp) * (sun_v + sky) / (sun_h + sky)
                hit |= m
        with np.errstate(divide="ignore", invalid="ignore"):
            t = (zk - oz) / dz
        yh = oy + t * dy
        m = (~hit) & (dz < 0) & (t > 0) & (yh >= y0) & (yh < y1)
        if m.any():
            xs = ox + t[m] * dx[m]
            fp = footprint(t[m], dx[m], dy[m], dz[m],
                           -dz[m] / np.sqrt(dx[m]**2 + dy[m]**2 + dz[m]**2),
                           f, ss)
            out[m] = albedo(material, xs, yh[m], seed, fp)
            hit |= m
    # a wall 30 m ahead for the rays above every surface
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (30000.0 - oy) / dy
    m = ~hit
    xs = ox + t[m] * dx[m]
    zs = oz + t[m] * dz[m]
    out[m] = albedo("asphalt", xs, zs, seed + 99,
                    footprint(t[m], dx[m], dy[m], dz[m], 1.0, f, ss)) * 0.8
    # vignetting (cos^4 of the off-axis angle, softened)
    c2 = 1.0 / (1.0 + a * a + b * b)
    out *= 0.55 + 0.45 * c2 * c2
    return out.reshape(h, ss, w, ss).mean(axis=(1, 3))


def blur(img, sigma):
    """Separable Gaussian blur, edges replicated."""
    r = max(1, int(math.ceil(3 * sigma)))
    x = np.arange(-r, r + 1)
    k = np.exp(-0.5 * (x / sigma) ** 2)
    k /= k.sum()
    p = np.pad(img, r, mode="edge")
    tmp = sum(k[i] * p[:, i:i + img.shape[1]] for i in range(2 * r + 1))
    return sum(k[i] * tmp[i:i + img.shape[0], :] for i in range(2 * r + 1))


def write_png(path, img):
    """8-bit grey PNG without any imaging library."""
    h, w = img.shape
    raw = b"".join(b"\x00" + img[y].tobytes() for y in range(h))

    def chunk(tag, data):
        c = struct.pack(">I", len(data)) + tag + data
        return c + struct.pack(">I", zlib.crc32(tag + data) & 0xFFFFFFFF)

    png = b"\x89PNG\r\n\x1a\n" + chunk(
        b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 0, 0, 0, 0)) + chunk(
            b"IDAT", zlib.compress(raw, 6)) + chunk(b"IEND", b"")
    with open(path, "wb") as fh:
        fh.write(png)


def camera_axes(pitch_deg, roll_deg):
    """Right, down and forward unit vectors of a camera pitched down by
    pitch_deg and rolled by roll_deg about its optical axis."""
    p = math.radians(pitch_deg)
    r = math.radians(roll_deg)
    zf = np.array([0.0, math.cos(p), -math.sin(p)])
    xr0 = np.array([1.0, 0.0, 0.0])
    yd0 = np.array([0.0, -math.sin(p), -math.cos(p)])
    xr = math.cos(r) * xr0 + math.sin(r) * yd0
    yd = -math.sin(r) * xr0 + math.cos(r) * yd0
    return xr, yd, zf


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", required=True)
    ap.add_argument("--scene", default="drop",
                    choices=["flat", "drop", "stairs", "upstep"])
    ap.add_argument("--drop-mm", type=float, default=100.0)
    ap.add_argument("--edge-mm", type=float, default=4500.0)
    ap.add_argument("--material", default="concrete",
                    choices=sorted(MATERIALS))
    ap.add_argument("--height-mm", type=float, default=1200.0)
    ap.add_argument("--pitch-deg", type=float, default=20.0)
    ap.add_argument("--roll-deg", type=float, default=0.0)
    ap.add_argument("--baseline-mm", type=float, default=120.0)
    ap.add_argument("--width", type=int, default=320)
    ap.add_argument("--height", type=int, default=240)
    ap.add_argument("--f", type=float, default=250.0)
    ap.add_argument("--speed", type=float, default=1.2, help="m/s")
    ap.add_argument("--fps", type=float, default=10.0)
    ap.add_argument("--frames", type=int, default=0,
                    help="0: walk until the edge is 0.5 m ahead")
    ap.add_argument("--bob-mm", type=float, default=25.0)
    ap.add_argument("--gait-hz", type=float, default=1.9)
    ap.add_argument("--sway-deg", type=float, default=1.0)
    ap.add_argument("--gain-right", type=float, default=1.0)
    ap.add_argument("--offset-right", type=float, default=0.0)
    ap.add_argument("--read-noise", type=float, default=2.0)
    ap.add_argument("--blur", type=float, default=0.7)
    ap.add_argument("--seed", type=int, default=1)
    o = ap.parse_args()
    if o.width < 32 or o.height < 32 or o.f <= 0 or o.baseline_mm <= 0:
        print("raycast_walk: bad camera", file=sys.stderr)
        return 2
    rng = np.random.default_rng(o.seed)
    os.makedirs(o.out, exist_ok=True)
    cam = {"width": o.width, "height": o.height, "f": o.f,
           "cx": (o.width - 1) / 2.0, "cy": (o.height - 1) / 2.0,
           "B_mm": o.baseline_mm}
    scene = Scene(o.scene, o.edge_mm, o.drop_mm)
    step_mm = o.speed * 1000.0 / o.fps
    frames = o.frames or max(1, int((o.edge_mm - 500.0) / step_mm) + 1)
    # the sun: the same for the whole walk, its share on the horizontal and
    # the vertical faces
    light = (0.7 + 0.2 * rng.random(), 0.3 + 0.3 * rng.random(), 0.35)
    exposure = [1.0, 1.0]
    phase = rng.random() * 2 * math.pi
    meta = {"renderer": "raycast_walk.py", "camera": cam,
            "scene": {"kind": o.scene, "edge_mm": o.edge_mm,
                      "drop_mm": o.drop_mm if o.scene != "flat" else 0.0,
                      "material": o.material},
            "frames": []}
    for i in range(frames):
        t = i / o.fps
        yc = i * step_mm
        g = 2 * math.pi * o.gait_hz * t + phase
        hgt = o.height_mm + o.bob_mm * math.sin(g)
        pitch = o.pitch_deg + o.sway_deg * math.sin(g + 0.7)
        roll = o.roll_deg + 0.5 * o.sway_deg * math.sin(0.5 * g)
        axes = camera_axes(pitch, roll)
        left_o = np.array([0.0, yc, hgt])
        right_o = left_o + o.baseline_mm * axes[0]
        # exposure drifts per camera, a few percent a frame
        for c in range(2):
            exposure[c] = min(1.25, max(0.8, exposure[c] *
                                        (1.0 + 0.03 * rng.standard_normal())))
        imgs = []
        for c, orig in enumerate((left_o, right_o)):
            rad = render_view(scene, cam, orig, axes, o.material, o.seed,
                              light) * light[0] / 0.8 * exposure[c]
            if c == 1:
                rad = rad * o.gain_right + o.offset_right
            rad = blur(rad, o.blur)
            shot = np.sqrt(np.maximum(rad, 0.0)) * 0.25
            rad = rad + rng.standard_normal(rad.shape) * np.hypot(
                o.read_noise, shot)
            imgs.append(np.clip(np.rint(rad), 0, 255).astype(np.uint8))
        write_png(os.path.join(o.out, "left_%04d.png" % i), imgs[0])
        write_png(os.path.join(o.out, "right_%04d.png" % i), imgs[1])
        edge = (o.edge_mm - yc) if o.scene != "flat" else None
        # the edge's row at the image centre column (upper level, X = 0)
        row = None
        if edge is not None and edge > 0:
            p = np.array([0.0, o.edge_mm, 0.0]) - left_o
            zc = float(p @ axes[2])
            if zc > 0:
                row = float(p @ axes[1]) / zc * o.f + cam["cy"]
        meta["frames"].append({
            "i": i, "H_mm": hgt, "pitch_deg": pitch, "roll_deg": roll,
            "edge_range_mm": edge, "edge_row": row,
            "edge_in_view": row is not None and 0 <= row <= o.height - 1})
    with open(os.path.join(o.out, "scene.json"), "w") as fh:
        json.dump(meta, fh, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
