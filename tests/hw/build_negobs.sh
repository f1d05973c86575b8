#!/usr/bin/env bash
# Host side of the run-curb / run-camera-loss sections (called by
# tests/hw/run.sh; can be run alone): builds the real firmware and the scenes
# it is shown in the guest, into OUT (default build/hw/negobs):
#
#   OUT/negobs_run      static aarch64, release, from this tree
#                       (meson cross build in build/hw-negobs_run-a64)
#   OUT/curb/{left,right}.raw   negobs_synth walk toward a 150 mm curb,
#                       edge 4.0 m -> 1.24 m, 24 frames at 10 fps / 1.2 m/s
#   OUT/flat/{left,right}.raw   one flat-ground pair (no hazard)
#   OUT/fmt/            curb frames 0, 8, 16 as a side-by-side GREY
#                       1280x720 camera, Y16 and Y10 640x480 (fmtraw.py)
#   OUT/rig.conf        the synth rig for negobs_run --config
#
# Frames: negobs_synth renders 320x240 8-bit grey PNGs (native build in
# build/hw-host: needs OpenCV 4); tests/hw/png2raw.py repeats every pixel
# 2x2 into 640x480 raw GREY (vivid loops 640x480p59.94; its capture scaler
# gives negobs_run the original 320x240 back).
#
# usage: bash tests/hw/build_negobs.sh [OUT]
# exit 0 ok; 77 when a prerequisite is missing (message on the last line);
# other = build failure.  Rebuilds only what changed (meson/ninja; the scenes
# are re-rendered when negobs_synth or png2raw.py is newer).
set -u -o pipefail
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
OUT=${1:-${NEGOBS_HW_WORK:-$ROOT/build/hw}/negobs}
A64=$ROOT/build/hw-negobs_run-a64
HOST=$ROOT/build/hw-host
mkdir -p "$OUT"

command -v meson > /dev/null || { echo "meson not installed"; exit 77; }
command -v python3 > /dev/null || { echo "python3 not installed (png2raw.py)"; exit 77; }

# 1. static aarch64 negobs_run (release: -O2 for TCG's sake). The board
# cross file links libcamera (a shared library only: no static link),
# libturbojpeg and libsystemd (Debian ships no libsystemd.a); the emulated
# sections need none of them (the libcamera-vimc section builds its own
# dynamic program, build_libcamera.sh; the guest has no systemd).
# The options go in a second machine file as well as on the command line:
# meson (1.0, bookworm) re-applies the cross file's [project options]
# (libcamera, systemd = enabled: the board build) over -D values whenever it
# regenerates the tree, and the static link then fails.  A later machine
# file wins over an earlier one on every regeneration.
OVR=$ROOT/build/hw-negobs_run-a64.ini
printf '%s\n' '# written by tests/hw/build_negobs.sh: the static emulator build' \
  '[project options]' "libcamera = 'disabled'" "mjpeg = 'disabled'" "systemd = 'disabled'" > "$OVR.new"
cmp -s "$OVR.new" "$OVR" || { mv "$OVR.new" "$OVR"; rm -rf "$A64"; }
rm -f "$OVR.new"
# a tree configured before this file existed (or with other options) is redone
if [[ -f $A64/build.ninja ]] &&
   ! meson introspect --buildoptions "$A64" | python3 -c '
import json, sys
o = {x["name"]: x["value"] for x in json.load(sys.stdin)}
sys.exit(0 if all(o.get(k) == "disabled" for k in ("libcamera", "mjpeg", "systemd")) else 1)'; then
  rm -rf "$A64"
fi
if [[ ! -f $A64/build.ninja ]]; then
  rm -rf "$A64"
  meson setup --cross-file "$ROOT/tools/cross/aarch64-linux-gnu.ini" --cross-file "$OVR" \
    --buildtype=release -Dtests=disabled -Dtools=disabled -Dlibcamera=disabled -Dmjpeg=disabled \
    -Dsystemd=disabled -Dc_link_args=-static "$A64" || exit 1
fi
meson compile -C "$A64" firmware_app/negobs_run || exit 1
if aarch64-linux-gnu-readelf -l "$A64/firmware_app/negobs_run" | grep -q 'program interpreter'; then
  echo "negobs_run is not static"; exit 1
fi
cp "$A64/firmware_app/negobs_run" "$OUT/negobs_run.new" && mv "$OUT/negobs_run.new" "$OUT/negobs_run"

# 2. negobs_synth, native (needs OpenCV: tools=auto turns it off without)
if [[ ! -f $HOST/build.ninja ]]; then
  rm -rf "$HOST"
  meson setup -Dtests=disabled "$HOST" || exit 1
fi
if ! meson compile -C "$HOST" tools/synth/negobs_synth; then
  if ! grep -q "negobs_synth" "$HOST/build.ninja"; then
    echo "negobs_synth not buildable here (OpenCV 4 missing?)"; exit 77
  fi
  exit 1
fi
SYNTH=$HOST/tools/synth/negobs_synth

# 3. scenes (the synth rig: f=250 px, B=120 mm, H=1200 mm, pitch 20 deg)
RIG=(--f 250 --baseline-mm 120 --height-mm 1200 --pitch-deg 20 --width 320 --height 240 --seed 7)
scene() { # name synth-args...
  local name=$1; shift
  local d=$OUT/$name
  if [[ -f $d/left.raw && -f $d/right.raw && $d/left.raw -nt $SYNTH &&
        $d/left.raw -nt $ROOT/tests/hw/png2raw.py && $d/left.raw -nt ${BASH_SOURCE[0]} ]]; then
    return 0
  fi
  rm -rf "$d" "$OUT/png-$name"
  "$SYNTH" "$@" "${RIG[@]}" --out "$OUT/png-$name" > /dev/null || return 1
  python3 "$ROOT/tests/hw/png2raw.py" "$OUT/png-$name" "$d" || return 1
  cp "$OUT/png-$name/gt.json" "$d/gt.json"
}
scene curb --scene curb --drop-mm 150 --edge-mm 4000 --frames 24 --speed 1.2 --fps 10 || exit 1
scene flat --scene flat --single || exit 1
# camera-format frames of three curb frames (run-fmt-*: side by side, Y16, Y10)
if [[ ! -f $OUT/fmt/sbs.raw || $OUT/curb/left.y -nt $OUT/fmt/sbs.raw ||
      $ROOT/tests/hw/fmtraw.py -nt $OUT/fmt/sbs.raw ]]; then
  rm -rf "$OUT/fmt"
  python3 "$ROOT/tests/hw/fmtraw.py" "$OUT/curb" "$OUT/fmt" 0 8 16 || exit 1
fi

cat > "$OUT/rig.conf" <<'EOF'
# negobs_synth's rig (tests/hw/build_negobs.sh): 320x240, f=250 px,
# B=120 mm, H=1200 mm, pitch 20 deg
width = 320
height = 240
focal_px = 250
baseline_mm = 120
cam_height_mm = 1200
cam_pitch_mdeg = 20000
max_disp = 63
# a synthetic frame held for a second is pixel-identical frame to frame,
# which no sensor is: the frozen-stream check is off here and on (with
# injected sensor noise) in run-fault-frozen
frozen_frames = 0
# TCG emulation takes seconds per pair, far over the 250 ms a device must
# keep: the latency gate is off here (tests/port covers it)
latency_budget_ms = 0
EOF
echo "negobs: $(du -sk "$OUT" | cut -f1) KiB in $OUT"
