#!/bin/sh
# tools/synth/pool_noise.py on one smooth-concrete walk (B = 12 cm, 16
# frames): a floor patch's error must be nearly independent from frame to
# frame (correlation below 0.3; 0.05 measured) and its mean over 4 frames
# at most 0.7 x one frame's spread (0.5 measured, 1/sqrt 4 for independent
# frames). This is what makes pooling frames worth building; a renderer or
# matcher whose errors followed the floor would fail it. Exit 77
# (skipped) when python3-opencv is missing.
# usage: test_pool_noise.sh POOL_NOISE_PY BUILD_DIR WORK_DIR
set -u
py=$1 build=$2 work=$3
rm -rf "$work"
pyi=python3; [ -x /usr/bin/python3 ] && pyi=/usr/bin/python3  # the Debian one has cv2
out=$("$pyi" "$py" --build "$build" --textures concrete --baselines 120 --frames 16 --work "$work")
rc=$?
[ "$rc" -eq 77 ] && { echo "skipped: python3-opencv missing"; exit 77; }
echo "$out"
[ "$rc" -eq 0 ] || { echo "FAIL: pool_noise.py exit $rc"; exit 1; }
echo "$out" | awk '$1 == "concrete" && $3 == "2-3" { sd1 = $5; corr = $6; sd4 = $8 }
    END {
      if (sd1 == "") { print "FAIL: no concrete 2-3 m row"; exit 1 }
      if (corr + 0 >= 0.3) { print "FAIL: frame-to-frame correlation " corr; exit 1 }
      if (sd4 + 0 > 0.7 * sd1) { print "FAIL: sd4 " sd4 " > 0.7 x sd1 " sd1; exit 1 }
      print "corr " corr " < 0.3; sd4 " sd4 " <= 0.7 x sd1 " sd1 }'
